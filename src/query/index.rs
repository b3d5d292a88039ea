//! Which colliders a query looks at: the awake colliders of the last step at their
//! end-of-step poses, searched by the broad phase's tree ([`AwakeTree`]), refitted to
//! those poses the first time a query asks after a step (a scene that never queries
//! never pays for it), and the fixed set (static colliders, sleepers) by its own index,
//! kept by the broad phase. The brute-force walk over everything is the reference the
//! tests hold the index to.

use std::sync::RwLock;

use bevy::prelude::*;

#[cfg(doc)]
use crate::world::AwakeTree;
use crate::world::{ColliderEntry, PhysicsWorld, STATIC};

/// An awake collider at the end of the last step.
#[derive(Clone, Copy, Debug)]
struct AwakePose {
    /// Index into `PhysicsWorld::colliders`.
    collider: u32,
    pos: Vec3,
    rot: Quat,
    lo: Vec3,
    hi: Vec3,
}

/// The awake colliders' poses and boxes, and the step they are of.
#[derive(Default, Debug)]
pub(crate) struct AwakeIndex {
    /// The step (`PhysicsWorld::step_count`) and collider count it was built for.
    built_for: Option<(u64, usize)>,
    /// Leaf i of the world's awake tree is `poses[i]`.
    poses: Vec<AwakePose>,
    /// The awake boxes' union, m.
    awake_extent: (Vec3, Vec3),
    /// The fixed set's boxes' union, when its own index was stale (collisions off).
    fixed_extent: (Vec3, Vec3),
}

/// A collider a query may look at: its entry, its pose now and its box, m.
pub(crate) struct Candidate<'a> {
    pub entry: &'a ColliderEntry,
    pub pose: (Vec3, Quat),
    pub lo: Vec3,
    pub hi: Vec3,
}

impl AwakeIndex {
    fn is_current(&self, world: &PhysicsWorld) -> bool {
        self.built_for == Some((world.step_count, world.colliders.len()))
    }

    fn rebuild(&mut self, world: &PhysicsWorld) {
        self.poses.clear();
        for (i, c) in world.colliders.iter().enumerate() {
            // Fixed entries copied in by the broad phase (after the awake ones) are
            // searched in the fixed set.
            if c.body == STATIC {
                debug_assert!(world.colliders[i..].iter().all(|c| c.body == STATIC));
                break;
            }
            let (pos, rot) = world.collider_pose(c);
            let (lo, hi) = c.shape.aabb(pos, rot);
            self.poses.push(AwakePose {
                collider: i as u32,
                pos,
                rot,
                lo,
                hi,
            });
        }
        let poses = &self.poses;
        let mut tree = world.awake_tree.write().unwrap_or_else(|e| e.into_inner());
        tree.fit(poses.len(), |i| (poses[i].lo, poses[i].hi));
        self.awake_extent = tree.extent();
        self.fixed_extent = if world.fixed.is_searchable() {
            world.fixed.extent()
        } else {
            finite_union(
                world
                    .fixed
                    .entries()
                    .iter()
                    .map(|c| (c.aabb_min, c.aabb_max)),
            )
        };
        self.built_for = Some((world.step_count, world.colliders.len()));
    }

    /// Calls `found` with every collider whose box overlaps [lo, hi] and passes `test`
    /// (given a box: lo, hi): the awake ones from the tree, whose subtrees `test` prunes
    /// (a ray's slab test prunes far more than its bounding box), then the fixed ones.
    pub fn overlapping<'a>(
        &self,
        world: &'a PhysicsWorld,
        (lo, hi): (Vec3, Vec3),
        test: impl Fn(Vec3, Vec3) -> bool,
        mut found: impl FnMut(Candidate<'a>),
    ) {
        let poses = &self.poses;
        let meets = |a: Vec3, b: Vec3| a.cmple(hi).all() && lo.cmple(b).all() && test(a, b);
        let tree = world.awake_tree.read().unwrap_or_else(|e| e.into_inner());
        debug_assert_eq!(tree.len(), poses.len(), "the tree fits this step's poses");
        tree.visit(meets, |i| {
            let p = &poses[i as usize];
            found(Candidate {
                entry: &world.colliders[p.collider as usize],
                pose: (p.pos, p.rot),
                lo: p.lo,
                hi: p.hi,
            })
        });
        let entries = world.fixed.entries();
        let fixed = |i: u32| {
            let c = &entries[i as usize];
            Candidate {
                entry: c,
                pose: (c.pos, c.rot),
                lo: c.aabb_min,
                hi: c.aabb_max,
            }
        };
        let mut offer = |c: Candidate<'a>| {
            if test(c.lo, c.hi) {
                found(c);
            }
        };
        if world.fixed.is_searchable() {
            world.fixed.overlapping(lo, hi, 0.0, |i| offer(fixed(i)));
        } else {
            // Changed since the broad phase last ran (or collisions are off): every entry.
            for i in 0..entries.len() as u32 {
                let c = fixed(i);
                if c.lo.cmple(hi).all() && lo.cmple(c.hi).all() {
                    offer(c);
                }
            }
        }
    }

    /// Every collider, no box test: the reference the indexed walk is tested against.
    #[cfg(test)]
    pub fn all<'a>(&self, world: &'a PhysicsWorld, mut found: impl FnMut(Candidate<'a>)) {
        for p in &self.poses {
            found(Candidate {
                entry: &world.colliders[p.collider as usize],
                pose: (p.pos, p.rot),
                lo: p.lo,
                hi: p.hi,
            });
        }
        for c in world.fixed.entries() {
            found(Candidate {
                entry: c,
                pose: (c.pos, c.rot),
                lo: c.aabb_min,
                hi: c.aabb_max,
            });
        }
    }

    /// The union of every finite collider box, m (lo > hi when there is none): a query
    /// along an unbounded ray or sweep need search no farther.
    pub fn extent(&self) -> (Vec3, Vec3) {
        let (a, b) = (self.awake_extent, self.fixed_extent);
        (a.0.min(b.0), a.1.max(b.1))
    }
}

/// The union of the finite boxes among `boxes`.
fn finite_union(boxes: impl Iterator<Item = (Vec3, Vec3)>) -> (Vec3, Vec3) {
    boxes
        .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), (lo, hi)| {
            (a.min(lo), b.max(hi))
        })
}

/// The spatial queries' cache: the awake colliders' index, built lazily after each step.
/// Added by [`TumblePlugin`](crate::TumblePlugin); read through
/// [`SpatialQuery`](super::SpatialQuery).
#[derive(Resource, Default)]
pub(crate) struct SpatialQueryCache {
    awake: RwLock<AwakeIndex>,
    /// Tests: walk every collider and skip every box test (the reference).
    #[cfg(test)]
    pub(crate) brute_force: std::sync::atomic::AtomicBool,
}

impl SpatialQueryCache {
    /// Whether queries check everything (tests' reference) rather than the index.
    #[cfg(test)]
    pub(crate) fn brute_force(&self) -> bool {
        self.brute_force.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Runs `f` with the awake index of the world's last step, building it first if the
    /// world has stepped since.
    pub(crate) fn with<R>(&self, world: &PhysicsWorld, f: impl FnOnce(&AwakeIndex) -> R) -> R {
        {
            let index = self.awake.read().unwrap_or_else(|e| e.into_inner());
            if index.is_current(world) {
                return f(&index);
            }
        }
        let mut index = self.awake.write().unwrap_or_else(|e| e.into_inner());
        if !index.is_current(world) {
            index.rebuild(world);
        }
        f(&index)
    }
}
