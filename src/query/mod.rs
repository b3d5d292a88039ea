//! Spatial queries: ray casts, shape casts, point, box and shape overlaps and point
//! projection against every collider, at the poses the last completed step left them in.
//!
//! [`SpatialQuery`] is a system parameter usable in any schedule (outside the physics
//! step's own sets, where the poses are half-way through a step). Names follow avian3d's
//! where they fit. Each query looks only at colliders whose bounding box its ray, sweep
//! or region meets: the fixed set (static colliders and sleepers) through its own index,
//! the awake colliders through one built on the first query after each step (about 40 ns
//! a collider; a game that never queries never pays it). Exact tests are parry3d's.
//!
//! ```no_run
//! # use bevy::prelude::*;
//! # use tumble::prelude::*;
//! fn aim(query: SpatialQuery, player: Single<(Entity, &Transform), With<RigidBody>>) {
//!     let (me, tf) = *player;
//!     let filter = SpatialQueryFilter::default().with_excluded_entities([me]);
//!     if let Some(hit) = query.cast_ray(tf.translation, tf.forward(), 100.0, true, &filter) {
//!         info!("looking at {} {:.2} m away, normal {}", hit.entity, hit.distance, hit.normal);
//!     }
//! }
//! ```

mod filter;
mod index;
#[cfg(test)]
mod parity_tests;

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

pub use filter::SpatialQueryFilter;
pub(crate) use index::SpatialQueryCache;
use index::{AwakeIndex, Candidate};

use crate::collider::{Collider, Shape};
use crate::geometry::query as exact;
use crate::world::PhysicsWorld;

/// A ray's hit on a collider.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHitData {
    /// The collider hit (a compound body's part is its own entity).
    pub entity: Entity,
    /// The body it belongs to (itself, or the body above a part), `None` for a static
    /// collider.
    pub body: Option<Entity>,
    /// Distance from the ray's origin, m.
    pub distance: f32,
    /// The hit point, world frame, m.
    pub point: Vec3,
    /// The surface's unit normal at the hit, facing the ray's origin side.
    pub normal: Vec3,
}

/// A cast shape's first contact with a collider.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHitData {
    /// The collider hit.
    pub entity: Entity,
    /// Its body, `None` for a static collider.
    pub body: Option<Entity>,
    /// How far the shape travelled before touching, m (0 if it started touching).
    pub distance: f32,
    /// The contact point on the collider hit, world frame, m.
    pub point: Vec3,
    /// The hit collider's outward unit normal there.
    pub normal: Vec3,
}

/// The point of a collider nearest to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointProjection {
    /// The collider.
    pub entity: Entity,
    /// Its body, `None` for a static collider.
    pub body: Option<Entity>,
    /// The nearest point on it, world frame, m (the query point itself when inside a
    /// solid projection).
    pub point: Vec3,
    /// Whether the query point is inside the collider.
    pub is_inside: bool,
    /// Distance from the query point to `point`, m.
    pub distance: f32,
}

/// Ray casts, shape casts and overlap queries against the colliders of the last step.
/// A collider despawned or stripped of its [`Collider`] since that step is never
/// returned, whatever the frame pacing: the index is the step's, the answer is now's.
#[derive(SystemParam)]
pub struct SpatialQuery<'w, 's> {
    world: Res<'w, PhysicsWorld>,
    cache: Res<'w, SpatialQueryCache>,
    live: Query<'w, 's, (), With<Collider>>,
}

/// The farthest a ray or a cast reaches, m: `f32::MAX` and other huge limits are cut to
/// this (parry's casts lose their precision on them).
pub const MAX_QUERY_DISTANCE: f32 = 1.0e7;

/// A query's pose, made usable: a finite position and a finite rotation of non-zero
/// length (normalized here). Anything else answers nothing, with a warning once: a NaN
/// in must never come back out as a NaN distance or point.
fn usable(what: &str, position: Vec3, rotation: Quat) -> Option<Quat> {
    let ok = position.is_finite() && rotation.is_finite() && rotation.length_squared() > 1e-12;
    if !ok {
        warn_once!(
            "tumble: a spatial query was given a {what} that is not finite or a rotation of \
             zero length ({position}, {rotation}); it finds nothing"
        );
        return None;
    }
    Some(rotation.normalize())
}

