//! Geometry: the contact manifold of two posed shapes, by a dispatch table over shape
//! pairs. Sphere, box and plane pairs are ours, each in its own file, and capsule–capsule
//! (parry's missed a second point); every other pair with a capsule, cylinder, cone or
//! convex hull goes to parry3d's convex manifolds
//! ([`parry`]), and every pair with a triangle mesh or heightfield to its composite
//! ones, a manifold per touching triangle ([`mesh`]). Plain functions without Bevy's
//! ECS, over [`Posed`] shapes; the data layer's `collide` and `collide_each` bring a
//! step's colliders to them.

mod box_box;
mod box_frame;
mod box_plane;
mod capsule_capsule;
mod manifold;
mod mesh;
#[cfg(test)]
mod parity_tests;
mod parry;
mod polygon;
pub(crate) mod query;
mod ray_interval;
mod sphere_box;
mod sphere_plane;
mod sphere_sphere;

use bevy::prelude::*;

use crate::collider::{Shape, ShapeKind};
pub(crate) use manifold::{Anchors, MAX_POINTS, Manifold};

#[cfg(feature = "bench-internals")]
pub(crate) use parry::collide as parry_collide;
pub(crate) use parry::{posed_aabb, unit_mass};

/// A shape at a pose.
#[derive(Clone, Copy, Debug)]
pub struct Posed<'a> {
    pub shape: &'a Shape,
    pub pos: Vec3,
    pub rot: Quat,
}

/// Collides A with B (A's kind ≤ B's kind) and fills `out` (normal from A to B, points).
pub type CollideFn = fn(Posed, Posed, f32, &mut Manifold);

fn sphere_sphere(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (Shape::Sphere { radius: ra }, Shape::Sphere { radius: rb }) = (a.shape, b.shape) else {
        return;
    };
    sphere_sphere::collide(a, *ra, b, *rb, margin, out);
}

fn sphere_plane(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (Shape::Sphere { radius }, Shape::Plane { half_extents }) = (a.shape, b.shape) else {
        return;
    };
    sphere_plane::collide(a, *radius, b, *half_extents, margin, out);
}

fn sphere_box(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (Shape::Sphere { radius }, Shape::Cuboid { half_extents }) = (a.shape, b.shape) else {
        return;
    };
    sphere_box::collide(a, *radius, b, *half_extents, margin, out);
}

fn box_box(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (Shape::Cuboid { half_extents: ha }, Shape::Cuboid { half_extents: hb }) =
        (a.shape, b.shape)
    else {
        return;
    };
    box_box::collide(a, *ha, b, *hb, margin, out);
}

fn capsule_capsule(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (
        Shape::Capsule {
            radius: ra,
            half_height: ha,
        },
        Shape::Capsule {
            radius: rb,
            half_height: hb,
        },
    ) = (a.shape, b.shape)
    else {
        return;
    };
    capsule_capsule::collide(a, (*ra, *ha), b, (*rb, *hb), margin, out);
}

fn box_plane(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (Shape::Cuboid { half_extents }, Shape::Plane { half_extents: rect }) = (a.shape, b.shape)
    else {
        return;
    };
    box_plane::collide(a, *half_extents, b, *rect, margin, out);
}

/// The dispatch table, indexed by [`ShapeKind`] (A ≤ B). `None`: the pair never collides.
/// Meshes and heightfields (`m`) are not in it: [`collide_each`] sends them to
/// [`mesh`] first; their cells only mark which pairs collide.
pub(crate) const DISPATCH: [[Option<CollideFn>; ShapeKind::COUNT]; ShapeKind::COUNT] = {
    let p = Some(parry::collide as CollideFn);
    let m = Some(no_single as CollideFn);
    let (ss, sb, sp) = (
        Some(sphere_sphere as CollideFn),
        Some(sphere_box as CollideFn),
        Some(sphere_plane as CollideFn),
    );
    let (bb, bp) = (Some(box_box as CollideFn), Some(box_plane as CollideFn));
    let cc = Some(capsule_capsule as CollideFn);
    [
        // Sphere Cuboid Capsule Cylinder Cone Hull TriMesh HeightField Plane
        [ss, sb, p, p, p, p, m, m, sp],             // Sphere
        [None, bb, p, p, p, p, m, m, bp],           // Cuboid
        [None, None, cc, p, p, p, m, m, p],         // Capsule
        [None, None, None, p, p, p, m, m, p],       // Cylinder
        [None, None, None, None, p, p, m, m, p],    // Cone
        [None, None, None, None, None, p, m, m, p], // Convex hull
        [None, None, None, None, None, None, None, None, None], // TriMesh (never moved by contact)
        [None, None, None, None, None, None, None, None, None], // HeightField
        [None, None, None, None, None, None, None, None, None], // Plane (static only)
    ]
};

/// The table's mark for the mesh pairs, which [`collide_each`] handles before it.
fn no_single(_: Posed, _: Posed, _: f32, _: &mut Manifold) {}

/// Whether a kind collides as a mesh of triangles (several manifolds a pair).
#[inline]
pub(crate) fn composite(kind: ShapeKind) -> bool {
    matches!(kind, ShapeKind::TriMesh | ShapeKind::HeightField)
}

/// Whether a pair has a mesh or heightfield in it: it has a manifold per touching
/// triangle, not one.
#[inline]
pub fn has_mesh(a: &Shape, b: &Shape) -> bool {
    composite(a.kind()) || composite(b.kind())
}

/// A mesh or heightfield pair's manifolds, one per touching triangle (`first`'s kind ≤
/// `second`'s).
pub(crate) fn collide_mesh(
    first: Posed,
    second: Posed,
    margin: f32,
    each: &mut dyn FnMut(Manifold),
) {
    mesh::collide(first, second, margin, each);
}
