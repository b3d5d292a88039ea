//! Sweep and prune along x: keep the boxes sorted by their lower x bound, sweep once
//! keeping the boxes whose x interval is still open, and test the other two axes only
//! against those. The order is kept between steps and re-sorted by insertion, which is
//! nearly linear because bodies move little per step: O(n + k) for k overlaps along x.

use super::candidate;
use crate::world::ColliderEntry;

/// Buffers kept between steps: the sorted order and the open intervals.
#[derive(Default, Debug, Clone)]
pub struct SweepAndPrune {
    order: Vec<u32>,
    active: Vec<u32>,
}

impl SweepAndPrune {
    /// All overlapping candidate pairs (i < j), in lexicographic order, like the reference,
    /// up to `cap` of them (the first `cap` met in the sweep). Returns whether the cap cut
    /// the list short.
    pub fn pairs(
        &mut self,
        colliders: &[ColliderEntry],
        pairs: &mut Vec<(u32, u32)>,
        cap: usize,
    ) -> bool {
        pairs.clear();
        let key = |i: u32| colliders[i as usize].aabb_min.x;
        if self.order.len() != colliders.len() {
            self.order.clear();
            self.order.extend(0..colliders.len() as u32);
        }
        // Insertion sort: fast on last step's nearly sorted order.
        for k in 1..self.order.len() {
            let item = self.order[k];
            let mut j = k;
            while j > 0 && key(self.order[j - 1]).total_cmp(&key(item)).is_gt() {
                self.order[j] = self.order[j - 1];
                j -= 1;
            }
            self.order[j] = item;
        }
        self.active.clear();
        let mut full = false;
        'sweep: for &i in &self.order {
            let ci = &colliders[i as usize];
            self.active
                .retain(|&j| colliders[j as usize].aabb_max.x >= ci.aabb_min.x);
            for &j in &self.active {
                if candidate(ci, &colliders[j as usize]) {
                    if pairs.len() == cap {
                        full = true;
                        break 'sweep;
                    }
                    pairs.push((i.min(j), i.max(j)));
                }
            }
            self.active.push(i);
        }
        pairs.sort_unstable();
        full
    }
}
