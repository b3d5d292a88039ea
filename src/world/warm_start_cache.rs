//! Last step's manifolds, found by entity pair: where the narrow phase looks up the
//! impulses a contact starts from.

use std::sync::{Mutex, OnceLock};

use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use super::Manifold;

/// Which entities a manifold joins, and which part of the pair it is ([`Manifold::sub`]).
pub(crate) type PairKey = (Entity, Entity, u32);

/// Last step's manifolds, kept where they were (the array is handed over whole at the
/// start of a step, not copied), and an index from each pair to its place.
///
/// The index holds a 4-byte place, not the 268-byte manifold: copying each manifold into
/// a map every step (15,000 manifolds, 4 MB a step on the large pyramid) held 2.4 % of
/// that scene's samples in the map's inserts, and more in `memmove`. And it is made only
/// when a lookup first misses the place it was looked for at (see [`Self::find`]): a
/// step whose pairs are last step's, in the same order, makes none (the inserts were
/// still 2 % of the 100 pyramids' samples).
#[derive(Default, Debug)]
pub(crate) struct WarmStartCache {
    /// Last step's manifolds, in last step's order.
    manifolds: Vec<Manifold>,
    /// Each pair's place in `manifolds`, made from `keys` when first needed.
    index: OnceLock<HashMap<PairKey, u32>>,
    /// The last index made, emptied, kept for its capacity: the next one is made in it,
    /// so a scene whose pairs change every step does not allocate a map every step.
    spare: Mutex<HashMap<PairKey, u32>>,
    /// Each manifold's pair, in `manifolds`' order (see [`Self::find`]).
    keys: Vec<PairKey>,
    /// Whether `index` was made from the array the next [`Self::take_over`] takes.
    indexed: bool,
    /// Each manifold's place in its step's candidate pairs ([`Manifold::pair`]), in
    /// `manifolds`' order.
    pair_of: Vec<u32>,
    /// The candidate pairs of the step that made `manifolds`, and each collider's entity
    /// then (see [`Self::remember_pairs`]).
    last_pairs: Vec<(u32, u32)>,
    last_entities: Vec<Entity>,
    /// Whether `last_pairs` and `last_entities` are those of `manifolds`' step.
    pairs_known: bool,
    /// This step's pairs are `last_pairs`, between the same entities (see
    /// [`Self::find_at`]).
    repeats: bool,
}

impl WarmStartCache {
    /// Indexes this step's `manifolds` (their pairs named by `key`) for the next step,
    /// which hands the array over with [`Self::take_over`].
    pub(crate) fn index(&mut self, manifolds: &[Manifold], key: impl Fn(&Manifold) -> PairKey) {
        self.forget_index();
        self.keys.clear();
        self.keys.extend(manifolds.iter().map(key));
        self.pair_of.clear();
        self.pair_of.extend(manifolds.iter().map(|m| m.pair));
        self.pairs_known = false;
        self.repeats = false;
        self.indexed = true;
    }

    /// Records the candidate pairs (colliders' places) of the step that [`Self::index`]
    /// just indexed, and its colliders' entities, so that the next step can tell a pair
    /// that had no manifold without the index (see [`Self::find_at`]).
    pub(crate) fn remember_pairs(
        &mut self,
        pairs: &[(u32, u32)],
        entities: impl Iterator<Item = Entity>,
    ) {
        self.last_pairs.clear();
        self.last_pairs.extend_from_slice(pairs);
        self.last_entities.clear();
        self.last_entities.extend(entities);
        self.pairs_known = true;
    }

    /// Whether this step's candidate pairs are those of the step the cache holds,
    /// between the same entities; [`Self::find_at`] relies on it. Called once a step,
    /// before the lookups.
    pub(crate) fn match_pairs(
        &mut self,
        pairs: &[(u32, u32)],
        mut entities: impl ExactSizeIterator<Item = Entity>,
    ) {
        self.repeats = self.pairs_known
            && !self.indexed
            && self.last_pairs == pairs
            && self.last_entities.len() == entities.len()
            && self
                .last_entities
                .iter()
                .all(|&e| entities.next() == Some(e));
    }