/// Accepts everything: the predicate of the queries that take none.
fn any(_: Entity) -> bool {
    true
}

impl SpatialQuery<'_, '_> {
    /// The first collider a ray from `origin` along `direction` hits within
    /// `max_distance` (m; `f32::MAX` for no limit: [`MAX_QUERY_DISTANCE`]). With `solid`, a ray starting inside
    /// a collider hits it at distance 0; without, it hits the inside of its boundary.
    pub fn cast_ray(
        &self,
        origin: Vec3,
        direction: Dir3,
        max_distance: f32,
        solid: bool,
        filter: &SpatialQueryFilter,
    ) -> Option<RayHitData> {
        self.cast_ray_predicate(origin, direction, max_distance, solid, filter, &any)
    }

    /// [`cast_ray`](Self::cast_ray), skipping colliders for which `predicate` (given the
    /// collider's entity) returns false.
    pub fn cast_ray_predicate(
        &self,
        origin: Vec3,
        direction: Dir3,
        max_distance: f32,
        solid: bool,
        filter: &SpatialQueryFilter,
        predicate: &dyn Fn(Entity) -> bool,
    ) -> Option<RayHitData> {
        let mut best: Option<(RayHitData, u64)> = None;
        self.ray_walk(
            origin,
            direction,
            max_distance,
            solid,
            filter,
            predicate,
            |hit, key| {
                if best.is_none_or(|(b, k)| (hit.distance, key) < (b.distance, k)) {
                    best = Some((hit, key));
                }
                true
            },
        );
        best.map(|(hit, _)| hit)
    }

    /// Every collider the ray hits within `max_distance`, nearest first (ties in spawn
    /// order), at most `max_hits`.
    pub fn ray_hits(
        &self,
        origin: Vec3,
        direction: Dir3,
        max_distance: f32,
        max_hits: usize,
        solid: bool,
        filter: &SpatialQueryFilter,
    ) -> Vec<RayHitData> {
        let mut hits = Vec::new();
        self.ray_walk(
            origin,
            direction,
            max_distance,
            solid,
            filter,
            &any,
            |hit, key| {
                hits.push((hit, key));
                true
            },
        );
        hits.sort_by(|a, b| a.0.distance.total_cmp(&b.0.distance).then(a.1.cmp(&b.1)));
        hits.truncate(max_hits);
        hits.into_iter().map(|(hit, _)| hit).collect()
    }

    /// Calls `callback` with each collider the ray hits within `max_distance`, in no
    /// particular order, until it returns false.
    pub fn ray_hits_callback(
        &self,
        origin: Vec3,
        direction: Dir3,
        max_distance: f32,
        solid: bool,
        filter: &SpatialQueryFilter,
        mut callback: impl FnMut(RayHitData) -> bool,
    ) {
        self.ray_walk(
            origin,
            direction,
            max_distance,
            solid,
            filter,
            &any,
            |hit, _| callback(hit),
        );
    }

    /// The first collider that `shape`, turned by `rotation` and moved from `origin`
    /// along `direction`, touches within `max_distance` (m). A shape that starts
    /// touching a collider hits it at distance 0.
    pub fn cast_shape(
        &self,
        shape: &Collider,
        origin: Vec3,
        rotation: Quat,
        direction: Dir3,
        max_distance: f32,
        filter: &SpatialQueryFilter,
    ) -> Option<ShapeHitData> {
        let rotation = usable("cast origin", origin, rotation)?;
        if max_distance.is_nan() {
            return None;
        }
        let dir = *direction;
        let max_distance = max_distance.min(MAX_QUERY_DISTANCE);
        let (lo0, hi0) = shape.shape.aabb(origin, rotation);
        let half = (hi0 - lo0) * 0.5;
        let reach = self.reach(origin, dir, max_distance, half);
        let (lo1, hi1) = shape.shape.aabb(origin + dir * reach, rotation);
        let mut best: Option<(ShapeHitData, u64)> = None;
        // The swept box must meet a candidate's: a slab test of the centre's path against
        // the candidate's box grown by the shape's half size.
        let centre = (lo0 + hi0) * 0.5;
        let sweeps = |lo: Vec3, hi: Vec3| {
            exact::ray_aabb(centre, dir, max_distance, lo - half, hi + half).is_some()
        };
        self.walk_where(lo0.min(lo1), hi0.max(hi1), sweeps, |c| {
            if !filter.admits(c.entry) {
                return;
            }
            let target = &c.entry.shape;
            if let Some((d, point, normal)) = exact::cast_shape(
                &shape.shape,
                (origin, rotation),
                dir,
                max_distance,
                target,
                c.pose,
            ) {
                let key = c.entry.key;
                if best.is_none_or(|(b, k)| (d, key) < (b.distance, k)) {
                    let hit = ShapeHitData {
                        entity: c.entry.entity,
                        body: c.entry.body_entity(),
                        distance: d,
                        point,
                        normal,
                    };
                    best = Some((hit, key));
                }
            }
        });
        best.map(|(hit, _)| hit)
    }

