//! Box–box by the separating-axis test over all 15 axes: the 3 face normals of each box
//! and the 9 cross products of their edge directions.
//!
//! The axis of greatest separation decides the contact. A face axis gives a face contact:
//! the other box's most anti-parallel face is clipped against the side planes of the
//! reference face, up to four points kept. An edge axis gives one point between the
//! closest points of the two edges. A face axis is preferred unless an edge axis is
//! clearly better, and A's face over B's, so resting boxes keep the same manifold from step
//! to step (the feature ids then match and warm starting works).

use bevy::prelude::*;

use super::box_frame::{BoxFrame, most_anti_parallel_face, push_face_points};
use super::polygon::box_face;
use super::{Manifold, Posed};

/// How much better (m) B's face axis or an edge axis must separate to be chosen.
const FACE_TOLERANCE: f32 = 0.001;
const EDGE_TOLERANCE: f32 = 0.005;

pub fn collide(a: Posed, ha: Vec3, b: Posed, hb: Vec3, margin: f32, out: &mut Manifold) {
    let (ba, bb) = (BoxFrame::new(&a, ha), BoxFrame::new(&b, hb));
    let d = bb.pos - ba.pos;
    // Everything in A's frame: r[i][j] = aᵢ·bⱼ (column j is bⱼ there), and the centres'
    // offset in each frame. Each box's radius along any of the 15 axes is then a few
    // products of these, with no vector turned per axis.
    let at = ba.axes.transpose();
    let r = at * bb.axes;
    let rows = [r.row(0), r.row(1), r.row(2)];
    let cols = [r.col(0), r.col(1), r.col(2)];
    let (ta, tb) = (at * d, bb.axes.transpose() * d);
    let (abs_rows, abs_cols) = (rows.map(Vec3::abs), cols.map(Vec3::abs));

    let mut face_a = (f32::MIN, 0);
    let mut face_b = (f32::MIN, 0);
    for k in 0..3 {
        // Along aₖ: B's radius is Σⱼ |aₖ·bⱼ| hbⱼ; along bₖ, A's is Σᵢ |aᵢ·bₖ| haᵢ.
        let sa = ta[k].abs() - ha[k] - abs_rows[k].dot(hb);
        let sb = tb[k].abs() - abs_cols[k].dot(ha) - hb[k];
        if sa > margin || sb > margin {
            return;
        }
        if sa > face_a.0 {
            face_a = (sa, k);
        }
        if sb > face_b.0 {
            face_b = (sb, k);
        }
    }
    let mut edge = (f32::MIN, 0, 0, Vec3::ZERO);
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            // aᵢ × bⱼ in A's frame: eᵢ × (column j) = (.., −r[i2][j], r[i1][j]).
            let mut axis = Vec3::ZERO;
            (axis[i1], axis[i2]) = (-cols[j][i2], cols[j][i1]);
            let len = axis.length();
            if len < 1e-5 {
                continue; // parallel edges: their face axes already cover this direction
            }
            // A's radius along it: ha_i1 |r[i2][j]| + ha_i2 |r[i1][j]|; B's, since
            // b_j1 · (aᵢ × bⱼ) = aᵢ · b_j2 and b_j2 · (aᵢ × bⱼ) = −aᵢ · b_j1:
            // hb_j1 |r[i][j2]| + hb_j2 |r[i][j1]|.
            let radius_a = ha[i1] * abs_cols[j][i2] + ha[i2] * abs_cols[j][i1];
            let radius_b = hb[j1] * abs_rows[i][j2] + hb[j2] * abs_rows[i][j1];
            let s = (ta.dot(axis).abs() - radius_a - radius_b) / len;
            if s > margin {
                return;
            }
            if s > edge.0 {
                edge = (s, i, j, axis / len);
            }
        }
    }

    let b_face_wins = face_b.0 > face_a.0 + FACE_TOLERANCE;
    let face_sep = face_a.0.max(face_b.0);
    if edge.0 > face_sep + EDGE_TOLERANCE {
        // The edge axis back in the world frame.
        let axis = ba.axes * edge.3;
        edge_contact(&ba, &bb, edge.1, edge.2, axis, margin, out);
    } else if b_face_wins {
        face_contact(&bb, &ba, face_b.1, true, margin, out);
    } else {
        face_contact(&ba, &bb, face_a.1, false, margin, out);
    }
}

/// Clips the incident box's face against the reference box's face `axis`. `flipped`: the
/// reference is B, so the manifold normal (A to B) is minus the reference normal.
fn face_contact(
    reference: &BoxFrame,
    incident: &BoxFrame,
    axis: usize,
    flipped: bool,
    margin: f32,
    out: &mut Manifold,
) {
    let along = reference.axes.col(axis);
    let sign = if (incident.pos - reference.pos).dot(along) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let n = along * sign;
    let ref_face = 2 * axis + usize::from(sign < 0.0);
    let inc_face = most_anti_parallel_face(incident, n);
    let slab = |k: usize| {
        let side = reference.axes.col(k);
        (side, side.dot(reference.pos), reference.half[k])
    };
    let poly = box_face(incident.pos, incident.axes, incident.half, inc_face)
        .clip_to_slabs([slab((axis + 1) % 3), slab((axis + 2) % 3)]);
    let plane = n.dot(reference.pos) + reference.half[axis];
    let base = (u32::from(flipped) << 28) | ((ref_face as u32) << 24) | ((inc_face as u32) << 20);
    push_face_points(&poly, n, plane, margin, base, out);
    out.normal = if flipped { -n } else { n };
}