    /// [`Self::find`] for the manifold of candidate pair `pair` (its place in this
    /// step's pairs). When the pairs repeat last step's ([`Self::match_pairs`]), a pair
    /// whose place has no manifold had none last step, and is told so without the
    /// index: a scene's pairs include some whose boxes are within the margin's boxes but
    /// not within reach (two cubes of a pyramid's layer corner to corner), and looking
    /// one up missed and made the index every step (1.8 % of the 385-cube pyramid's
    /// samples).
    #[inline]
    pub(crate) fn find_at(&self, key: &PairKey, pair: u32, next: &mut usize) -> Option<&Manifold> {
        if self.repeats {
            // Manifolds of pairs this run passed by without a lookup (asleep, filtered).
            while self.pair_of.get(*next).is_some_and(|&q| q < pair) {
                *next += 1;
            }
            if self.pair_of.get(*next) != Some(&pair) {
                return None;
            }
        }
        self.find(key, next)
    }

    /// Takes last step's indexed manifolds and leaves `manifolds` empty (its capacity
    /// that of the array before, so no step allocates). Manifolds no one indexed since
    /// the last take-over (a step whose solve did not run) leave the cache empty.
    pub(crate) fn take_over(&mut self, manifolds: &mut Vec<Manifold>) {
        std::mem::swap(&mut self.manifolds, manifolds);
        manifolds.clear();
        if !std::mem::take(&mut self.indexed) {
            self.clear();
        }
    }

    /// The manifold a pair had last step, looked for first at place `next`, and `next`
    /// moved after the place found. None between [`Self::index`] and
    /// [`Self::take_over`], while the index names places in an array the cache does not
    /// hold yet. The narrow phase visits pairs in the same order every step and last step's
    /// manifolds are in that order, so a pair's manifold is nearly always the one after
    /// the last found: one sequential read instead of a hash-map probe (whose cache miss
    /// on 15,000 manifolds was 2 % of the large pyramid's samples).
    #[inline]
    pub(crate) fn find(&self, key: &PairKey, next: &mut usize) -> Option<&Manifold> {
        if self.indexed {
            return None;
        }
        let i = if self.keys.get(*next) == Some(key) {
            *next
        } else {
            let index = self.index.get_or_init(|| {
                // A poisoned lock (a panic elsewhere while it was held) only costs the
                // spare capacity.
                let mut index = self
                    .spare
                    .lock()
                    .map_or_else(|_| HashMap::default(), |mut s| std::mem::take(&mut *s));
                index.reserve(self.keys.len());
                for (i, &k) in self.keys.iter().enumerate() {
                    index.insert(k, i as u32);
                }
                index
            });
            *index.get(key)? as usize
        };
        *next = i + 1;
        debug_assert!(i < self.manifolds.len(), "indexed, then cut");
        self.manifolds.get(i)
    }

    /// How many manifolds last step left.
    pub(crate) fn len(&self) -> usize {
        self.manifolds.len()
    }

    /// The colliders of last step's manifold `i` (its pair, if no collider has moved in
    /// the colliders' array since).
    pub(crate) fn pair_at(&self, i: usize) -> Option<(u32, u32)> {
        self.manifolds.get(i).map(|m| (m.a, m.b))
    }

    /// Whether this step's pairs repeat last step's ([`Self::match_pairs`]).
    #[cfg(test)]
    pub(crate) fn repeats(&self) -> bool {
        self.repeats
    }

    /// Whether a lookup has made the index this step.
    #[cfg(test)]
    pub(crate) fn has_index(&self) -> bool {
        self.index.get().is_some()
    }

    /// Forgets everything (no contacts this step).
    pub(crate) fn clear(&mut self) {
        self.keys.clear();
        self.pair_of.clear();
        self.pairs_known = false;
        self.repeats = false;
        self.forget_index();
        self.manifolds.clear();
        self.indexed = false;
    }

