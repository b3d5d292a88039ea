//! Capsule–capsule: the closest points of the two inner segments, and each segment's
//! ends against the other segment, kept when they lie along the same normal. Parry's own
//! pair gives a second point only when its clipping finds one: two capsules 2.7° apart,
//! one swinging flat onto the other, got one point at the far end, and the near end sank
//! 8 mm in a step. With the ends as points, the swing is stopped as it closes.

use bevy::prelude::*;

use super::Posed;
use super::polygon::reduce;
use super::{MAX_POINTS, Manifold};

/// Candidate points off the main normal by more than this (cos 22.5°) are not the same
/// contact.
const SAME_NORMAL: f32 = 0.924;

/// The point of segment [p, q] closest to `x`.
fn closest_on_segment(p: Vec3, q: Vec3, x: Vec3) -> Vec3 {
    let d = q - p;
    let len2 = d.length_squared();
    if len2 == 0.0 {
        return p;
    }
    p + d * ((x - p).dot(d) / len2).clamp(0.0, 1.0)
}

/// The closest points of segments [p1, q1] and [p2, q2].
fn closest_between_segments(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (Vec3, Vec3) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (c, b) = (d1.dot(r), d1.dot(d2));
    let denom = a * e - b * b;
    // Parallel (or a point): any s; take the one that makes t fit.
    let mut s = if denom > 1e-12 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = if e > 0.0 { (b * s + f) / e } else { 0.0 };
    if t < 0.0 {
        t = 0.0;
        s = if a > 0.0 {
            (-c / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    } else if t > 1.0 {
        t = 1.0;
        s = if a > 0.0 {
            ((b - c) / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    }
    (p1 + d1 * s, p2 + d2 * t)
}

/// Collides two capsules (radius, half height each) within `margin`.
pub fn collide(
    a: Posed,
    (ra, ha): (f32, f32),
    b: Posed,
    (rb, hb): (f32, f32),
    margin: f32,
    out: &mut Manifold,
) {
    let (a0, a1) = (a.pos - a.rot * Vec3::Y * ha, a.pos + a.rot * Vec3::Y * ha);
    let (b0, b1) = (b.pos - b.rot * Vec3::Y * hb, b.pos + b.rot * Vec3::Y * hb);
    let (pa, pb) = closest_between_segments(a0, a1, b0, b1);
    let gap = pb - pa;
    let dist = gap.length();
    if dist - ra - rb > margin {
        return;
    }
    // Coincident axes: any direction across A's axis will do.
    let normal = if dist > 1e-9 {
        gap / dist
    } else {
        (a.rot * Vec3::X).normalize()
    };
    // The closest pair, then each segment's ends against the other segment.
    let candidates = [
        (pa, pb, 0),
        (a0, closest_on_segment(b0, b1, a0), 1),
        (a1, closest_on_segment(b0, b1, a1), 2),
        (closest_on_segment(a0, a1, b0), b0, 3),
        (closest_on_segment(a0, a1, b1), b1, 4),
    ];
    let mut points: [(Vec3, f32, u32); 5] = [(Vec3::ZERO, 0.0, 0); 5];
    let mut n = 0;
    for (i, &(x, y, id)) in candidates.iter().enumerate() {
        let along = (y - x).dot(normal);
        let d = (y - x).length();
        // Not along the main normal (an end off to the side), or beyond reach.
        let aligned = i == 0 || d < 1e-9 || along >= SAME_NORMAL * d;
        let separation = along - ra - rb;
        if !aligned || separation > margin {
            continue;
        }
        // The same spot as one kept already (an end that is the closest point).
        let mid = 0.5 * ((x + normal * ra) + (y - normal * rb));
        if points[..n].iter().any(|p| p.0.distance_squared(mid) < 1e-8) {
            continue;
        }
        points[n] = (mid, separation, id);
        n += 1;
    }
    let (keep, len) = reduce(&points[..n], normal);
    out.normal = normal;
    for &i in &keep[..len.min(MAX_POINTS)] {
        let (p, s, id) = points[i];
        out.push(p, s, id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    #[test]
    fn parallel_capsules_touch_along_their_length() {
        let s = Shape::Capsule {
            radius: 0.2,
            half_height: 0.3,
        };
        let a = Posed {
            shape: &s,
            pos: Vec3::ZERO,
            rot: Quat::IDENTITY,
        };
        // Side by side 1 mm apart, B turned 2.7° about z: both ends are points.
        let b = Posed {
            shape: &s,
            pos: Vec3::new(0.401, 0.0, 0.0),
            rot: Quat::from_rotation_z(0.047),
        };
        let mut m = Manifold::default();
        collide(a, (0.2, 0.3), b, (0.2, 0.3), 0.05, &mut m);
        assert!(m.len >= 2, "{m:?}");
        assert!(m.normal.abs_diff_eq(Vec3::X, 0.03), "{}", m.normal);
        let ys: Vec<f32> = m.points().iter().map(|p| p.point.y).collect();
        assert!(
            ys.iter().any(|&y| y > 0.25) && ys.iter().any(|&y| y < -0.25),
            "{ys:?}"
        );
        // Crossed at right angles: one point.
        let c = Posed {
            shape: &s,
            pos: Vec3::new(0.399, 0.0, 0.0),
            rot: Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
        };
        let mut m = Manifold::default();
        collide(a, (0.2, 0.3), c, (0.2, 0.3), 0.05, &mut m);
        assert_eq!(m.len, 1);
        assert!((m.points()[0].separation + 0.001).abs() < 1e-5);
    }
}