/// One point between the closest points of A's edge along axis `i` and B's along `j`.
fn edge_contact(
    a: &BoxFrame,
    b: &BoxFrame,
    i: usize,
    j: usize,
    axis: Vec3,
    margin: f32,
    out: &mut Manifold,
) {
    let n = if axis.dot(b.pos - a.pos) >= 0.0 {
        axis
    } else {
        -axis
    };
    let (pa, signs_a) = support_edge(a, i, n);
    let (pb, signs_b) = support_edge(b, j, -n);
    let (ua, ub) = (a.axes.col(i), b.axes.col(j));
    let (qa, qb) = closest_points_on_segments(pa, ua, a.half[i], pb, ub, b.half[j]);
    let s = n.dot(qb - qa);
    if s > margin {
        return;
    }
    out.normal = n;
    let id = 0x4000_0000 | ((i as u32) << 12) | ((j as u32) << 8) | (signs_a << 4) | signs_b;
    out.push(0.5 * (qa + qb), s, id);
}

/// Centre of the edge of `b` parallel to axis `k` that lies furthest along `dir`, and the
/// sign bits that name it.
fn support_edge(b: &BoxFrame, k: usize, dir: Vec3) -> (Vec3, u32) {
    let mut p = b.pos;
    let mut bits = 0;
    for m in (0..3).filter(|&m| m != k) {
        let axis = b.axes.col(m);
        if axis.dot(dir) >= 0.0 {
            p += axis * b.half[m];
            bits |= 1 << m;
        } else {
            p -= axis * b.half[m];
        }
    }
    (p, bits)
}

