//! The fixed set: static colliders and sleeping bodies, kept between steps.
//!
//! Nothing in it moves, so its bounds are computed once, when an entry is inserted, and its
//! search order only when the set changes. Each step, the broad phase asks it for the
//! entries that overlap an awake collider's box; entries near nothing awake cost nothing.
//!
//! Search: a [`BoundsIndex`] over the entries' boxes (sorted by lower x bound, very wide
//! entries apart), rebuilt only when the set changed.

use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use super::bounds_index::BoundsIndex;
use crate::world::{ColliderEntry, STATIC};

#[derive(Default, Debug, Clone)]
pub(crate) struct FixedSet {
    entries: Vec<ColliderEntry>,
    /// Where each entity's entry is in `entries`.
    slots: HashMap<Entity, u32>,
    /// The search order over the entries' boxes.
    index: BoundsIndex,
    /// Entries changed since `index` was built.
    dirty: bool,
    /// The parts of sleeping compound bodies, by body: they leave with it.
    parts: HashMap<Entity, Vec<Entity>>,
}

impl FixedSet {
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn entries(&self) -> &[ColliderEntry] {
        &self.entries
    }

    pub fn get(&self, entity: Entity) -> Option<&ColliderEntry> {
        self.slots.get(&entity).map(|&i| &self.entries[i as usize])
    }

    pub fn contains(&self, entity: Entity) -> bool {
        self.slots.contains_key(&entity)
    }

    /// Puts `entry` in the set (replacing the entity's old entry) with its bounds at its
    /// pose. Its `body` is set to [`STATIC`].
    pub fn insert(&mut self, mut entry: ColliderEntry) {
        (entry.aabb_min, entry.aabb_max) = entry.shape.aabb(entry.pos, entry.rot);
        entry.body = STATIC;
        if entry.owner != entry.entity {
            let parts = self.parts.entry(entry.owner).or_default();
            if !parts.contains(&entry.entity) {
                parts.push(entry.entity);
            }
        }
        match self.slots.get(&entry.entity) {
            Some(&i) => self.entries[i as usize] = entry,
            None => {
                self.slots.insert(entry.entity, self.entries.len() as u32);
                self.entries.push(entry);
            }
        }
        self.dirty = true;
    }

    /// Takes the entity's entry out; returns whether it was there.
    pub fn remove(&mut self, entity: Entity) -> bool {
        // A compound body's parts leave with it.
        if let Some(parts) = self.parts.remove(&entity) {
            for part in parts {
                self.remove(part);
            }
        }
        let Some(i) = self.slots.remove(&entity) else {
            return false;
        };
        self.entries.swap_remove(i as usize);
        if let Some(moved) = self.entries.get(i as usize) {
            self.slots.insert(moved.entity, i);
        }
        self.dirty = true;
        true
    }

    /// Rebuilds the search order if the set changed since the last call.
    pub fn update_search(&mut self) {
        if !self.dirty {
            return;
        }
        self.dirty = false;
        let entries = &self.entries;
        self.index.rebuild(entries.len(), |i| {
            let c = &entries[i as usize];
            (c.aabb_min, c.aabb_max)
        });
    }

    /// Calls `found` with the index of every entry whose bounds, fattened by `margin`,
    /// overlap [lo, hi]. Call [`update_search`](Self::update_search) after changes first.
    #[inline]
    pub fn overlapping(&self, lo: Vec3, hi: Vec3, margin: f32, found: impl FnMut(u32)) {
        debug_assert!(!self.dirty, "FixedSet searched before update_search");
        let (lo, hi) = (lo - Vec3::splat(margin), hi + Vec3::splat(margin));
        let entries = &self.entries;
        let aabb = |i: u32| {
            let c = &entries[i as usize];
            (c.aabb_min, c.aabb_max)
        };
        self.index.overlapping(aabb, lo, hi, found);
    }

    /// The union of the entries' finite boxes (not infinite planes), m; lo > hi when
    /// there are none. As of the last [`update_search`](Self::update_search).
    pub fn extent(&self) -> (Vec3, Vec3) {
        self.index.extent()
    }

    /// Whether the search order is up to date (the broad phase updates it; with
    /// collisions off, or after a change since, it is not).
    pub fn is_searchable(&self) -> bool {
        !self.dirty
    }

    /// The reference for [`overlapping`](Self::overlapping): every entry tested.
    #[cfg(test)]
    pub fn overlapping_brute_force(&self, lo: Vec3, hi: Vec3, margin: f32) -> Vec<u32> {
        let (lo, hi) = (lo - Vec3::splat(margin), hi + Vec3::splat(margin));
        (0..self.entries.len() as u32)
            .filter(|&i| {
                let c = &self.entries[i as usize];
                c.aabb_min.cmple(hi).all() && lo.cmple(c.aabb_max).all()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Collider;

    fn entry(entity: u32, collider: Collider, pos: Vec3) -> ColliderEntry {
        let e = Entity::from_raw_u32(entity).unwrap();
        ColliderEntry::new(e, entity as u64, 0, collider.shape, pos, Quat::IDENTITY)
    }

    fn query(set: &FixedSet, lo: Vec3, hi: Vec3) -> Vec<u32> {
        let mut out = vec![];
        set.overlapping(lo, hi, 0.01, |i| out.push(i));
        out.sort_unstable();
        out
    }

    #[test]
    fn finds_what_brute_force_finds_with_a_plane_and_a_long_wall() {
        let mut set = FixedSet::default();
        set.insert(entry(1, Collider::plane(), Vec3::ZERO));
        set.insert(entry(
            2,
            Collider::cuboid(40.0, 1.0, 0.5),
            Vec3::new(0.0, 1.0, 5.0),
        ));
        for i in 0..200u32 {
            let p = Vec3::new(
                (i % 20) as f32 * 1.5 - 15.0,
                0.5,
                (i / 20) as f32 * 1.5 - 7.0,
            );
            set.insert(entry(10 + i, Collider::sphere(0.5), p));
        }
        set.update_search();
        for k in 0..100 {
            let c = Vec3::new(
                k as f32 * 0.37 - 18.0,
                (k % 7) as f32 * 0.4,
                k as f32 * 0.21 - 9.0,
            );
            let (lo, hi) = (c - Vec3::splat(0.3), c + Vec3::splat(0.3 + k as f32 * 0.05));
            assert_eq!(
                query(&set, lo, hi),
                set.overlapping_brute_force(lo, hi, 0.01)
            );
        }
    }

    #[test]
    fn insert_replaces_and_remove_keeps_the_others_findable() {
        let mut set = FixedSet::default();
        let a = entry(1, Collider::sphere(0.5), Vec3::ZERO);
        set.insert(a.clone());
        set.insert(entry(2, Collider::sphere(0.5), Vec3::X * 3.0));
        set.insert(ColliderEntry {
            pos: Vec3::X * 10.0,
            ..a
        });
        assert_eq!(set.len(), 2);
        assert_eq!(set.get(a.entity).unwrap().body, STATIC);
        set.update_search();
        assert!(query(&set, Vec3::splat(-0.2), Vec3::splat(0.2)).is_empty());
        assert!(set.remove(a.entity));
        assert!(!set.remove(a.entity));
        set.update_search();
        let near_second = query(&set, Vec3::new(2.9, -0.1, -0.1), Vec3::new(3.1, 0.1, 0.1));
        assert_eq!(near_second.len(), 1);
        assert_eq!(set.entries()[near_second[0] as usize].pos, Vec3::X * 3.0);
    }
}
