//! The awake colliders' bounding-volume tree (parry3d's `Bvh`), kept between steps and
//! shared by the broad phase and the spatial queries. Leaf i is collider i of the step's
//! list (the awake ones come first).
//!
//! - The broad phase ([`AwakeTree::pairs`]) gives each leaf a box enlarged past its
//!   collider's swept, fattened box (by [`ENLARGE`] of its longest side), as Box2D's
//!   broad phase does, and keeps the pairs of overlapping enlarged boxes (the
//!   candidates) between steps. While every swept box stays inside its enlarged one, the
//!   candidates still hold every overlapping pair, and a step only tests them against
//!   this step's boxes: a settled stack walks no tree at all. A leaf whose swept box
//!   leaves its enlarged box gets a new one, and its candidates are found again by one
//!   query down the tree; when many do, or the number of awake colliders changes (then
//!   leaf i is another collider than last step and the tree is built afresh), the
//!   candidates come from traversing the tree against itself. Measured against our
//!   sweep and prune on the same boxes (`benches/broad_phase.rs`), that traversal found
//!   the same pairs 8–16× faster (rain: 41.5 against 674 µs a step), hence the tree.
//! - A spatial query after the step refits the same tree to the colliders' end-of-step
//!   boxes ([`AwakeTree::fit`]) the first time it asks (a bounced body can end outside
//!   its swept box), then walks it ([`AwakeTree::visit`]). A game that never queries
//!   never pays for that refit; one that does makes the next step's broad phase start
//!   afresh (the tree no longer holds the enlarged boxes).

use bevy::prelude::*;
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace, TraversalAction};

use super::STATIC;

/// The least number of leaves for which the tree is re-optimised as it is refitted.
pub(crate) const OPTIMIZE_FROM: usize = 256;

/// How far a leaf's box in the tree reaches past its collider's swept box on each side,
/// as a share of that box's longest side (Box2D enlarges by 0.1 m, for bodies of about
/// a metre): a resting body stays inside it for good, a falling one for a few steps.
pub(crate) const ENLARGE: f32 = 0.1;

/// When more than one leaf in this many leaves its enlarged box in a step, the
/// candidates come from traversing the whole tree instead of a query per such leaf.
const REQUERY_SHARE: usize = 8;

/// A leaf as the broad phase sees it this step: its collider's swept, fattened box (m)
/// and body.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Leaf {
    pub lo: Vec3,
    pub hi: Vec3,
    pub body: u32,
}

impl Leaf {
    /// The pair rule: different bodies, not both static, boxes overlapping.
    #[inline]
    fn pairs_with(&self, o: &Leaf) -> bool {
        self.body != o.body
            && (self.body != STATIC || o.body != STATIC)
            && self.lo.cmple(o.hi).all()
            && o.lo.cmple(self.hi).all()
    }

    fn enlarged(&self) -> Aabb {
        let extra = Vec3::splat(ENLARGE * (self.hi - self.lo).max_element());
        Aabb::new(self.lo - extra, self.hi + extra)
    }

    fn inside(&self, b: &Aabb) -> bool {
        b.mins.cmple(self.lo).all() && self.hi.cmple(b.maxs).all()
    }
}

/// The tree over the awake colliders and its scratch.
#[derive(Default)]
pub(crate) struct AwakeTree {
    bvh: Bvh,
    workspace: BvhWorkspace,
    /// Leaves in the tree.
    leaves: usize,
    /// Scratch for building afresh.
    boxes: Vec<Aabb>,
    /// The broad phase's state between steps.
    kept: Kept,
}

/// What the broad phase keeps between steps: each leaf's enlarged box (what the tree
/// holds while `valid`) and the pairs of overlapping enlarged boxes.
#[derive(Default)]
struct Kept {
    /// The tree holds `enlarged` and `candidates` are all its overlapping pairs.
    valid: bool,
    /// The last step's candidates passed the pair cap: find pairs directly until the
    /// pairs fall well under it (a spawned pile), rather than fill two lists a step.
    crowded: bool,
    enlarged: Vec<Aabb>,
    /// Pairs of leaves (i < j) whose enlarged boxes overlap, in no particular order.
    candidates: Vec<(u32, u32)>,
    /// This step's leaves.
    leaves: Vec<Leaf>,
    /// Leaves whose swept box left their enlarged box this step, and a flag per leaf.
    moved: Vec<u32>,
    is_moved: Vec<bool>,
}

impl AwakeTree {
    /// Gives leaf i the box `aabb(i)` for i in `0..n`: refitted in place when the tree
    /// has `n` leaves, else built afresh.
    pub fn fit(&mut self, n: usize, aabb: impl Fn(usize) -> (Vec3, Vec3)) {
        self.kept.valid = false;
        self.place(n, |i| {
            let (lo, hi) = aabb(i);
            Aabb::new(lo, hi)
        });
    }

