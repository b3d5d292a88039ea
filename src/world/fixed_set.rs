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
use crate::collider::Shape;
use crate::world::{ColliderEntry, STATIC};

/// [`half_space_reaches`] for entry `c`.
#[cfg(test)]
fn reaches(c: &ColliderEntry, lo: Vec3, hi: Vec3) -> bool {
    half_space_reaches(half_space_normal(c), c.pos, lo, hi)
}

/// An infinite plane's normal, `Vec3::ZERO` for any other entry.
fn half_space_normal(c: &ColliderEntry) -> Vec3 {
    match c.shape {
        Shape::Plane { half_extents: None } => c.rot * Vec3::Y,
        _ => Vec3::ZERO,
    }
}

/// Whether an entry at `pos` whose [`half_space_normal`] is `n` may reach the box
/// [lo, hi] whose bounds its own overlap. Only an infinite plane can say no: its bounds
/// are all of space, but it is a half-space, and a box wholly in front of its surface
/// does not reach it. Without this every awake collider paired with every infinite
/// plane each step: the 10,000-ball pit's five walls made 50,000 pairs a step, most of
/// them out of reach (its narrow phase takes half as long without them), and the large
/// pyramid's floor 5,050 for the 100 cubes on it. A gap within a millionth of the box's
/// distance from the plane's origin counts as reaching (rounding), and so does a NaN.
#[inline]
fn half_space_reaches(n: Vec3, pos: Vec3, lo: Vec3, hi: Vec3) -> bool {
    if n == Vec3::ZERO {
        return true;
    }
    let (centre, half) = (lo * 0.5 + hi * 0.5, hi * 0.5 - lo * 0.5);
    let offset = centre - pos;
    // The box's lowest point against the plane: its centre's height less its extent
    // along the normal.
    let gap = n.dot(offset) - n.abs().dot(half);
    let scale = offset.abs().max_element() + half.max_element();
    !(gap > 1e-6 * scale)
}

#[derive(Default, Debug, Clone)]
pub(crate) struct FixedSet {
    entries: Vec<ColliderEntry>,
    /// Where each entity's entry is in `entries`.
    slots: HashMap<Entity, u32>,
    /// The search order over the entries' boxes.
    index: BoundsIndex,
    /// Entries changed since `index` was built.
    dirty: bool,
    /// Each entry's [`half_space_normal`], as of the last build of `index`.
    normals: Vec<Vec3>,
    /// The parts of sleeping compound bodies, by body: they leave with it.
    parts: HashMap<Entity, Vec<Entity>>,
    /// How many entries are sleeping bodies (or their parts): a scene without any skips
    /// the search for sleepers an awake body is about to reach.
    asleep: usize,
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

    /// Whether any entry is a sleeping body (or a part of one).
    pub fn has_sleepers(&self) -> bool {
        self.asleep > 0
    }

    /// The bounds of a sleeping body's entries: its own collider's and its parts'.
    pub fn sleeping_bounds(&self, entity: Entity, mut found: impl FnMut(Vec3, Vec3)) {
        let parts = self.parts.get(&entity).map_or(&[][..], |p| &p[..]);
        for e in std::iter::once(&entity).chain(parts) {
            if let Some(c) = self.get(*e).filter(|c| c.asleep) {
                found(c.aabb_min, c.aabb_max);
            }
        }
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
        self.asleep += entry.asleep as usize;
        match self.slots.get(&entry.entity) {
            Some(&i) => {
                self.asleep -= self.entries[i as usize].asleep as usize;
                self.entries[i as usize] = entry;
            }
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
        let gone = self.entries.swap_remove(i as usize);
        self.asleep -= gone.asleep as usize;
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
        self.normals.clear();
        self.normals.extend(entries.iter().map(half_space_normal));
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

    /// [`overlapping`](Self::overlapping), less the infinite planes the fattened box does
    /// not reach (see [`half_space_reaches`]): what the broad phase pairs an awake collider with.
    /// (Spatial queries keep `overlapping`: a cast's box may stop short of a plane that
    /// the cast itself reaches.)
    #[inline]
    pub fn touching(&self, lo: Vec3, hi: Vec3, margin: f32, mut found: impl FnMut(u32)) {
        let (flo, fhi) = (lo - Vec3::splat(margin), hi + Vec3::splat(margin));
        self.overlapping(lo, hi, margin, |i| {
            let (n, pos) = (self.normals[i as usize], self.entries[i as usize].pos);
            if half_space_reaches(n, pos, flo, fhi) {
                found(i);
            }
        });
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
            // The broad phase's `touching`: the same, less the floor plane (entity 1)
            // when the fattened box is above it.
            let mut touching = vec![];
            set.touching(lo, hi, 0.01, |i| touching.push(i));
            touching.sort_unstable();
            let mut expected = set.overlapping_brute_force(lo, hi, 0.01);
            let floor = set.slots[&Entity::from_raw_u32(1).unwrap()];
            if lo.y - 0.01 > 1e-4 {
                expected.retain(|&i| i != floor);
            }
            assert_eq!(touching, expected, "box {lo} {hi}");
        }
    }

    #[test]
    fn a_box_in_front_of_an_infinite_plane_does_not_reach_it() {
        // Tilted planes and random boxes, against the box's eight corners: the box reaches
        // the half-space when a corner is on or below the surface. Boxes within the
        // rounding allowance of the surface are left out of the comparison.
        let mut rng = crate::rng::Rnd(0x0009_1ae5);
        let (mut culled, mut kept) = (0, 0);
        for k in 0..2000 {
            let rot = match k % 3 {
                0 => Quat::IDENTITY,
                1 => Quat::from_rotation_arc(Vec3::Y, Vec3::X),
                _ => Quat::from_rotation_arc(Vec3::Y, rng.dir()),
            };
            let pos = rng.vec(-20.0, 20.0);
            let c = entry(1, Collider::plane(), pos);
            let c = ColliderEntry { rot, ..c };
            let centre = pos + rng.vec(-3.0, 3.0);
            let half = rng.vec(0.05, 2.0);
            let (lo, hi) = (centre - half, centre + half);
            let n = rot * Vec3::Y;
            let corners = (0..8).map(|b| {
                let pick = |bit: u32, l: f32, h: f32| if b & bit == 0 { l } else { h };
                Vec3::new(
                    pick(1, lo.x, hi.x),
                    pick(2, lo.y, hi.y),
                    pick(4, lo.z, hi.z),
                )
            });
            let lowest = corners
                .map(|p| n.dot(p - pos))
                .fold(f32::INFINITY, f32::min);
            if lowest.abs() < 1e-3 {
                continue;
            }
            assert_eq!(
                reaches(&c, lo, hi),
                lowest <= 0.0,
                "plane {n} at {pos}, box {lo} {hi}"
            );
            if lowest > 0.0 { culled += 1 } else { kept += 1 }
        }
        assert!(culled > 300 && kept > 300, "{culled} culled, {kept} kept");
        // Not a plane, or a bounded one: always reaches (its bounds decide).
        for shape in [Collider::sphere(0.5), Collider::plane_rect(1.0, 1.0)] {
            let c = entry(1, shape, Vec3::ZERO);
            assert!(reaches(&c, Vec3::splat(5.0), Vec3::splat(6.0)));
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