    /// Every collider that contains `point` (on its surface counts), in spawn order.
    pub fn point_intersections(&self, point: Vec3, filter: &SpatialQueryFilter) -> Vec<Entity> {
        if usable("point", point, Quat::IDENTITY).is_none() {
            return Vec::new();
        }
        self.collect(point, point, filter, |c| {
            exact::contains_point(&c.entry.shape, c.pose, point)
        })
    }

    /// Every collider whose bounding box overlaps the box [`min`, `max`] (m), in spawn
    /// order: a broad test, not the shapes themselves (but for an infinite plane, whose
    /// box would be all of space: it counts when the box reaches below it).
    pub fn aabb_intersections(
        &self,
        min: Vec3,
        max: Vec3,
        filter: &SpatialQueryFilter,
    ) -> Vec<Entity> {
        if usable("box", min, Quat::IDENTITY).is_none() || !max.is_finite() {
            return Vec::new();
        }
        let region = Shape::Cuboid {
            half_extents: ((max - min) * 0.5).max(Vec3::ZERO),
        };
        let centre = (min + max) * 0.5;
        self.collect(min, max, filter, |c| {
            let boxes = c.lo.cmple(max).all() && min.cmple(c.hi).all();
            match c.entry.shape {
                Shape::Plane { half_extents: None } => {
                    exact::intersects(&region, (centre, Quat::IDENTITY), &c.entry.shape, c.pose)
                }
                _ => boxes,
            }
        })
    }

    /// Every collider that overlaps `shape` at `position`, turned by `rotation` (touching
    /// counts), in spawn order.
    pub fn shape_intersections(
        &self,
        shape: &Collider,
        position: Vec3,
        rotation: Quat,
        filter: &SpatialQueryFilter,
    ) -> Vec<Entity> {
        let Some(rotation) = usable("position", position, rotation) else {
            return Vec::new();
        };
        let (lo, hi) = shape.shape.aabb(position, rotation);
        self.collect(lo, hi, filter, |c| {
            exact::intersects(&shape.shape, (position, rotation), &c.entry.shape, c.pose)
        })
    }

    /// The collider point nearest to `point`. With `solid`, a point inside a collider
    /// projects onto itself (distance 0); without, onto the collider's boundary.
    pub fn project_point(
        &self,
        point: Vec3,
        solid: bool,
        filter: &SpatialQueryFilter,
    ) -> Option<PointProjection> {
        usable("point", point, Quat::IDENTITY)?;
        let (elo, ehi) = self.cache.with(&self.world, AwakeIndex::extent);
        // Search a growing box around the point: a collider whose box misses a box of
        // half size r is farther than r away, so the nearest within r is the nearest.
        let mut r = 0.5f32;
        loop {
            let (lo, hi) = (point - Vec3::splat(r), point + Vec3::splat(r));
            let mut best: Option<(PointProjection, u64)> = None;
            self.walk(lo, hi, |c| {
                if !filter.admits(c.entry) {
                    return;
                }
                let (p, is_inside) = exact::project_point(&c.entry.shape, c.pose, point, solid);
                let distance = p.distance(point);
                let key = c.entry.key;
                if best.is_none_or(|(b, k)| (distance, key) < (b.distance, k)) {
                    let projection = PointProjection {
                        entity: c.entry.entity,
                        body: c.entry.body_entity(),
                        point: p,
                        is_inside,
                        distance,
                    };
                    best = Some((projection, key));
                }
            });
            let covers_all = !(elo.cmplt(lo).any() || ehi.cmpgt(hi).any());
            if best.is_some_and(|(b, _)| b.distance <= r) || covers_all || !r.is_finite() {
                return best.map(|(b, _)| b);
            }
            r *= 4.0;
        }
    }

