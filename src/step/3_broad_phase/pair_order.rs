//! The canonical order of a step's candidate pairs: by their colliders' spawn-order keys,
//! pairs with a fixed collider first, each pair with the lower key first (see
//! [`canonical_order`]).
//!
//! Sorting the pairs by a closure that looks up both colliders' keys read two 300-byte
//! [`ColliderEntry`]s at random per comparison: on the 4,096-ball pit (about 20,000
//! pairs) that sort was a fifth of the whole step. Here each collider's key is read once,
//! the colliders are ranked by it, and each pair becomes one `u64` (fixed-first bit, lower
//! rank, higher rank), only as wide as the ranks need, that a radix sort orders in a few
//! passes and that decodes back through the ranks. The comparison sort it replaced is
//! kept as the reference it is tested against.

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
    /// The radix sort's second buffer.
    spare: Vec<u64>,
    /// Last step's call, to answer a repeat of it without sorting.
    last: LastOrder,
}

/// One call of [`canonical_order`]: what the order depends on (each collider's key and
/// whether it is fixed, and the pairs as they came) and the order it gave. A settled
/// scene's tree yields the same pairs in the same order step after step (the 4,096-ball
/// pit from about step 60 on), and sorting them again was 4.5 % of its step.
#[derive(Default)]
struct LastOrder {
    colliders: Vec<(u64, bool)>,
    input: Vec<(u32, u32)>,
    output: Vec<(u32, u32)>,
}

