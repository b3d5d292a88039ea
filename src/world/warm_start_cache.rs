//! Last step's manifolds, found by entity pair: where the narrow phase looks up the
//! impulses a contact starts from.

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
/// that scene's samples in the map's inserts, and more in `memmove`.
#[derive(Default, Debug)]
pub(crate) struct WarmStartCache {
    /// Last step's manifolds, in last step's order.
    manifolds: Vec<Manifold>,
    /// Each pair's place in `manifolds`.
    index: HashMap<PairKey, u32>,
    /// Whether `index` was made from the array the next [`Self::take_over`] takes.
    indexed: bool,
}

impl WarmStartCache {
    /// Indexes this step's `manifolds` (their pairs named by `key`) for the next step,
    /// which hands the array over with [`Self::take_over`].
    pub(crate) fn index(&mut self, manifolds: &[Manifold], key: impl Fn(&Manifold) -> PairKey) {
        self.index.clear();
        self.index.reserve(manifolds.len());
        for (i, m) in manifolds.iter().enumerate() {
            self.index.insert(key(m), i as u32);
        }
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

    /// The manifold a pair had last step. None between [`Self::index`] and
    /// [`Self::take_over`], while the index names places in an array the cache does not
    /// hold yet.
    #[inline]
    pub(crate) fn get(&self, key: &PairKey) -> Option<&Manifold> {
        if self.indexed {
            return None;
        }
        let i = *self.index.get(key)?;
        debug_assert!((i as usize) < self.manifolds.len(), "indexed, then cut");
        self.manifolds.get(i as usize)
    }

    /// Forgets everything (no contacts this step).
    pub(crate) fn clear(&mut self) {
        self.index.clear();
        self.manifolds.clear();
        self.indexed = false;
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
        assert!(cache.get(&(e1, e2, 7)).is_none(), "not taken over yet");
        cache.take_over(&mut manifolds);
        assert!(manifolds.is_empty());
        assert_eq!(cache.get(&(e1, e2, 7)).map(|m| m.sub), Some(7));
        assert!(cache.get(&(e2, e1, 7)).is_none());
        // A step that found manifolds but never indexed them: nothing stale is found.
        manifolds.push(manifold(3));
        cache.take_over(&mut manifolds);
        assert!(cache.get(&(e1, e2, 7)).is_none());
        assert!(cache.get(&(e1, e2, 0)).is_none());
    }
}
