//! Sweep and prune along x: sort the boxes by their lower x bound, sweep once keeping the
//! boxes whose x interval is still open, and test the other two axes only against those.
//! O(n log n + k) for k overlaps along x.

use super::candidate;
use crate::world::ColliderEntry;

/// All overlapping candidate pairs (i < j), in lexicographic order, like the reference.
pub fn sweep_and_prune_pairs(colliders: &[ColliderEntry], pairs: &mut Vec<(u32, u32)>) {
    pairs.clear();
    let mut order: Vec<u32> = (0..colliders.len() as u32).collect();
    order.sort_unstable_by(|&a, &b| {
        colliders[a as usize]
            .aabb_min
            .x
            .total_cmp(&colliders[b as usize].aabb_min.x)
    });
    let mut active: Vec<u32> = Vec::new();
    for &i in &order {
        let ci = &colliders[i as usize];
        active.retain(|&j| colliders[j as usize].aabb_max.x >= ci.aabb_min.x);
        for &j in &active {
            if candidate(ci, &colliders[j as usize]) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
        active.push(i);
    }
    pairs.sort_unstable();
}
