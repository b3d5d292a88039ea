//! Stage 3, broad phase: candidate collider pairs whose bounding boxes overlap.
//!
//! Each collider's box is swept over the body's free motion this step (start pose and
//! free end pose) and fattened by the speculative margin, so a fast body meets what lies
//! in its path. Sweep-and-prune finds the overlaps; the brute-force O(n²) search is kept
//! as the reference it is tested against.

mod brute_force;
mod sweep_and_prune;

use bevy::prelude::*;

use crate::settings::SolverSettings;
use crate::world::{ColliderEntry, PhysicsWorld, STATIC};

pub use brute_force::brute_force_pairs;
pub use sweep_and_prune::SweepAndPrune;

/// Updates every collider's swept, fattened bounds and finds the overlapping pairs.
pub fn find_pairs(
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SolverSettings>,
    mut sap: Local<SweepAndPrune>,
) {
    let world = &mut *world;
    update_bounds(world, settings.speculative_margin);
    sap.pairs(&world.colliders, &mut world.pairs);
}

/// Bounds over the start and free-end poses, fattened by `margin`.
pub fn update_bounds(world: &mut PhysicsWorld, margin: f32) {
    for ci in 0..world.colliders.len() {
        let c = world.colliders[ci];
        let (mut lo, mut hi) = c.shape.aabb(c.pos, c.rot);
        if c.body != STATIC {
            let (p, q) = world.body_pose(c.body as usize);
            let (lo1, hi1) = c.shape.aabb(p, q);
            (lo, hi) = (lo.min(lo1), hi.max(hi1));
        }
        let c = &mut world.colliders[ci];
        c.aabb_min = lo - Vec3::splat(margin);
        c.aabb_max = hi + Vec3::splat(margin);
    }
}

fn overlaps(a: &ColliderEntry, b: &ColliderEntry) -> bool {
    a.aabb_min.cmple(b.aabb_max).all() && b.aabb_min.cmple(a.aabb_max).all()
}

/// A pair is only kept if at least one side can move; static–static and colliders of the
/// same body never collide.
fn candidate(a: &ColliderEntry, b: &ColliderEntry) -> bool {
    (a.body != STATIC || b.body != STATIC) && a.body != b.body && overlaps(a, b)
}
