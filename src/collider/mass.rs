//! The mass properties a shape implies: volume, centre of mass, principal axes and
//! moments (solid shapes; surfaces weigh nothing and can only be static or kinematic).

use bevy::prelude::*;

use super::Shape;

impl Shape {
    /// Volume in m³ (0 for planes, which can only be static).
    #[inline]
    pub fn volume(&self) -> f32 {
        match *self {
            Shape::Sphere { radius } => 4.0 / 3.0 * std::f32::consts::PI * radius.powi(3),
            Shape::Cuboid { half_extents: h } => 8.0 * h.x * h.y * h.z,
            Shape::Capsule { .. } | Shape::Cylinder { .. } | Shape::Cone { .. } => {
                crate::geometry::unit_mass(self).0
            }
            Shape::ConvexHull(ref h) => h.volume(),
            // Surfaces: nothing to weigh (they can only be static or kinematic).
            Shape::TriMesh(_) | Shape::HeightField(_) | Shape::Plane { .. } => 0.0,
        }
    }

    /// The solid shape's centre of mass in its local frame, m: the origin but for a
    /// cone, whose centre of mass is a quarter of its height above the base, and a hull.
    #[inline]
    pub fn center_of_mass(&self) -> Vec3 {
        match *self {
            Shape::Cone { half_height, .. } => Vec3::new(0.0, -0.5 * half_height, 0.0),
            Shape::ConvexHull(ref h) => h.center_of_mass(),
            _ => Vec3::ZERO,
        }
    }

    /// The rotation of the shape's principal axes in its local frame: identity but for
    /// a convex hull, whose axes can lie any way.
    #[inline]
    pub fn principal_frame(&self) -> Quat {
        match *self {
            Shape::ConvexHull(ref h) => h.principal_inertia(1.0).1,
            _ => Quat::IDENTITY,
        }
    }

    /// Principal moments of inertia of the solid shape with the given mass, about its
    /// centre of mass along its [`principal_frame`](Self::principal_frame), kg·m².
    #[inline]
    pub fn principal_inertia(&self, mass: f32) -> Vec3 {
        match *self {
            Shape::Sphere { radius } => Vec3::splat(0.4 * mass * radius * radius),
            Shape::Cuboid { half_extents: h } => {
                let s = h * 2.0;
                let (x2, y2, z2) = (s.x * s.x, s.y * s.y, s.z * s.z);
                Vec3::new(y2 + z2, x2 + z2, x2 + y2) * (mass / 12.0)
            }
            // From parry3d's mass properties at unit density, scaled to the mass.
            Shape::Capsule { .. } | Shape::Cylinder { .. } | Shape::Cone { .. } => {
                let (volume, inertia) = crate::geometry::unit_mass(self);
                inertia * (mass / volume)
            }
            Shape::ConvexHull(ref h) => h.principal_inertia(mass).0,
            // Surfaces have no volume; a kinematic one never needs inertia.
            Shape::TriMesh(_) | Shape::HeightField(_) | Shape::Plane { .. } => Vec3::splat(mass),
        }
    }
}
