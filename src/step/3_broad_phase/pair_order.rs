//! The canonical order of a step's candidate pairs: by their colliders' spawn-order keys,
//! pairs with a fixed collider first, each pair with the lower key first (see
//! [`canonical_order`]).
//!
//! Sorting the pairs by a closure that looks up both colliders' keys read two 300-byte
//! [`ColliderEntry`]s at random per comparison: on the 4,096-ball pit (about 20,000
//! pairs) that sort was a fifth of the whole step. Here each collider's key is read once,
//! the colliders are ranked by it, and each pair becomes one `u64` (fixed-first bit, lower
//! rank, higher rank) that sorts as plain integers and decodes back through the ranks.
//! The comparison sort it replaced is kept as the reference it is tested against.

use crate::world::{ColliderEntry, STATIC};

/// Buffers kept between steps.
#[derive(Default)]
pub struct PairOrderScratch {
    /// (key, collider index), sorted: the colliders in key order.
    by_key: Vec<(u64, u32)>,
    /// Per collider: its place in key order, with [`FIXED_BIT`] set for a fixed collider.
    rank: Vec<u32>,
    /// Per pair: [`pack`]ed.
    packed: Vec<u64>,
}

/// Marks a fixed (static or asleep) collider in [`PairOrderScratch::rank`].
const FIXED_BIT: u32 = 1 << 31;

/// Puts the pairs in the order of their colliders' spawn order keys (pairs with a fixed
/// collider before the others), each pair with the lower key first, so the narrow phase
/// and the solver visit the same contacts in the same order whatever the ECS's table
/// order, the entity ids and the fixed set's internal order are (they change as
/// unrelated bodies come and go). Pairs with something fixed (static or asleep) go first,
/// whatever was spawned first: each Gauss–Seidel pass then works up from the ground,
/// which stacks need (the solver runs them once more at the end of the pass, see
/// `solve_contacts`). Two colliders with the same key (none today: every collider gets
/// its own `SpawnOrder`) are ranked by their index.
pub fn canonical_order(
    colliders: &[ColliderEntry],
    pairs: &mut [(u32, u32)],
    scratch: &mut PairOrderScratch,
) {
    assert!(
        colliders.len() < FIXED_BIT as usize,
        "more colliders than a rank holds"
    );
    let PairOrderScratch {
        by_key,
        rank,
        packed,
    } = scratch;
    by_key.clear();
    by_key.extend(colliders.iter().enumerate().map(|(i, c)| (c.key, i as u32)));
    // Usually sorted already, or nearly (the ECS's order follows spawning): linear then.
    by_key.sort_unstable();
    rank.clear();
    rank.resize(colliders.len(), 0);
    for (r, &(_, i)) in by_key.iter().enumerate() {
        let fixed = colliders[i as usize].body == STATIC;
        rank[i as usize] = r as u32 | if fixed { FIXED_BIT } else { 0 };
    }
    packed.clear();
    packed.extend(
        pairs
            .iter()
            .map(|&(a, b)| pack(rank[a as usize], rank[b as usize])),
    );
    packed.sort_unstable();
    for (p, &k) in pairs.iter_mut().zip(packed.iter()) {
        let (lo, hi) = unpack(k);
        *p = (by_key[lo as usize].1, by_key[hi as usize].1);
    }
}

/// One pair as a sortable integer: bit 63 set unless a side is fixed, then the lower
/// rank (bits 32–62), then the higher (bits 0–30).
#[inline]
fn pack(a: u32, b: u32) -> u64 {
    let moving = (a | b) & FIXED_BIT == 0;
    let (a, b) = (a & !FIXED_BIT, b & !FIXED_BIT);
    debug_assert_ne!(a, b, "a pair of one collider");
    let (lo, hi) = (a.min(b), a.max(b));
    (u64::from(moving) << 63) | (u64::from(lo) << 32) | u64::from(hi)
}

/// The lower and higher rank of a [`pack`]ed pair.
#[inline]
fn unpack(k: u64) -> (u32, u32) {
    (((k >> 32) as u32) & !FIXED_BIT, k as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;
    use crate::rng::Rnd;
    use bevy::prelude::*;

    /// The comparison sort this replaced: the reference.
    fn reference_order(colliders: &[ColliderEntry], pairs: &mut [(u32, u32)]) {
        let key = |i: u32| colliders[i as usize].key;
        for p in pairs.iter_mut() {
            if key(p.0) > key(p.1) {
                *p = (p.1, p.0);
            }
        }
        let fixed = |i: u32| colliders[i as usize].body == STATIC;
        pairs.sort_unstable_by_key(|&(a, b)| (!(fixed(a) || fixed(b)), key(a), key(b)));
    }

    /// A whole number in `0..n`.
    fn below(rnd: &mut Rnd, n: u32) -> u32 {
        ((rnd.unit() * n as f32) as u32).min(n - 1)
    }

    /// `n` colliders with distinct random keys, about a fifth of them fixed, and
    /// `pairs` random pairs of distinct colliders (no pair twice), in random order.
    fn random_input(rnd: &mut Rnd, n: u32, pairs: usize) -> (Vec<ColliderEntry>, Vec<(u32, u32)>) {
        let mut keys: Vec<u64> = (0..n as u64).map(|k| k * 7 + 3).collect();
        // A shuffle, with a few keys as large as an entity-bits stand-in.
        for i in (1..keys.len()).rev() {
            keys.swap(i, below(rnd, i as u32 + 1) as usize);
        }
        for k in keys.iter_mut().take(3) {
            *k = u64::MAX - *k;
        }
        let shape = Shape::Sphere { radius: 0.5 };
        let colliders = (0..n)
            .map(|i| {
                let body = if below(rnd, 5) == 0 { STATIC } else { i };
                let key = keys[i as usize];
                ColliderEntry::new(
                    Entity::PLACEHOLDER,
                    key,
                    body,
                    shape.clone(),
                    Vec3::ZERO,
                    Quat::IDENTITY,
                )
            })
            .collect();
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        while out.len() < pairs {
            let (a, b) = (below(rnd, n), below(rnd, n));
            if a != b && seen.insert((a.min(b), a.max(b))) {
                out.push((a, b));
            }
        }
        (colliders, out)
    }

    #[test]
    fn ranks_order_the_pairs_as_the_key_comparisons_do() {
        let mut rnd = Rnd(0x5eed);
        let mut scratch = PairOrderScratch::default();
        for (n, count) in [(2, 1), (3, 3), (50, 200), (700, 5_000), (3_000, 20_000)] {
            let (colliders, pairs) = random_input(&mut rnd, n, count);
            let (mut expected, mut fast) = (pairs.clone(), pairs);
            reference_order(&colliders, &mut expected);
            canonical_order(&colliders, &mut fast, &mut scratch);
            assert_eq!(fast, expected, "{n} colliders, {count} pairs");
        }
    }

    #[test]
    fn the_order_does_not_depend_on_the_input_order() {
        let mut rnd = Rnd(7);
        let mut scratch = PairOrderScratch::default();
        let (colliders, mut pairs) = random_input(&mut rnd, 400, 3_000);
        let mut first = pairs.clone();
        canonical_order(&colliders, &mut first, &mut scratch);
        pairs.reverse();
        for p in pairs.iter_mut().step_by(3) {
            *p = (p.1, p.0);
        }
        canonical_order(&colliders, &mut pairs, &mut scratch);
        assert_eq!(pairs, first);
    }
}
