//! Geometry: the contact manifold of two posed shapes, by a dispatch table over shape
//! pairs. Sphere, box and plane pairs are ours, each in its own file, and capsule–capsule
//! (parry's missed a second point); every other pair with a capsule, cylinder, cone or
//! convex hull goes to parry3d's convex manifolds
//! ([`parry`]), and every pair with a triangle mesh or heightfield to its composite
//! ones, a manifold per touching triangle ([`mesh`]). Plain functions without Bevy's
//! ECS; the narrow phase calls [`collide_each`], the continuous sweep [`collide`].

mod box_box;
mod box_frame;
mod box_plane;
mod capsule_capsule;
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
use crate::world::{ColliderEntry, Manifold};

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

impl<'a> Posed<'a> {
    pub fn of(c: &'a ColliderEntry) -> Self {
        Self {
            shape: &c.shape,
            pos: c.pos,
            rot: c.rot,
        }
    }
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
fn composite(kind: ShapeKind) -> bool {
    matches!(kind, ShapeKind::TriMesh | ShapeKind::HeightField)
}

/// Whether a pair has a mesh or heightfield in it: [`collide_each`] is needed, not
/// [`collide`].
#[inline]
pub fn has_mesh(a: &Shape, b: &Shape) -> bool {
    composite(a.kind()) || composite(b.kind())
}

/// Collides two colliders and calls `each` with every manifold: one for convex pairs,
/// one per touching triangle with a mesh or heightfield. Normals point from `a` to `b`.
pub fn collide_each(
    a: &ColliderEntry,
    ia: u32,
    b: &ColliderEntry,
    ib: u32,
    margin: f32,
    each: &mut dyn FnMut(Manifold),
) {
    let (ka, kb) = (a.shape.kind(), b.shape.kind());
    if !(composite(ka) || composite(kb)) {
        if let Some(m) = collide(a, ia, b, ib, margin) {
            each(m);
        }
        return;
    }
    let swap = ka > kb;
    let (first, second) = if swap { (b, a) } else { (a, b) };
    if DISPATCH[first.shape.kind() as usize][second.shape.kind() as usize].is_none() {
        return;
    }
    mesh::collide(Posed::of(first), Posed::of(second), margin, &mut |mut m| {
        (m.a, m.b) = if swap { (ib, ia) } else { (ia, ib) };
        if swap {
            m.flip();
        }
        each(m);
    });
}

/// Collides two colliders, ordering them for the table. The manifold's normal points from
/// `a` to `b` as given. Returns `None` when they don't touch within `margin`.
pub fn collide(
    a: &ColliderEntry,
    ia: u32,
    b: &ColliderEntry,
    ib: u32,
    margin: f32,
) -> Option<Manifold> {
    if composite(a.shape.kind()) || composite(b.shape.kind()) {
        // The deepest of its manifolds.
        let mut deepest: Option<(f32, Manifold)> = None;
        collide_each(a, ia, b, ib, margin, &mut |m| {
            let d = m
                .points()
                .iter()
                .map(|p| -p.separation)
                .fold(f32::MIN, f32::max);
            if deepest.as_ref().is_none_or(|(best, _)| d > *best) {
                deepest = Some((d, m));
            }
        });
        return deepest.map(|(_, m)| m);
    }
    let nudged;
    let b = match coincident_nudge(a, b) {
        Some(offset) => {
            nudged = ColliderEntry {
                pos: b.pos + offset,
                ..b.clone()
            };
            &nudged
        }
        None => b,
    };
    let swap = a.shape.kind() > b.shape.kind();
    let (first, second) = if swap { (b, a) } else { (a, b) };
    let f = DISPATCH[first.shape.kind() as usize][second.shape.kind() as usize]?;
    let mut m = Manifold {
        a: ia,
        b: ib,
        ..default()
    };
    if swap {
        std::mem::swap(&mut m.a, &mut m.b);
    }
    f(Posed::of(first), Posed::of(second), margin, &mut m);
    if m.len == 0 {
        return None;
    }
    if swap {
        m.flip();
    }
    Some(m)
}

/// Two colliders whose centres coincide give no direction to push apart: box–box ties on
/// every axis, two spheres have no line between centres. Every pair of a pile spawned at
/// one point would then push the same way, and the pile would squeeze out into a long
/// line whose ends fly off. So a coincident pair is collided as if `b` sat a thousandth
/// of the smaller shape's size away, in a direction hashed from the two entities: the
/// pile's pairs push every which way and it spreads as a ball. Returns that offset.
pub(crate) fn coincident_nudge(a: &ColliderEntry, b: &ColliderEntry) -> Option<Vec3> {
    let scale = 0.5e-3 * a.shape.thickness().min(b.shape.thickness());
    if !scale.is_finite() || a.pos.distance_squared(b.pos) > scale * scale {
        return None;
    }
    // Keyed by spawn order, not entity ids: a recycled id must not change the direction.
    let mut h = a.key ^ b.key.rotate_left(32);
    let mut next = || {
        h = h.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let dir = Vec3::new(next(), next(), next()).normalize_or(Vec3::Y);
    Some(dir * scale)
}
