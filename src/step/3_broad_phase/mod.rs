//! Stage 3, broad phase: candidate collider pairs whose bounding boxes overlap.
//!
//! Each collider's box is swept over the body's free motion this step (start pose and
//! free end pose) and fattened by the speculative margin, so a fast body meets what lies
//! in its path. A bounding-volume tree kept between steps (parry3d's, in the data layer:
//! [`AwakeTree`], which the spatial queries use too) finds the awake overlaps; our sweep
//! and prune, which it replaced, and the brute-force O(n²) search are kept as the
//! references it is tested against.

#[cfg(test)]
mod brute_force;
mod pair_order;
#[cfg(test)]
mod parity_tests;
#[cfg(any(test, feature = "bench-internals"))]
mod sweep_and_prune;

use bevy::prelude::*;

use pair_order::PairOrderScratch;
pub use pair_order::canonical_order;

use crate::limits::MAX_PAIRS_PER_STEP;
use crate::settings::SolverSettings;
#[cfg(doc)]
use crate::world::AwakeTree;
#[cfg(any(test, feature = "bench-internals"))]
use crate::world::ColliderEntry;
use crate::world::{Leaf, PhysicsWorld, STATIC};

#[cfg(test)]
use brute_force::brute_force_pairs;
#[cfg(any(test, feature = "bench-internals"))]
pub use sweep_and_prune::SweepAndPrune;

/// Buffers kept between steps: per fixed entry, its index in this step's collider list
/// (`u32::MAX` when not copied).
#[derive(Default)]
pub struct BroadPhaseScratch {
    copied: Vec<u32>,
    found: Vec<u32>,
    /// The pair cap was hit last step (warn once per episode).
    capped: bool,
    order: PairOrderScratch,
}

/// Updates the awake colliders' swept, fattened bounds and finds the overlapping pairs:
/// awake with awake by the tree, awake with fixed (static or asleep) by asking the
/// [`FixedSet`]. Fixed entries that something may touch are copied to the end of the
/// step's collider list, so later stages see one list.
pub fn find_pairs(
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SolverSettings>,
    mut scratch: Local<BroadPhaseScratch>,
) {
    let world = &mut *world;
    let scratch = &mut *scratch;
    let margin = settings.speculative_margin;
    update_bounds(world, margin);
    let cap = MAX_PAIRS_PER_STEP;
    let mut full = {
        let colliders = &world.colliders;
        let tree = world.awake_tree.get_mut();
        let tree = tree.unwrap_or_else(|e| e.into_inner());
        let leaf = |i: usize| {
            let c = &colliders[i];
            Leaf {
                lo: c.aabb_min,
                hi: c.aabb_max,
                body: c.body,
            }
        };
        tree.pairs(colliders.len(), leaf, &mut world.pairs, cap)
    };

    world.fixed.update_search();
    scratch.copied.clear();
    scratch.copied.resize(world.fixed.len(), u32::MAX);
    let awake = world.colliders.len();
    for ci in 0..awake {
        let c = &world.colliders[ci];
        if c.body == STATIC {
            continue;
        }
        let (c_min, c_max) = (c.aabb_min, c.aabb_max);
        scratch.found.clear();
        let found = &mut scratch.found;
        world
            .fixed
            .touching(c_min, c_max, margin, |f| found.push(f));
        if world.pairs.len() + found.len() > cap {
            full = true;
            break;
        }
        for &f in found.iter() {
            let slot = &mut scratch.copied[f as usize];
            if *slot == u32::MAX {
                *slot = world.colliders.len() as u32;
                world
                    .colliders
                    .push(world.fixed.entries()[f as usize].clone());
            }
            world.pairs.push((ci as u32, *slot));
        }
    }
    canonical_order(&world.colliders, &mut world.pairs, &mut scratch.order);
    if full && !scratch.capped {
        warn!(
            "tumble: more than {cap} overlapping pairs this step (a pile spawned into one \
             point?); the rest wait for later steps"
        );
    }
    scratch.capped = full;
}

/// Bounds over the start and free-end poses, fattened by `margin`.
pub fn update_bounds(world: &mut PhysicsWorld, margin: f32) {
    for ci in 0..world.colliders.len() {
        let c = &world.colliders[ci];
        let (mut lo, mut hi) = c.shape.aabb(c.pos, c.rot);
        if c.body != STATIC {
            let (p, q) = world.collider_pose(c);
            let (lo1, hi1) = c.shape.aabb(p, q);
            (lo, hi) = (lo.min(lo1), hi.max(hi1));
        }
        let c = &mut world.colliders[ci];
        c.aabb_min = lo - Vec3::splat(margin);
        c.aabb_max = hi + Vec3::splat(margin);
    }
}

#[cfg(any(test, feature = "bench-internals"))]
fn overlaps(a: &ColliderEntry, b: &ColliderEntry) -> bool {
    a.aabb_min.cmple(b.aabb_max).all() && b.aabb_min.cmple(a.aabb_max).all()
}

/// A pair is only kept if at least one side can move; static–static and colliders of the
/// same body never collide. (The reference for [`Leaf`]'s rule, which the tree applies.)
#[cfg(any(test, feature = "bench-internals"))]
fn candidate(a: &ColliderEntry, b: &ColliderEntry) -> bool {
    (a.body != STATIC || b.body != STATIC) && a.body != b.body && overlaps(a, b)
}
