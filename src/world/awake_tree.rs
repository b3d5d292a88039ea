//! The awake colliders' bounding-volume tree (parry3d's `Bvh`), kept between steps and
//! shared by the broad phase and the spatial queries. Leaf i is collider i of the step's
//! list (the awake ones come first).
//!
//! - The broad phase gives each leaf its collider's swept, fattened box, refits and
//!   traverses the tree against itself ([`AwakeTree::pairs`]). When the number of awake
//!   colliders changes, leaf i is another collider than last step, so the tree is built
//!   afresh. Measured against our sweep and prune on the same boxes
//!   (`benches/broad_phase.rs`): the same pairs, 8–16× faster (rain: 41.5 against
//!   674 µs a step), so it replaced it.
//! - A spatial query after the step refits the same tree to the colliders' end-of-step
//!   boxes ([`AwakeTree::fit`]) the first time it asks (a bounced body can end outside
//!   its swept box), then walks it ([`AwakeTree::visit`]). A game that never queries
//!   never pays for that refit; the next step's broad phase overwrites every leaf anyway.

use bevy::prelude::*;
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace, TraversalAction};

/// The least number of leaves for which the tree is re-optimised as it is refitted.
pub(crate) const OPTIMIZE_FROM: usize = 256;

/// The tree over the awake colliders and its scratch.
#[derive(Default)]
pub(crate) struct AwakeTree {
    bvh: Bvh,
    workspace: BvhWorkspace,
    /// Leaves in the tree.
    leaves: usize,
    /// Scratch for building afresh.
    boxes: Vec<Aabb>,
}

impl AwakeTree {
    /// Gives leaf i the box `aabb(i)` for i in `0..n`: refitted in place when the tree
    /// has `n` leaves, else built afresh.
    pub fn fit(&mut self, n: usize, aabb: impl Fn(usize) -> (Vec3, Vec3)) {
        let leaf = |i| {
            let (lo, hi) = aabb(i);
            Aabb::new(lo, hi)
        };
        if n != self.leaves {
            self.boxes.clear();
            self.boxes.extend((0..n).map(leaf));
            self.bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.boxes);
            self.leaves = n;
        } else {
            for i in 0..n {
                self.bvh.insert_or_update_partially(leaf(i), i as u32, 0.0);
            }
            self.bvh.refit(&mut self.workspace);
        }
        debug_assert_eq!(self.bvh.leaf_count() as usize, n, "one leaf per collider");
    }

    /// [`fit`](Self::fit) for the broad phase (which also lets the tree improve its
    /// shape a little each step), then every overlapping pair of leaves (i < j) that
    /// `keep` accepts, in no particular order, up to `cap` of them. Returns whether the
    /// cap cut the list short.
    pub fn pairs(
        &mut self,
        n: usize,
        aabb: impl Fn(usize) -> (Vec3, Vec3),
        keep: impl Fn(u32, u32) -> bool,
        pairs: &mut Vec<(u32, u32)>,
        cap: usize,
    ) -> bool {
        pairs.clear();
        let refit = n == self.leaves;
        self.fit(n, aabb);
        // A small tree's shape matters little, and parry's incremental optimisation
        // rebuilds parts of it each step: for 35 bouncing balls it was a third of the
        // broad phase.
        if refit && n >= OPTIMIZE_FROM {
            self.bvh.optimize_incremental(&mut self.workspace);
        }
        let mut full = false;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| {
                if keep(a, b) {
                    if pairs.len() == cap {
                        full = true;
                    } else {
                        pairs.push((a.min(b), a.max(b)));
                    }
                }
            });
        full
    }

    /// Number of leaves (colliders) the tree holds.
    pub fn len(&self) -> usize {
        self.leaves
    }

    /// Calls `found` with each leaf whose box passes `test` (given lo and hi, m), testing
    /// inner boxes first so that a subtree whose box fails is skipped whole.
    pub fn visit(&self, test: impl Fn(Vec3, Vec3) -> bool, mut found: impl FnMut(u32)) {
        if self.leaves == 0 {
            return;
        }
        self.bvh.traverse(|node| {
            if !test(node.mins(), node.maxs()) {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                found(leaf);
            }
            TraversalAction::Continue
        });
    }

    /// The union of the leaves' boxes, m (lo > hi when empty).
    pub fn extent(&self) -> (Vec3, Vec3) {
        if self.leaves == 0 {
            return (Vec3::INFINITY, Vec3::NEG_INFINITY);
        }
        let root = self.bvh.root_aabb();
        (root.mins, root.maxs)
    }
}