    /// Runs `found` on every collider whose box meets [lo, hi].
    fn walk<'a>(&'a self, lo: Vec3, hi: Vec3, found: impl FnMut(Candidate<'a>)) {
        self.walk_where(lo, hi, |_, _| true, found);
    }

    /// Runs `found` on every collider whose box meets [lo, hi] and passes `test` (given
    /// a box, lo and hi, m), which also prunes the awake tree's subtrees.
    fn walk_where<'a>(
        &'a self,
        lo: Vec3,
        hi: Vec3,
        test: impl Fn(Vec3, Vec3) -> bool,
        mut found: impl FnMut(Candidate<'a>),
    ) {
        let world: &'a PhysicsWorld = &self.world;
        // Gone since the step (despawned, or its collider removed): not there any more.
        let mut found = |c: Candidate<'a>| {
            if self.live.contains(c.entry.entity) {
                found(c)
            }
        };
        #[cfg(test)]
        if self.cache.brute_force() {
            return self.cache.with(world, |index| index.all(world, &mut found));
        }
        self.cache.with(world, |index| {
            index.overlapping(world, (lo, hi), test, &mut found)
        });
    }

    /// The entities among the colliders meeting [lo, hi] that pass `filter` and `test`,
    /// in spawn order.
    fn collect(
        &self,
        lo: Vec3,
        hi: Vec3,
        filter: &SpatialQueryFilter,
        test: impl Fn(&Candidate) -> bool,
    ) -> Vec<Entity> {
        let mut out = Vec::new();
        self.walk(lo, hi, |c| {
            if filter.admits(c.entry) && test(&c) {
                out.push((c.entry.key, c.entry.entity));
            }
        });
        out.sort_unstable();
        out.into_iter().map(|(_, e)| e).collect()
    }

    /// How far along `dir` from `origin` a sweep of a box of half size `half` can meet
    /// any finite collider: `max_distance`, cut at the scene's extent.
    fn reach(&self, origin: Vec3, dir: Vec3, max_distance: f32, half: Vec3) -> f32 {
        let (lo, hi) = self.cache.with(&self.world, AwakeIndex::extent);
        match exact::ray_aabb(origin, dir, max_distance, lo - half, hi + half) {
            Some((_, exit)) => exit,
            // Past every finite collider: only infinite planes are left, met anywhere.
            None => 0.0,
        }
    }

    /// Runs `hit` on every collider the ray hits (with its spawn-order key) until it
    /// returns false.
    #[allow(clippy::too_many_arguments)]
    fn ray_walk(
        &self,
        origin: Vec3,
        direction: Dir3,
        max_distance: f32,
        solid: bool,
        filter: &SpatialQueryFilter,
        predicate: &dyn Fn(Entity) -> bool,
        mut hit: impl FnMut(RayHitData, u64) -> bool,
    ) {
        if usable("ray origin", origin, Quat::IDENTITY).is_none() || max_distance.is_nan() {
            return;
        }
        let dir = *direction;
        let max_distance = max_distance.min(MAX_QUERY_DISTANCE);
        let reach = self.reach(origin, dir, max_distance, Vec3::ZERO);
        let end = origin + dir * reach;
        let mut going = true;
        let crosses = |lo, hi| exact::ray_aabb(origin, dir, max_distance, lo, hi).is_some();
        self.walk_where(origin.min(end), origin.max(end), crosses, |c| {
            if !going || !filter.admits(c.entry) || !predicate(c.entry.entity) {
                return;
            }
            if let Some((distance, normal)) =
                exact::cast_ray(&c.entry.shape, c.pose, origin, dir, max_distance, solid)
            {
                let data = RayHitData {
                    entity: c.entry.entity,
                    body: c.entry.body_entity(),
                    distance,
                    point: origin + dir * distance,
                    normal,
                };
                going = hit(data, c.entry.key);
            }
        });
    }
}
