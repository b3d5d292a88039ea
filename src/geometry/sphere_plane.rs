//! Sphere–plane and sphere–bounded-plane.
//!
//! An infinite plane is a half-space: everything below it is inside and is pushed up.
//! A bounded plane (a rectangle) is a thin two-sided wall: a sphere touches the face from
//! the side its centre is on, or an edge or corner of the rectangle.

use bevy::prelude::*;

use super::{Manifold, Posed};

/// Feature ids: the face, or an edge/corner region of the rectangle.
const FACE: u32 = 0;

pub fn collide(
    sphere: Posed,
    r: f32,
    plane: Posed,
    half: Option<Vec2>,
    margin: f32,
    out: &mut Manifold,
) {
    let n = plane.rot * Vec3::Y;
    let local = plane.rot.inverse() * (sphere.pos - plane.pos);
    let Some(h) = half else {
        // Half-space: the contact normal points from the sphere into the plane.
        let s = local.y - r;
        if s <= margin {
            out.normal = -n;
            out.push(sphere.pos - n * (r + 0.5 * s), s, FACE);
        }
        return;
    };
    let clamped = Vec3::new(local.x.clamp(-h.x, h.x), 0.0, local.z.clamp(-h.y, h.y));
    let region = u32::from(clamped.x != local.x) | (u32::from(clamped.z != local.z) << 1);
    let d = local - clamped;
    let dist = d.length();
    let s = dist - r;
    if s > margin {
        return;
    }
    // Normal from the sphere towards the closest point of the rectangle.
    let local_n = if dist > 1e-9 { -d / dist } else { -Vec3::Y };
    out.normal = plane.rot * local_n;
    let closest = plane.pos + plane.rot * clamped;
    out.push(closest - out.normal * (0.5 * s), s, FACE + region);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    fn posed(shape: &Shape, pos: Vec3, rot: Quat) -> Posed<'_> {
        Posed { shape, pos, rot }
    }

    #[test]
    fn sphere_above_tilted_plane() {
        let (s, p) = (
            Shape::Sphere { radius: 0.5 },
            Shape::Plane { half_extents: None },
        );
        let rot = Quat::from_rotation_z(0.3);
        let n = rot * Vec3::Y;
        let mut m = Manifold::default();
        collide(
            posed(&s, n * 0.6, Quat::IDENTITY),
            0.5,
            posed(&p, Vec3::ZERO, rot),
            None,
            0.2,
            &mut m,
        );
        assert_eq!(m.len, 1);
        assert!((m.points[0].separation - 0.1).abs() < 1e-6);
        assert!((m.normal + n).length() < 1e-6);
        // The point lies midway between the surfaces.
        assert!((m.points[0].point - n * 0.05).length() < 1e-6);
    }

    #[test]
    fn sphere_beside_bounded_plane_touches_its_edge() {
        let (s, p) = (
            Shape::Sphere { radius: 0.5 },
            Shape::Plane {
                half_extents: Some(Vec2::ONE),
            },
        );
        let mut m = Manifold::default();
        // Level with the plane, 0.4 m beyond its +x edge: overlap 0.1 at the edge.
        collide(
            posed(&s, Vec3::new(1.4, 0.0, 0.0), Quat::IDENTITY),
            0.5,
            posed(&p, Vec3::ZERO, Quat::IDENTITY),
            Some(Vec2::ONE),
            0.0,
            &mut m,
        );
        assert_eq!(m.len, 1);
        assert!((m.points[0].separation + 0.1).abs() < 1e-6);
        assert!((m.normal - Vec3::NEG_X).length() < 1e-6);
        // Off the rectangle entirely: nothing.
        let mut m = Manifold::default();
        collide(
            posed(&s, Vec3::new(3.0, 0.0, 0.0), Quat::IDENTITY),
            0.5,
            posed(&p, Vec3::ZERO, Quat::IDENTITY),
            Some(Vec2::ONE),
            0.1,
            &mut m,
        );
        assert_eq!(m.len, 0);
    }

    #[test]
    fn bounded_plane_is_two_sided() {
        let (s, p) = (
            Shape::Sphere { radius: 0.5 },
            Shape::Plane {
                half_extents: Some(Vec2::ONE),
            },
        );
        let mut m = Manifold::default();
        collide(
            posed(&s, Vec3::new(0.0, -0.45, 0.0), Quat::IDENTITY),
            0.5,
            posed(&p, Vec3::ZERO, Quat::IDENTITY),
            Some(Vec2::ONE),
            0.0,
            &mut m,
        );
        assert!(
            (m.normal - Vec3::Y).length() < 1e-6,
            "pushed down, away from the wall"
        );
    }
}
