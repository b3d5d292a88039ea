//! Hidden entry points for `benches/pairs.rs` (feature `bench-internals`): one shape
//! pair's manifold through our hand-written function or through parry3d, so the two can
//! be timed on the same poses. Not part of the API.

use bevy::prelude::*;

use crate::collider::Shape;
use crate::geometry::{DISPATCH, Posed, parry_collide};
use crate::world::Manifold;

pub use crate::rng::Rnd;

/// Which implementation collides the pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Implementation {
    /// The dispatch table's function (ours where we have one).
    Ours,
    /// Parry's convex manifold, converted as for every parry pair.
    Parry,
}

/// The number of points of A's manifold with B (A's kind ≤ B's kind) within `margin`.
pub fn collide(
    with: Implementation,
    a: (&Shape, Vec3, Quat),
    b: (&Shape, Vec3, Quat),
    margin: f32,
) -> usize {
    let pa = Posed { shape: a.0, pos: a.1, rot: a.2 };
    let pb = Posed { shape: b.0, pos: b.1, rot: b.2 };
    let mut m = Manifold::default();
    match with {
        Implementation::Ours => {
            if let Some(f) = DISPATCH[a.0.kind() as usize][b.0.kind() as usize] {
                f(pa, pb, margin, &mut m);
            }
        }
        Implementation::Parry => parry_collide(pa, pb, margin, &mut m),
    }
    m.len
}
