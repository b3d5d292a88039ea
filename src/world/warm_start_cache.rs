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
}

impl WarmStartCache {
    /// Indexes this step's `manifolds` (their pairs named by `key`) for the next step,
    /// which hands the array over with [`Self::take_over`].
    pub(crate) fn index(&mut self, manifolds: &[Manifold], key: impl Fn(&Manifold) -> PairKey) {
        self.forget_index();
        self.keys.clear();
        self.keys.extend(manifolds.iter().map(key));
        self.indexed = true;
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

    /// Whether a lookup has made the index this step.
    #[cfg(test)]
    pub(crate) fn has_index(&self) -> bool {
        self.index.get().is_some()
    }

    /// Forgets everything (no contacts this step).
    pub(crate) fn clear(&mut self) {
        self.keys.clear();
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