impl LastOrder {
    /// Whether this call repeats the last one.
    fn repeats(&self, colliders: &[ColliderEntry], pairs: &[(u32, u32)]) -> bool {
        self.input == pairs
            && self.colliders.len() == colliders.len()
            && (self.colliders.iter().zip(colliders)).all(|(&k, c)| k == (c.key, c.body == STATIC))
    }
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
/// `solve_contacts`). Two colliders with the same key (none while every collider gets
/// its own `SpawnOrder`) are ranked by their index.
pub fn canonical_order(
    colliders: &[ColliderEntry],
    pairs: &mut [(u32, u32)],
    scratch: &mut PairOrderScratch,
) {
    // (2³¹ colliders would take 600 GB.)
    debug_assert!(
        colliders.len() < FIXED_BIT as usize,
        "more colliders than a rank holds"
    );
    let PairOrderScratch {
        by_key,
        rank,
        packed,
        spare,
        last,
    } = scratch;
    if last.repeats(colliders, pairs) {
        pairs.copy_from_slice(&last.output);
        return;
    }
    last.input.clear();
    last.input.extend_from_slice(pairs);
    last.colliders.clear();
    (last.colliders).extend(colliders.iter().map(|c| (c.key, c.body == STATIC)));
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
    // A rank takes `bits` bits: a key takes 2·bits + 1.
    let bits = u32::BITS - (colliders.len() as u32).leading_zeros();
    packed.clear();
    packed.extend(
        pairs
            .iter()
            .map(|&(a, b)| pack(rank[a as usize], rank[b as usize], bits)),
    );
    // Keys are distinct (one a pair): any sort gives the same order.
    if packed.len() < RADIX_FROM {
        packed.sort_unstable();
    } else {
        radix_sort(packed, spare, 2 * bits + 1);
    }
    let mask = (1u64 << bits) - 1;
    for (p, &k) in pairs.iter_mut().zip(packed.iter()) {
        let (lo, hi) = ((k >> bits) & mask, k & mask);
        *p = (by_key[lo as usize].1, by_key[hi as usize].1);
    }
    last.output.clear();
    last.output.extend_from_slice(pairs);
}

/// One pair as a sortable integer of 2·`bits` + 1 bits: the top one set unless a side is
/// fixed, then the lower rank, then the higher (each of `bits` bits).
#[inline]
fn pack(a: u32, b: u32, bits: u32) -> u64 {
    let moving = (a | b) & FIXED_BIT == 0;
    let (a, b) = (a & !FIXED_BIT, b & !FIXED_BIT);
    debug_assert_ne!(a, b, "a pair of one collider");
    debug_assert!(a.max(b) < 1 << bits, "a rank wider than its field");
    let (lo, hi) = (a.min(b), a.max(b));
    (u64::from(moving) << (2 * bits)) | (u64::from(lo) << bits) | u64::from(hi)
}

/// The fewest pairs the radix sort is used for. A pass clears, scans and sums its 2,048
/// counters whatever the count of keys: on the 10-box tower (9 pairs) that was 4 % of the
/// step, where a comparison sort of nine keys costs next to nothing.
const RADIX_FROM: usize = 256;

/// Bits a radix sort pass sorts by: 2,048 counters, which fit the first-level cache.
const DIGIT: u32 = 11;

/// Sorts `keys` whose set bits are all below bit `bits`: a least-significant-digit radix
/// sort, [`DIGIT`] bits a pass (a pass whose digit is the same in every key is skipped),
/// with `spare` as the second buffer. The ball pit's ~20,000 keys of 27 bits take three
/// passes over the keys instead of the ~15 comparisons a key of a comparison sort.
fn radix_sort(keys: &mut Vec<u64>, spare: &mut Vec<u64>, bits: u32) {
    const BUCKETS: usize = 1 << DIGIT;
    debug_assert!(keys.iter().all(|&k| bits >= 64 || k >> bits == 0));
    spare.clear();
    spare.resize(keys.len(), 0);
    let mut count = [0u32; BUCKETS];
    let mut shift = 0;
    while shift < bits {
        let digit = |k: u64| ((k >> shift) as usize) & (BUCKETS - 1);
        count.fill(0);
        for &k in keys.iter() {
            count[digit(k)] += 1;
        }
        if count.iter().any(|&c| c as usize == keys.len()) {
            shift += DIGIT;
            continue;
        }
        let mut start = 0;
        for c in count.iter_mut() {
            (*c, start) = (start, start + *c);
        }
        for &k in keys.iter() {
            let d = digit(k);
            spare[count[d] as usize] = k;
            count[d] += 1;
        }
        std::mem::swap(keys, spare);
        shift += DIGIT;
    }
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
    fn the_radix_sort_sorts_as_the_comparison_sort_does() {
        // Splitmix64: every bit of the keys random.
        let mut state = 11u64;
        let mut next = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let z = (state ^ (state >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        let mut spare = Vec::new();
        for (n, bits) in [
            (0, 5),
            (1, 7),
            (1_000, 3),
            (5_000, 21),
            (20_000, 27),
            (3_000, 63),
        ] {
            let mut keys: Vec<u64> = (0..n).map(|_| next() & ((1u64 << bits) - 1)).collect();
            let mut expected = keys.clone();
            expected.sort_unstable();
            radix_sort(&mut keys, &mut spare, bits);
            assert_eq!(keys, expected, "{n} keys of {bits} bits");
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

    #[test]
    fn a_repeated_call_gives_the_last_order_and_a_changed_collider_a_new_one() {
        let mut rnd = Rnd(11);
        let mut scratch = PairOrderScratch::default();
        let (mut colliders, pairs) = random_input(&mut rnd, 300, 2_000);
        for round in 0..4 {
            // Round 1 repeats round 0; then a key changes, then whether one is fixed.
            if round == 2 {
                colliders[5].key = u64::MAX - 1;
            }
            if round == 3 {
                let c = &mut colliders[7];
                c.body = if c.body == STATIC { 0 } else { STATIC };
            }
            let (mut expected, mut fast) = (pairs.clone(), pairs.clone());
            reference_order(&colliders, &mut expected);
            canonical_order(&colliders, &mut fast, &mut scratch);
            assert_eq!(fast, expected, "round {round}");
        }
    }
}
