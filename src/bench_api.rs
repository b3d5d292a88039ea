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
    let pa = Posed {
        shape: a.0,
        pos: a.1,
        rot: a.2,
    };
    let pb = Posed {
        shape: b.0,
        pos: b.1,
        rot: b.2,
    };
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

/// Our sweep and prune over boxes, kept between calls as in the step (its order is last
/// call's, so nearly sorted input sorts in one pass).
#[derive(Default)]
pub struct SweepAndPrune {
    sap: crate::step::broad_phase::SweepAndPrune,
    colliders: Vec<crate::world::ColliderEntry>,
    pairs: Vec<(u32, u32)>,
}

impl SweepAndPrune {
    /// The overlapping pairs among `boxes` (min, max), each a body of its own.
    pub fn pairs(&mut self, boxes: &[(Vec3, Vec3)]) -> &[(u32, u32)] {
        use crate::world::{ColliderEntry, ContactFilter};
        self.colliders.truncate(boxes.len());
        while self.colliders.len() < boxes.len() {
            let i = self.colliders.len() as u32;
            self.colliders.push(ColliderEntry {
                entity: Entity::PLACEHOLDER,
                owner: Entity::PLACEHOLDER,
                key: i as u64,
                body: i,
                asleep: false,
                shape: Shape::Sphere { radius: 0.5 },
                offset: Vec3::ZERO,
                local_rot: Quat::IDENTITY,
                pos: Vec3::ZERO,
                rot: Quat::IDENTITY,
                friction: 0.5,
                restitution: 0.0,
                filter: ContactFilter::default(),
                aabb_min: Vec3::ZERO,
                aabb_max: Vec3::ZERO,
            });
        }
        for (c, &(lo, hi)) in self.colliders.iter_mut().zip(boxes) {
            (c.aabb_min, c.aabb_max) = (lo, hi);
        }
        self.sap.pairs(&self.colliders, &mut self.pairs, usize::MAX);
        &self.pairs
    }
}
