//! The reference broad phase: test every pair. O(n²); kept to check the fast one.

use super::candidate;
use crate::world::ColliderEntry;

/// All overlapping candidate pairs (i < j), in lexicographic order.
pub fn brute_force_pairs(colliders: &[ColliderEntry], pairs: &mut Vec<(u32, u32)>) {
    pairs.clear();
    for i in 0..colliders.len() {
        for j in i + 1..colliders.len() {
            if candidate(&colliders[i], &colliders[j]) {
                pairs.push((i as u32, j as u32));
            }
        }
    }
}