    fn place(&mut self, n: usize, leaf: impl Fn(usize) -> Aabb) {
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

    /// Every pair of leaves (i < j) of `leaf(i)` for i in `0..n` that pairs: different
    /// bodies, not both static, boxes overlapping; in no particular order, up to `cap`
    /// of them. Returns whether the cap cut the list short.
    pub fn pairs(
        &mut self,
        n: usize,
        leaf: impl Fn(usize) -> Leaf,
        pairs: &mut Vec<(u32, u32)>,
        cap: usize,
    ) -> bool {
        pairs.clear();
        let kept = &mut self.kept;
        kept.leaves.clear();
        kept.leaves.extend((0..n).map(leaf));
        if n != self.leaves {
            // Colliders came or went: leaf i is another collider than last step.
            kept.enlarged.clear();
            kept.enlarged.extend(kept.leaves.iter().map(Leaf::enlarged));
            return self.pairs_directly(pairs, cap);
        }
        kept.moved.clear();
        for (i, (l, e)) in kept.leaves.iter().zip(&mut kept.enlarged).enumerate() {
            if !l.inside(e) {
                *e = l.enlarged();
                kept.moved.push(i as u32);
            }
        }
        // When many leave their boxes (bouncing balls), the candidates would only add a
        // filter to the traversal.
        if kept.crowded || kept.moved.len() * REQUERY_SHARE > n {
            return self.pairs_directly(pairs, cap);
        }
        if !self.update_candidates(cap) {
            self.kept.crowded = true;
            return self.pairs_directly(pairs, cap);
        }
        let leaves = &self.kept.leaves;
        for &(a, b) in &self.kept.candidates {
            if leaves[a as usize].pairs_with(&leaves[b as usize]) {
                if pairs.len() == cap {
                    return true;
                }
                pairs.push((a, b));
            }
        }
        false
    }

    /// Brings the tree and the candidates up to this step's enlarged boxes (the tree has
    /// `n` leaves, and few moved). Returns false when the candidates passed `cap` (then
    /// the tree holds no valid state).
    fn update_candidates(&mut self, cap: usize) -> bool {
        let n = self.kept.leaves.len();
        let fresh = !self.kept.valid;
        if fresh {
            let enlarged = std::mem::take(&mut self.kept.enlarged);
            self.place(n, |i| enlarged[i]);
            self.kept.enlarged = enlarged;
        } else if self.kept.moved.is_empty() {
            return true;
        } else {
            for &i in &self.kept.moved {
                let e = self.kept.enlarged[i as usize];
                self.bvh.insert_or_update_partially(e, i, 0.0);
            }
            self.bvh.refit(&mut self.workspace);
        }
        if n >= OPTIMIZE_FROM {
            self.bvh.optimize_incremental(&mut self.workspace);
        }
        self.kept.valid = false;
        let found = if fresh {
            self.all_candidates(cap)
        } else {
            self.requery_moved(cap)
        };
        debug_assert!(
            !found || (self.kept.leaves.iter().zip(&self.kept.enlarged)).all(|(l, e)| l.inside(e)),
            "every swept box lies in its enlarged box"
        );
        self.kept.valid = found;
        found
    }

    /// Every overlapping pair of enlarged boxes, by traversing the tree against itself.
    fn all_candidates(&mut self, cap: usize) -> bool {
        let candidates = &mut self.kept.candidates;
        candidates.clear();
        let mut fits = true;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| {
                if candidates.len() == cap {
                    fits = false;
                } else {
                    candidates.push((a.min(b), a.max(b)));
                }
            });
        fits
    }

    /// The candidates again for the moved leaves only: their old ones dropped, each
    /// one's enlarged box queried down the tree (a pair of two moved leaves found from
    /// the lower one).
    fn requery_moved(&mut self, cap: usize) -> bool {
        let Kept {
            candidates,
            moved,
            is_moved,
            enlarged,
            ..
        } = &mut self.kept;
        is_moved.clear();
        is_moved.resize(enlarged.len(), false);
        moved.iter().for_each(|&i| is_moved[i as usize] = true);
        candidates.retain(|&(a, b)| !is_moved[a as usize] && !is_moved[b as usize]);
        for &i in moved.iter() {
            let e = enlarged[i as usize];
            self.bvh.traverse(|node| {
                if !(node.mins().cmple(e.maxs).all() && e.mins.cmple(node.maxs()).all()) {
                    return TraversalAction::Prune;
                }
                if let Some(j) = node.leaf_data()
                    && j != i
                    && (!is_moved[j as usize] || j > i)
                {
                    candidates.push((i.min(j), i.max(j)));
                }
                TraversalAction::Continue
            });
            if candidates.len() > cap {
                return false;
            }
        }
        true
    }

    /// The pairs without candidates: the tree refitted to this step's boxes and
    /// traversed against itself (what a crowded step does).
    fn pairs_directly(&mut self, pairs: &mut Vec<(u32, u32)>, cap: usize) -> bool {
        self.kept.valid = false;
        let n = self.kept.leaves.len();
        let refit = n == self.leaves;
        let leaves = std::mem::take(&mut self.kept.leaves);
        self.place(n, |i| Aabb::new(leaves[i].lo, leaves[i].hi));
        if refit && n >= OPTIMIZE_FROM {
            self.bvh.optimize_incremental(&mut self.workspace);
        }
        let mut full = false;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| {
                if leaves[a as usize].pairs_with(&leaves[b as usize]) {
                    if pairs.len() == cap {
                        full = true;
                    } else {
                        pairs.push((a.min(b), a.max(b)));
                    }
                }
            });
        // Back to candidates once the pairs fall well under the cap.
        self.kept.crowded = full || pairs.len() > cap / 2;
        self.kept.leaves = leaves;
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
