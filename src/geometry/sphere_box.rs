//! Sphere–box: the closest point of the box to the sphere's centre, found in the box's
//! frame by clamping. A centre inside the box is pushed out through the nearest face.

use bevy::prelude::*;

use super::{Manifold, Posed};

pub fn collide(sphere: Posed, r: f32, cuboid: Posed, h: Vec3, margin: f32, out: &mut Manifold) {
    let local = cuboid.rot.inverse() * (sphere.pos - cuboid.pos);
    let clamped = local.clamp(-h, h);
    let (surface, outward, s, id) = if clamped != local {
        let d = local - clamped;
        let dist = d.length();
        // Region id: which coordinates were clamped, and to which side.
        let id = (0..3).fold(0, |acc, k| {
            acc | (u32::from(clamped[k] != local[k]) << (2 * k))
                | (u32::from(local[k] > 0.0) << (2 * k + 1))
        });
        (clamped, d / dist.max(1e-12), dist - r, id)
    } else {
        // Inside: the face with the least depth.
        let depth = h - local.abs();
        let k = if depth.x <= depth.y && depth.x <= depth.z {
            0
        } else if depth.y <= depth.z {
            1
        } else {
            2
        };
        let mut n = Vec3::ZERO;
        n[k] = if local[k] >= 0.0 { 1.0 } else { -1.0 };
        let mut surface = local;
        surface[k] = n[k] * h[k];
        (surface, n, -depth[k] - r, 0x100 | k as u32)
    };
    if s > margin {
        return;
    }
    // Contact normal from the sphere to the box: against the box's outward normal.
    out.normal = cuboid.rot * -outward;
    let on_box = cuboid.pos + cuboid.rot * surface;
    out.push(on_box - out.normal * (0.5 * s), s, id);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    fn run(center: Vec3, rot: Quat) -> Manifold {
        let (s, b) = (
            Shape::Sphere { radius: 0.5 },
            Shape::Cuboid {
                half_extents: Vec3::ONE,
            },
        );
        let mut m = Manifold::default();
        collide(
            Posed {
                shape: &s,
                pos: center,
                rot: Quat::IDENTITY,
            },
            0.5,
            Posed {
                shape: &b,
                pos: Vec3::ZERO,
                rot,
            },
            Vec3::ONE,
            0.1,
            &mut m,
        );
        m
    }

    #[test]
    fn sphere_on_top_face() {
        let m = run(Vec3::new(0.3, 1.45, 0.2), Quat::IDENTITY);
        assert_eq!(m.len, 1);
        assert!((m.normal + Vec3::Y).length() < 1e-6);
        assert!((m.points[0].separation + 0.05).abs() < 1e-6);
    }

    #[test]
    fn sphere_near_a_corner_of_a_turned_box() {
        let rot = Quat::from_rotation_y(0.7);
        let corner = rot * Vec3::ONE;
        let dir = corner.normalize();
        let m = run(corner + dir * 0.55, rot);
        assert_eq!(m.len, 1);
        assert!((m.points[0].separation - 0.05).abs() < 1e-5);
        assert!((m.normal + dir).length() < 1e-5);
    }

    #[test]
    fn centre_inside_is_pushed_out_through_the_nearest_face() {
        let m = run(Vec3::new(0.2, 0.1, 0.9), Quat::IDENTITY);
        assert!(
            (m.normal + Vec3::Z).length() < 1e-6,
            "out through +z: normal {}",
            m.normal
        );
        assert!((m.points[0].separation + 0.6).abs() < 1e-5);
    }
}
