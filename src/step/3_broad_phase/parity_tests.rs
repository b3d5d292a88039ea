//! Sweep-and-prune finds exactly the pairs the brute-force reference finds, on 50 random
//! scenes of 500 colliders (spheres, boxes, bounded and infinite planes, some static); and
//! the fixed set, after random inserts, moves and removals, finds exactly what testing
//! every entry finds.

use super::{SweepAndPrune, brute_force_pairs};
use crate::collider::Shape;
use crate::world::{AwakeTree, Leaf};
use crate::world::{ColliderEntry, FixedSet, STATIC};
use bevy::prelude::*;
use proptest::prelude::*;

fn scene(seed: u64) -> Vec<ColliderEntry> {
    let mut state = seed | 1;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f32 / (1u64 << 53) as f32
    };
    (0..500)
        .map(|i| {
            let shape = match (rnd() * 10.0) as u32 {
                0..=3 => Shape::Sphere {
                    radius: 0.1 + rnd(),
                },
                4..=8 => Shape::Cuboid {
                    half_extents: Vec3::new(0.1 + rnd(), 0.1 + rnd(), 0.1 + rnd()),
                },
                _ if rnd() < 0.1 => Shape::Plane { half_extents: None },
                _ => Shape::Plane {
                    half_extents: Some(Vec2::new(0.5 + 3.0 * rnd(), 0.5 + 3.0 * rnd())),
                },
            };
            let pos = Vec3::new(rnd(), rnd(), rnd()) * 30.0;
            let rot = Quat::from_euler(EulerRot::XYZ, rnd() * 6.3, rnd() * 6.3, rnd() * 6.3);
            let (lo, hi) = shape.aabb(pos, rot);
            let body = if matches!(shape, Shape::Plane { .. }) || rnd() < 0.2 {
                STATIC
            } else {
                i
            };
            ColliderEntry {
                aabb_min: lo - Vec3::splat(0.02),
                aabb_max: hi + Vec3::splat(0.02),
                ..ColliderEntry::new(Entity::PLACEHOLDER, i as u64, body, shape, pos, rot)
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(50))]
    #[test]
    fn sweep_and_prune_matches_brute_force(seed in any::<u64>()) {
        let colliders = scene(seed);
        let (mut reference, mut fast) = (Vec::new(), Vec::new());
        brute_force_pairs(&colliders, &mut reference);
        // A fresh sweep, then the same buffers again after the boxes moved: the kept order
        // is re-sorted by insertion and must still find exactly the reference pairs.
        let mut sap = SweepAndPrune::default();
        sap.pairs(&colliders, &mut fast, usize::MAX);
        prop_assert_eq!(&reference, &fast);
        let mut moved = colliders.clone();
        for (k, c) in moved.iter_mut().enumerate() {
            let shift = bevy::prelude::Vec3::X * ((k % 7) as f32 - 3.0) * 0.3;
            c.aabb_min += shift;
            c.aabb_max += shift;
        }
        brute_force_pairs(&moved, &mut reference);
        sap.pairs(&moved, &mut fast, usize::MAX);
        prop_assert!(!reference.is_empty());
        prop_assert_eq!(reference, fast);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(50))]
    #[test]
    fn fixed_set_matches_brute_force_after_inserts_moves_and_removals(seed in any::<u64>()) {
        let colliders = scene(seed);
        let entity = |k: usize| Entity::from_raw_u32(k as u32 + 1).unwrap();
        let mut set = FixedSet::default();
        // Insert all 500, then move every third (re-insert at a new place) and remove
        // every fifth: swap-removal must keep every other entry findable.
        for (k, c) in colliders.iter().enumerate() {
            set.insert(ColliderEntry { entity: entity(k), owner: entity(k), ..c.clone() });
        }
        for (k, c) in colliders.iter().enumerate().step_by(3) {
            let pos = c.pos + Vec3::new(5.0, -3.0, 2.0);
            set.insert(ColliderEntry { entity: entity(k), owner: entity(k), pos, ..c.clone() });
        }
        for k in (0..colliders.len()).step_by(5) {
            prop_assert!(set.remove(entity(k)));
        }
        prop_assert_eq!(set.len(), 400);
        for k in 0..colliders.len() {
            prop_assert_eq!(set.contains(entity(k)), k % 5 != 0);
        }
        set.update_search();
        for q in colliders.iter().take(100) {
            let (lo, hi) = (q.aabb_min, q.aabb_max + Vec3::splat(0.5));
            let mut fast = Vec::new();
            set.overlapping(lo, hi, 0.02, |i| fast.push(i));
            fast.sort_unstable();
            prop_assert_eq!(fast, set.overlapping_brute_force(lo, hi, 0.02));
        }
    }
}

/// The tree's pairs of `colliders` this step, sorted.
fn tree_pairs(
    tree: &mut AwakeTree,
    colliders: &[ColliderEntry],
    cap: usize,
) -> (Vec<(u32, u32)>, bool) {
    let leaf = |i: usize| Leaf {
        lo: colliders[i].aabb_min,
        hi: colliders[i].aabb_max,
        body: colliders[i].body,
    };
    let mut pairs = Vec::new();
    let full = tree.pairs(colliders.len(), leaf, &mut pairs, cap);
    pairs.sort_unstable();
    (pairs, full)
}

fn shift(c: &mut ColliderEntry, by: Vec3) {
    c.aabb_min += by;
    c.aabb_max += by;
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(30))]
    /// The tree, over successive steps, finds exactly the reference pairs every time:
    /// boxes that barely move (they stay in their enlarged boxes: the kept candidates),
    /// a few that move far (their candidates found again one by one), all moving far
    /// (the tree traversed again), fewer colliders (built afresh), the same number of
    /// colliders in another order and with some sharing a body (leaf i is another
    /// collider), a spatial query's refit in between, and a pair cap hit then lifted.
    #[test]
    fn tree_matches_brute_force_over_steps(seed in any::<u64>()) {
        let mut colliders = scene(seed);
        let mut tree = AwakeTree::default();
        let mut reference = Vec::new();
        for step in 0..10usize {
            let n = colliders.len();
            for (k, c) in colliders.iter_mut().enumerate() {
                let jitter = Vec3::new(((k + step) % 5) as f32 - 2.0, 0.1, -0.2) * 1e-3;
                let far = match step {
                    2 | 3 => k % 37 == step,
                    4 => true,
                    _ => false,
                };
                let by = if far { Vec3::new(((k + step) % 5) as f32 - 2.0, 0.1, -0.2) * 0.6 } else { jitter };
                shift(c, by);
            }
            match step {
                5 => colliders.truncate(350),
                6 => {
                    colliders.reverse();
                    for k in (0..colliders.len()).step_by(7) {
                        if k + 1 < colliders.len() && colliders[k].body != STATIC {
                            colliders[k + 1].body = colliders[k].body;
                        }
                    }
                }
                8 => tree.fit(n, |i| (colliders[i].aabb_min, colliders[i].aabb_max + Vec3::ONE)),
                _ => {}
            }
            brute_force_pairs(&colliders, &mut reference);
            prop_assert!(reference.len() > 10);
            if step == 7 {
                let (capped, full) = tree_pairs(&mut tree, &colliders, 10);
                prop_assert!(full && capped.len() == 10, "step {}: the cap", step);
                prop_assert!(capped.iter().all(|p| reference.contains(p)));
            }
            let (fast, full) = tree_pairs(&mut tree, &colliders, usize::MAX);
            prop_assert!(!full);
            prop_assert_eq!(&reference, &fast, "step {}", step);
        }
    }
}