    /// Drops the index, keeping its map (emptied) as the spare.
    pub(crate) fn forget_index(&mut self) {
        if let Some(mut old) = self.index.take() {
            old.clear();
            if let Ok(spare) = self.spare.get_mut() {
                *spare = old;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifold(sub: u32) -> Manifold {
        Manifold { sub, ..default() }
    }

    #[test]
    fn finds_last_steps_manifold_and_forgets_an_unindexed_step() {
        let (e1, e2) = (
            Entity::from_raw_u32(1).unwrap(),
            Entity::from_raw_u32(2).unwrap(),
        );
        let key = |m: &Manifold| (e1, e2, m.sub);
        let mut cache = WarmStartCache::default();
        let mut manifolds = vec![manifold(0), manifold(7)];
        cache.index(&manifolds, key);
        assert!(
            cache.find(&(e1, e2, 7), &mut 0).is_none(),
            "not taken over yet"
        );
        cache.take_over(&mut manifolds);
        assert!(manifolds.is_empty());
        assert_eq!(cache.find(&(e1, e2, 7), &mut 0).map(|m| m.sub), Some(7));
        assert!(cache.find(&(e2, e1, 7), &mut 0).is_none());
        // Looked for where it is, or anywhere else: found, and the next place is after it.
        for hint in [0, 1, 5, usize::MAX] {
            let mut next = hint;
            assert_eq!(cache.find(&(e1, e2, 0), &mut next).map(|m| m.sub), Some(0));
            assert_eq!(next, 1);
            assert_eq!(cache.find(&(e1, e2, 7), &mut next).map(|m| m.sub), Some(7));
            assert_eq!(next, 2);
        }
        // A step that found manifolds but never indexed them: nothing stale is found.
        manifolds.push(manifold(3));
        cache.take_over(&mut manifolds);
        assert!(cache.find(&(e1, e2, 7), &mut 0).is_none());
        assert!(cache.find(&(e1, e2, 0), &mut 0).is_none());
    }

    #[test]
    fn repeated_pairs_tell_a_pair_without_a_manifold_without_the_index() {
        let entity = |i: u32| Entity::from_raw_u32(i).unwrap();
        // Ten pairs of colliders 0-10; pairs 3 and 7 had no manifold last step.
        let pairs: Vec<(u32, u32)> = (0..10).map(|i| (i, i + 1)).collect();
        let entities = || (0..11).map(entity);
        let key = |m: &Manifold| (entity(m.a), entity(m.b), m.sub);
        let touching = |k: &u32| *k != 3 && *k != 7;
        // The cache as last step's store leaves it: its manifolds indexed, its pairs
        // remembered, taken over.
        let last_step = || {
            let mut manifolds: Vec<Manifold> = (0..10)
                .filter(touching)
                .map(|k| Manifold {
                    a: k,
                    b: k + 1,
                    pair: k,
                    ..default()
                })
                .collect();
            let mut cache = WarmStartCache::default();
            cache.index(&manifolds, key);
            cache.remember_pairs(&pairs, entities());
            cache.take_over(&mut manifolds);
            cache
        };
        let look_up_all = |cache: &WarmStartCache| {
            let mut next = 0;
            (0..10u32)
                .map(|k| {
                    let found = cache.find_at(&(entity(k), entity(k + 1), 0), k, &mut next);
                    found.map(|m| (m.a, m.pair))
                })
                .collect::<Vec<_>>()
        };
        let expected: Vec<_> = (0..10).map(|k| touching(&k).then_some((k, k))).collect();
        let mut cache = last_step();
        cache.match_pairs(&pairs, entities());
        assert!(cache.repeats());
        assert_eq!(look_up_all(&cache), expected);
        assert!(
            !cache.has_index(),
            "a pair without a manifold made the index"
        );
        // The same lookups when the pairs differ (one fewer pair, or a collider that is
        // another entity now): the index answers the same.
        for (other_pairs, other_entity) in [(pairs[..9].to_vec(), 11), (pairs.clone(), 5)] {
            let mut again = last_step();
            let now = (0..11).map(|i| entity(if i == other_entity { 99 } else { i }));
            again.match_pairs(&other_pairs, now);
            assert!(!again.repeats());
            assert_eq!(look_up_all(&again), expected);
            assert!(again.has_index());
        }
    }

    #[test]
    fn the_index_is_made_only_on_a_miss_and_its_map_is_reused() {
        let (e1, e2) = (
            Entity::from_raw_u32(1).unwrap(),
            Entity::from_raw_u32(2).unwrap(),
        );
        let key = |m: &Manifold| (e1, e2, m.sub);
        let mut cache = WarmStartCache::default();
        let mut manifolds: Vec<Manifold> = (0..64).map(manifold).collect();
        cache.index(&manifolds, key);
        cache.take_over(&mut manifolds);
        // Every pair where it was: no map.
        let mut next = 0;
        for sub in 0..64 {
            assert_eq!(
                cache.find(&(e1, e2, sub), &mut next).map(|m| m.sub),
                Some(sub)
            );
        }
        assert!(cache.index.get().is_none(), "made without a miss");
        // A pair out of place: the map is made, and finds it.
        assert_eq!(cache.find(&(e1, e2, 40), &mut 3).map(|m| m.sub), Some(40));
        let made = cache.index.get().expect("made on the miss").capacity();
        assert!(made >= 64);
        // The next step's index starts from that map, emptied.
        manifolds.extend((0..64).map(manifold));
        cache.index(&manifolds, key);
        let spare = cache.spare.lock().unwrap();
        assert!(spare.is_empty() && spare.capacity() == made);
    }
}