/// Closest points of segments pa + s·ua (|s| ≤ la) and pb + t·ub (|t| ≤ lb), unit u's.
pub fn closest_points_on_segments(
    pa: Vec3,
    ua: Vec3,
    la: f32,
    pb: Vec3,
    ub: Vec3,
    lb: f32,
) -> (Vec3, Vec3) {
    let r = pa - pb;
    let b = ua.dot(ub);
    let (c, f) = (ua.dot(r), ub.dot(r));
    let denom = 1.0 - b * b;
    let mut s = if denom > 1e-8 {
        ((b * f - c) / denom).clamp(-la, la)
    } else {
        0.0
    };
    let t = (b * s + f).clamp(-lb, lb);
    s = (b * t - c).clamp(-la, la);
    (pa + ua * s, pb + ub * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    fn boxes(pa: Vec3, qa: Quat, pb: Vec3, qb: Quat, margin: f32) -> Manifold {
        let s = Shape::Cuboid {
            half_extents: Vec3::splat(0.5),
        };
        let mut m = Manifold::default();
        collide(
            Posed {
                shape: &s,
                pos: pa,
                rot: qa,
            },
            Vec3::splat(0.5),
            Posed {
                shape: &s,
                pos: pb,
                rot: qb,
            },
            Vec3::splat(0.5),
            margin,
            &mut m,
        );
        m
    }

    #[test]
    fn stacked_cubes_touch_on_four_face_points() {
        let m = boxes(
            Vec3::ZERO,
            Quat::IDENTITY,
            Vec3::new(0.1, 0.99, 0.0),
            Quat::IDENTITY,
            0.02,
        );
        assert_eq!(m.len, 4);
        assert!((m.normal - Vec3::Y).length() < 1e-6);
        for p in m.points() {
            assert!((p.separation + 0.01).abs() < 1e-5);
            assert!((p.point.y - 0.495).abs() < 1e-5);
            assert!(
                p.point.x >= -0.4 - 1e-5 && p.point.x <= 0.5 + 1e-5,
                "clipped to the overlap"
            );
        }
        let mut ids: Vec<_> = m.points().iter().map(|p| p.id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), 4, "distinct feature ids");
    }

    #[test]
    fn separated_boxes_make_no_contact() {
        let m = boxes(
            Vec3::ZERO,
            Quat::IDENTITY,
            Vec3::new(0.0, 1.1, 0.0),
            Quat::IDENTITY,
            0.05,
        );
        assert_eq!(m.len, 0);
    }

    #[test]
    fn crossed_edges_touch_at_one_point() {
        // A turned 45° about z has a top edge along z; B turned 45° about x has a bottom
        // edge along x: they cross at right angles.
        let qb = Quat::from_rotation_x(std::f32::consts::FRAC_PI_4);
        let qa = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        let reach = 0.5 * 2f32.sqrt();
        let m = boxes(
            Vec3::ZERO,
            qa,
            Vec3::new(0.0, 2.0 * reach - 0.01, 0.0),
            qb,
            0.02,
        );
        assert_eq!(m.len, 1, "{m:?}");
        assert!((m.normal - Vec3::Y).length() < 1e-4, "normal {}", m.normal);
        assert!((m.points[0].separation + 0.01).abs() < 1e-4);
        assert!(m.points[0].point.xz().length() < 1e-4);
    }

    #[test]
    fn normal_points_from_a_to_b_either_way() {
        let m = boxes(
            Vec3::new(0.0, 0.99, 0.0),
            Quat::IDENTITY,
            Vec3::ZERO,
            Quat::IDENTITY,
            0.02,
        );
        assert!((m.normal + Vec3::Y).length() < 1e-6);
    }

    /// Half the box's extent along a unit axis, in the world frame.
    fn radius_along(b: &BoxFrame, axis: Vec3) -> f32 {
        (0..3)
            .map(|k| b.axes.col(k).dot(axis).abs() * b.half[k])
            .sum()
    }

    /// The brute-force reference for `collide`'s axis choice: every axis's separation
    /// measured in the world frame, each box's radius along it summed over its axes.
    fn reference(a: Posed, ha: Vec3, b: Posed, hb: Vec3, margin: f32, out: &mut Manifold) {
        let (ba, bb) = (BoxFrame::new(&a, ha), BoxFrame::new(&b, hb));
        let d = bb.pos - ba.pos;
        let sep =
            |axis: Vec3| d.dot(axis).abs() - radius_along(&ba, axis) - radius_along(&bb, axis);
        let (mut face_a, mut face_b) = ((f32::MIN, 0), (f32::MIN, 0));
        for k in 0..3 {
            let (sa, sb) = (sep(ba.axes.col(k)), sep(bb.axes.col(k)));
            if sa > margin || sb > margin {
                return;
            }
            face_a = if sa > face_a.0 { (sa, k) } else { face_a };
            face_b = if sb > face_b.0 { (sb, k) } else { face_b };
        }
        let mut edge = (f32::MIN, 0, 0, Vec3::ZERO);
        for i in 0..3 {
            for j in 0..3 {
                let axis = ba.axes.col(i).cross(bb.axes.col(j));
                if axis.length() < 1e-5 {
                    continue;
                }
                let axis = axis.normalize();
                let s = sep(axis);
                if s > margin {
                    return;
                }
                edge = if s > edge.0 { (s, i, j, axis) } else { edge };
            }
        }
        let face_sep = face_a.0.max(face_b.0);
        if edge.0 > face_sep + EDGE_TOLERANCE {
            edge_contact(&ba, &bb, edge.1, edge.2, edge.3, margin, out);
        } else if face_b.0 > face_a.0 + FACE_TOLERANCE {
            face_contact(&bb, &ba, face_b.1, true, margin, out);
        } else {
            face_contact(&ba, &bb, face_a.1, false, margin, out);
        }
    }

    #[test]
    fn axes_in_a_frame_find_what_the_world_frame_reference_finds() {
        let mut r = crate::rng::Rnd(0xb0c5_0015);
        let s = Shape::Cuboid {
            half_extents: Vec3::ONE,
        };
        let (mut touching, mut edges) = (0, 0);
        for case in 0..4000 {
            let (ha, hb) = (r.vec(0.05, 1.0), r.vec(0.05, 1.0));
            // Axis-aligned or turned: resting boxes share axes (their parallel edges are
            // the skipped ones).
            let turn = |r: &mut crate::rng::Rnd| {
                if r.unit() < 0.3 {
                    Quat::IDENTITY
                } else {
                    r.rot()
                }
            };
            let (qa, qb) = (turn(&mut r), turn(&mut r));
            let reach = ha.length() + hb.length();
            let pa = r.vec(-5.0, 5.0);
            let pb = pa + r.dir() * r.range(0.0, reach);
            let posed = |pos, rot| Posed {
                shape: &s,
                pos,
                rot,
            };
            let margin = 0.02;
            let (mut m, mut want) = (Manifold::default(), Manifold::default());
            collide(posed(pa, qa), ha, posed(pb, qb), hb, margin, &mut m);
            reference(posed(pa, qa), ha, posed(pb, qb), hb, margin, &mut want);
            assert_eq!(m.len, want.len, "case {case}: {m:?} against {want:?}");
            if m.len == 0 {
                continue;
            }
            touching += 1;
            edges += usize::from(m.points[0].id & 0x4000_0000 != 0);
            assert!(
                (m.normal - want.normal).length() < 1e-4,
                "case {case}: {m:?} against {want:?}"
            );
            for (p, q) in m.points().iter().zip(want.points()) {
                assert_eq!(p.id, q.id, "case {case}");
                assert!(
                    (p.point - q.point).length() < 1e-4,
                    "case {case}: {p:?} against {q:?}"
                );
                assert!((p.separation - q.separation).abs() < 1e-4, "case {case}");
            }
        }
        // The test means something only if both kinds of contact are common.
        assert!(
            touching > 1000 && edges > 100,
            "{touching} touching, {edges} on edges"
        );
    }
}
