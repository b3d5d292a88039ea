//! Box–plane and box–bounded-plane: the box face most facing the plane, clipped to the
//! rectangle when the plane is bounded, every vertex within the margin kept (reduced to
//! four). An infinite plane is a half-space; a bounded plane is a thin two-sided wall,
//! touched from the side the box's centre is on.

use bevy::prelude::*;

use super::box_frame::{BoxFrame, most_anti_parallel_face, push_face_points};
use super::polygon::box_face;
use super::{Manifold, Posed};

pub fn collide(
    cuboid: Posed,
    h: Vec3,
    plane: Posed,
    half: Option<Vec2>,
    margin: f32,
    out: &mut Manifold,
) {
    let b = BoxFrame::new(&cuboid, h);
    let pr = Mat3::from_quat(plane.rot);
    let np = pr.col(1);
    let side = match half {
        Some(_) if (b.pos - plane.pos).dot(np) < 0.0 => -1.0,
        _ => 1.0,
    };
    // n points from the plane towards the box's side.
    let n = np * side;
    let face = most_anti_parallel_face(&b, n);
    let mut poly = box_face(b.pos, b.axes, h, face);
    if let Some(r) = half {
        let slab = |axis: Vec3, extent: f32| (axis, axis.dot(plane.pos), extent);
        poly = poly.clip_to_slabs([slab(pr.col(0), r.x), slab(pr.col(2), r.y)]);
    }
    // The plane is the reference face: a vertex's separation is its height along n.
    let before = out.len;
    push_face_points(&poly, n, n.dot(plane.pos), margin, (face as u32) << 20, out);
    if out.len > before {
        out.normal = -n;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    fn run(pos: Vec3, rot: Quat, half: Option<Vec2>) -> Manifold {
        let (b, p) = (
            Shape::Cuboid {
                half_extents: Vec3::splat(0.5),
            },
            Shape::Plane { half_extents: half },
        );
        let mut m = Manifold::default();
        collide(
            Posed {
                shape: &b,
                pos,
                rot,
            },
            Vec3::splat(0.5),
            Posed {
                shape: &p,
                pos: Vec3::ZERO,
                rot: Quat::IDENTITY,
            },
            half,
            0.02,
            &mut m,
        );
        m
    }

    #[test]
    fn flat_box_touches_with_its_four_bottom_corners() {
        let m = run(Vec3::new(3.0, 0.49, 1.0), Quat::IDENTITY, None);
        assert_eq!(m.len, 4);
        assert!((m.normal + Vec3::Y).length() < 1e-6);
        assert!(
            m.points()
                .iter()
                .all(|p| (p.separation + 0.01).abs() < 1e-6 && (p.point.y + 0.005).abs() < 1e-6)
        );
    }

    #[test]
    fn box_on_a_corner_touches_at_one_point() {
        let rot = Quat::from_rotation_arc(Vec3::new(1.0, 1.0, 1.0).normalize(), Vec3::Y);
        let reach = 0.5 * 3f32.sqrt();
        let m = run(Vec3::Y * (reach - 0.01), rot, None);
        assert_eq!(m.len, 1, "{m:?}");
        assert!((m.points[0].separation + 0.01).abs() < 1e-4);
    }

    #[test]
    fn box_overhanging_a_ledge_is_clipped_to_it() {
        let m = run(
            Vec3::new(1.0, 0.49, 0.0),
            Quat::IDENTITY,
            Some(Vec2::new(1.0, 1.0)),
        );
        assert_eq!(m.len, 4);
        assert!(
            m.points()
                .iter()
                .all(|p| p.point.x <= 1.0 + 1e-6 && p.point.x >= 0.5 - 1e-6),
            "{m:?}"
        );
    }
}
