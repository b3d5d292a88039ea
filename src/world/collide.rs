//! A step's colliders into the geometry: the contact manifolds of two [`ColliderEntry`]s
//! at their start-of-step poses, by the geometry's dispatch table. The narrow phase calls
//! [`collide_each`]; the continuous sweep and the wake before a step call [`collide`].

use bevy::prelude::*;

use super::ColliderEntry;
use crate::geometry::{DISPATCH, Manifold, Posed, collide_mesh, composite};

/// A collider's shape at its pose.
fn posed(c: &ColliderEntry) -> Posed<'_> {
    Posed {
        shape: &c.shape,
        pos: c.pos,
        rot: c.rot,
    }
}

/// Collides two colliders and calls `each` with every manifold: one for convex pairs,
/// one per touching triangle with a mesh or heightfield. Normals point from `a` to `b`.
pub(crate) fn collide_each(
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
    collide_mesh(posed(first), posed(second), margin, &mut |mut m| {
        (m.a, m.b) = if swap { (ib, ia) } else { (ia, ib) };
        if swap {
            m.flip();
        }
        each(m);
    });
}

/// Collides two colliders, ordering them for the table. The manifold's normal points from
/// `a` to `b` as given. Returns `None` when they don't touch within `margin`.
pub(crate) fn collide(
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
    f(posed(first), posed(second), margin, &mut m);
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
