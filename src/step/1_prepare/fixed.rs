//! Keeping the fixed set in step with the ECS. Static colliders and sleeping bodies are not
//! gathered every step: they enter the [`FixedSet`](crate::world::FixedSet)
//! once, carry the [`InFixedSet`] marker (so the per-step gather skips them by archetype),
//! and are looked at again only when something about them changes:
//! - a new static collider or a body that fell asleep (no marker yet);
//! - a marked entity whose `Transform`, `Collider`, `RigidBody`, `Friction`,
//!   `Restitution`, `Velocity`, `ExternalForce`, `ExternalImpulse` or `CollisionLayers`
//!   changed (for a sleeper that is the user's hand, and it wakes);
//! - an inserted or removed `Sensor` or `CollisionEventsEnabled` (markers: recorded by
//!   observers, so the per-step scan does not test them);
//! - a removed `Sleeping` (woken), `Collider`, `RigidBody` or marker, or a despawn:
//!   recorded by observers the moment it happens, whatever the frame pacing
//!   ([`PendingRechecks`]);
//! - every sleeper, when sleeping is switched off or the global push is on.
//!
//! A static collider that moves, changes shape or leaves, and a sleeper that is despawned
//! or loses its collider, wakes the sleepers it touched, and everything asleep that
//! touches those (Box2D wakes the island of a destroyed body the same way): nothing is
//! left hanging on a support that is gone.
//!
//! It runs before [`prepare_bodies`](super::prepare_bodies) with a command flush in
//! between, so a body woken here is gathered in the same step.

use bevy::ecs::query::QueryData;
use bevy::prelude::*;

use super::compound::{BodyPart, PartItem, PartScratch};
use super::hierarchy::{ChainQuery, owner_body, parent_frame, unsupported, world_transform};
use super::lifecycle::PendingRechecks;
use super::{FilterItem, fixed_entry, order_key, reject, validate_static};
use crate::body::*;
use crate::collider::Collider;
use crate::effects::{Effects, GravityScale};
use crate::layers::CollisionLayers;
use crate::settings::{GlobalForce, SolverSettings};
use crate::world::PhysicsWorld;

/// Tumble's bookkeeping: this entity is static or asleep and lives in the fixed set, so
/// the per-step gather skips it. Added and removed by tumble; don't insert it yourself.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct InFixedSet;

/// What deciding an entity's place in the fixed set reads.
#[derive(QueryData)]
pub struct FixedItem {
    transform: &'static Transform,
    collider: Option<&'static Collider>,
    kind: Option<&'static RigidBody>,
    friction: Option<&'static Friction>,
    restitution: Option<&'static Restitution>,
    sleeping: Has<Sleeping>,
    marked: Has<InFixedSet>,
    rejected: Has<PhysicsRejected>,
    order: Option<&'static SpawnOrder>,
    filter: FilterItem,
    parent: Has<ChildOf>,
    children: Option<&'static Children>,
    density: Option<&'static ColliderDensity>,
}

/// Marked entities with a change that may move them, resize them or wake them (of a
/// changed `Transform`, only a pose that differs counts: see [`Edits`]).
type ChangedFilter = (
    With<InFixedSet>,
    Or<(
        Or<(
            Changed<Transform>,
            Changed<Collider>,
            Changed<RigidBody>,
            Changed<Friction>,
            Changed<Restitution>,
            Changed<Velocity>,
            Changed<ExternalForce>,
            Changed<ExternalImpulse>,
            Changed<CollisionLayers>,
        )>,
        // What a body is weighed and moved by.
        Or<(
            Changed<Mass>,
            Changed<AngularInertia>,
            Changed<CenterOfMass>,
            Changed<ColliderDensity>,
            Changed<GravityScale>,
            Changed<LinearDamping>,
            Changed<AngularDamping>,
        )>,
    )>,
);

/// What changed on an entity the [`ChangedFilter`] let through.
#[derive(QueryData)]
pub struct Edits {
    transform: Ref<'static, Transform>,
    collider: Option<Ref<'static, Collider>>,
    kind: Option<Ref<'static, RigidBody>>,
    friction: Option<Ref<'static, Friction>>,
    restitution: Option<Ref<'static, Restitution>>,
    velocity: Option<Ref<'static, Velocity>>,
    force: Option<Ref<'static, ExternalForce>>,
    impulse: Option<Ref<'static, ExternalImpulse>>,
    layers: Option<Ref<'static, CollisionLayers>>,
    mass: Option<Ref<'static, Mass>>,
    inertia: Option<Ref<'static, AngularInertia>>,
    center_of_mass: Option<Ref<'static, CenterOfMass>>,
    density: Option<Ref<'static, ColliderDensity>>,
    gravity_scale: Option<Ref<'static, GravityScale>>,
    damping: (
        Option<Ref<'static, LinearDamping>>,
        Option<Ref<'static, AngularDamping>>,
    ),
}

impl EditsItem<'_, '_> {
    /// Something besides the Transform changed.
    fn other_changed(&self) -> bool {
        fn changed<T: Component>(r: &Option<Ref<T>>) -> bool {
            r.as_ref().is_some_and(|r| r.is_changed())
        }
        changed(&self.collider)
            || changed(&self.kind)
            || changed(&self.friction)
            || changed(&self.restitution)
            || changed(&self.velocity)
            || changed(&self.force)
            || changed(&self.impulse)
            || changed(&self.layers)
            || changed(&self.mass)
            || changed(&self.inertia)
            || changed(&self.center_of_mass)
            || changed(&self.density)
            || changed(&self.gravity_scale)
            || changed(&self.damping.0)
            || changed(&self.damping.1)
    }
}

/// What a game may have edited on a body in the frame it fell asleep: the sleep stage
/// zeroed its velocity and then marked it `Sleeping`, so anything changed after the
/// marker was added is the game's hand, and wakes it.
#[derive(QueryData)]
pub struct LateEdits {
    sleeping: Ref<'static, Sleeping>,
    velocity: Option<Ref<'static, Velocity>>,
    force: Option<Ref<'static, ExternalForce>>,
    impulse: Option<Ref<'static, ExternalImpulse>>,
    mass: Option<Ref<'static, Mass>>,
    gravity_scale: Option<Ref<'static, GravityScale>>,
}

impl LateEditsItem<'_, '_> {
    fn edited(&self, this_run: bevy::ecs::change_detection::Tick) -> bool {
        let since = self.sleeping.added();
        fn newer<T: Component>(
            r: &Option<Ref<T>>,
            since: bevy::ecs::change_detection::Tick,
            now: bevy::ecs::change_detection::Tick,
        ) -> bool {
            r.as_ref()
                .is_some_and(|r| r.last_changed().is_newer_than(since, now))
        }
        newer(&self.velocity, since, this_run)
            || newer(&self.force, since, this_run)
            || newer(&self.impulse, since, this_run)
            || newer(&self.mass, since, this_run)
            || newer(&self.gravity_scale, since, this_run)
    }
}

/// Not yet in the fixed set, and not rejected.
type Unmarked = (Without<InFixedSet>, Without<PhysicsRejected>);

/// Scratch kept between steps: the entities to look at, and the bounds of entries that
/// moved or left (whose sleeping neighbours wake).
#[derive(Default)]
pub struct SyncScratch {
    /// (entity, wake it if asleep)
    recheck: Vec<(Entity, bool)>,
    disturbed: Vec<(Vec3, Vec3)>,
    /// Per fixed entry: woken already in this search.
    woken: Vec<bool>,
    wake_list: Vec<Entity>,
    parts: PartScratch,
}

/// Brings the fixed set up to date with what changed since the last step (see the module
/// docs), and wakes sleepers the user touched.
#[allow(clippy::too_many_arguments)]
pub fn sync_fixed_set(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    effects: Res<Effects>,
    global: Res<GlobalForce>,
    unmarked: Query<
        Entity,
        (
            With<Collider>,
            Without<RigidBody>,
            Without<BodyPart>,
            Unmarked,
        ),
    >,
    part_edits: Query<Entity, (With<BodyPart>, Or<(Changed<Transform>, Changed<Collider>)>)>,
    part_items: Query<PartItem>,
    fell_asleep: Query<(Entity, LateEdits), (With<Sleeping>, Unmarked)>,
    ticks: bevy::ecs::system::SystemChangeTick,
    changed: Query<(Entity, Has<Sleeping>, Edits), ChangedFilter>,
    sleepers: Query<Entity, (With<Sleeping>, With<InFixedSet>)>,
    mut pending: ResMut<PendingRechecks>,
    settings: Res<SolverSettings>,
    items: Query<FixedItem>,
    chain: ChainQuery,
    mut scratch: Local<SyncScratch>,
) {
    let world = &mut *world;
    let SyncScratch {
        recheck,
        disturbed,
        woken,
        wake_list,
        parts,
    } = &mut *scratch;
    recheck.clear();
    disturbed.clear();
    let wake_all = !effects.sleeping || (effects.global_force && global.0 != Vec3::ZERO);
    if wake_all {
        recheck.extend(sleepers.iter().map(|e| (e, true)));
    }
    // A Transform written with the value it had (an interpolation plugin restoring the
    // true pose every step, game code setting it every frame) is not a move: it must not
    // wake a sleeper or re-insert a static collider.
    recheck.extend(changed.iter().filter_map(|(e, sleeping, edits)| {
        let tf = &*edits.transform;
        let same_pose = world.fixed.get(e).is_some_and(|entry| {
            let same_shape =
                (edits.collider.as_ref()).is_none_or(|c| c.shape.scaled(tf.scale) == entry.shape);
            entry.pos == tf.translation && entry.rot == tf.rotation.normalize() && same_shape
        });
        (!same_pose || edits.other_changed()).then_some((e, sleeping))
    }));
    recheck.extend(unmarked.iter().map(|e| (e, false)));
    recheck.extend(part_edits.iter().map(|e| (e, false)));
    let now = ticks.this_run();
    recheck.extend(
        fell_asleep
            .iter()
            .map(|(e, late)| (e, wake_all || late.edited(now))),
    );
    recheck.extend(pending.entities.drain(..).map(|e| (e, false)));
    if recheck.is_empty() {
        return;
    }
    // One decision per entity; waking wins.
    recheck.sort_unstable_by_key(|&(e, wake)| (e, !wake));
    recheck.dedup_by_key(|&mut (e, _)| e);

    for &(entity, wake) in recheck.iter() {
        let old = world.fixed.get(entity).cloned();
        // A compound body's part that changed or left: its sleeping body wakes.
        if let Some(o) = old.as_ref().filter(|o| o.owner != entity)
            && let Ok(mut owner) = commands.get_entity(o.owner)
        {
            owner.try_remove::<Sleeping>();
        }
        let Ok(mut item) = items.get(entity) else {
            // Despawned (or lost its Transform): whatever slept on it wakes.
            disturbed.extend(old.map(|c| (c.aabb_min, c.aabb_max)));
            world.fixed.remove(entity);
            if let Ok(mut e) = commands.get_entity(entity) {
                e.try_remove::<InFixedSet>();
            }
            continue;
        };
        // Under a parent: placed by the whole chain, or refused (see `hierarchy`).
        let placed;
        if item.parent {
            let (tf, under_body) = world_transform(entity, &chain);
            let body = item.kind.is_some_and(|k| *k != RigidBody::Static);
            let collider = item.collider.is_some();
            let frame = parent_frame(entity, &chain);
            if under_body && collider && !body {
                // A part of the body above it: that body's gather (or its fixed-set
                // entry, asleep) places it. A changed part wakes its sleeping body.
                if let Some(owner) = owner_body(entity, &chain) {
                    commands.entity(owner).try_remove::<Sleeping>();
                }
                commands
                    .entity(entity)
                    .insert(BodyPart)
                    .try_remove::<InFixedSet>();
                continue;
            }
            if let Some(e) = unsupported(body, &frame, under_body) {
                disturbed.extend(old.as_ref().map(|c| (c.aabb_min, c.aabb_max)));
                world.fixed.remove(entity);
                reject(&mut commands, entity, e);
                continue;
            }
            placed = tf;
            item.transform = &placed;
        }
        // A sleeper woken where it lies, with its collider, needs no help: it moves, and
        // touching wakes its neighbours. Anything that leaves, jumps or changes shape does.
        let woken_in_place = old.as_ref().is_some_and(|c| {
            c.asleep
                && !item.rejected
                && item
                    .collider
                    .is_some_and(|col| col.shape.scaled(item.transform.scale) == c.shape)
                && c.pos == item.transform.translation
                && c.rot == item.transform.rotation.normalize()
        });
        let was_asleep = old.as_ref().is_some_and(|c| c.asleep);
        if wake && item.sleeping {
            commands.entity(entity).remove::<Sleeping>();
        }
        if (wake && item.sleeping) || (was_asleep && !item.sleeping) {
            // Woken: it must be still for the whole time to sleep again.
            commands.entity(entity).insert(SleepTimer(0.0));
        }
        let is_static = item.kind.is_none_or(|k| *k == RigidBody::Static);
        let belongs = !item.rejected
            && (is_static || (item.sleeping && !wake))
            && (item.collider.is_some() || item.kind.is_some());
        if !belongs {
            if !woken_in_place {
                disturbed.extend(old.as_ref().map(|c| (c.aabb_min, c.aabb_max)));
            }
            world.fixed.remove(entity);
            if item.marked {
                commands.entity(entity).remove::<InFixedSet>();
            }
            continue;
        }
        match item.collider {
            Some(c) => match validate_static(item.transform, c, item.friction, item.restitution) {
                Ok(()) => {
                    let (tf, key) = (item.transform, order_key(entity, item.order));
                    let material = (item.friction, item.restitution, item.filter.get());
                    let entry = fixed_entry(entity, key, tf, c, material);
                    world.fixed.insert(entry(item.sleeping));
                    let new = world.fixed.get(entity).cloned();
                    // Moved, resized, or stopped touching some layers: what slept on it
                    // may have lost its support.
                    if let (Some(o), Some(n)) = (&old, &new)
                        && (o.pos, o.rot, &o.shape, o.filter) != (n.pos, n.rot, &n.shape, n.filter)
                    {
                        disturbed.push((o.aabb_min, o.aabb_max));
                        disturbed.push((n.aabb_min, n.aabb_max));
                    }
                }
                Err(e) => {
                    disturbed.extend(old.as_ref().map(|c| (c.aabb_min, c.aabb_max)));
                    world.fixed.remove(entity);
                    reject(&mut commands, entity, e);
                    continue;
                }
            },
            None => {
                disturbed.extend(old.as_ref().map(|c| (c.aabb_min, c.aabb_max)));
                world.fixed.remove(entity);
            }
        }
        // A compound body's parts sleep with it (a static one's stay).
        if let Some(children) = item.children {
            let density = item.density.map(|d| d.0);
            parts.collect(children, item.transform.scale, density, &part_items);
            parts.insert_fixed(&mut world.fixed, entity, item.transform, item.sleeping);
        }
        if !item.marked {
            commands.entity(entity).insert(InFixedSet);
        }
    }
    let margin = settings.speculative_margin;
    wake_neighbours(&mut commands, world, disturbed, (woken, wake_list), margin);
}

/// Wakes every sleeper whose bounds (fattened by `margin`) meet one of the `disturbed`
/// boxes, then every sleeper touching those, and so on: the sleeping island around a
/// support that moved or left. Woken bodies leave the fixed set now, so the gather that
/// follows this step takes them.
pub(super) fn wake_neighbours(
    commands: &mut Commands,
    world: &mut PhysicsWorld,
    disturbed: &mut Vec<(Vec3, Vec3)>,
    (woken, list): (&mut Vec<bool>, &mut Vec<Entity>),
    margin: f32,
) {
    if disturbed.is_empty() {
        return;
    }
    world.fixed.update_search();
    woken.clear();
    woken.resize(world.fixed.len(), false);
    list.clear();
    let entries = world.fixed.entries();
    while let Some((lo, hi)) = disturbed.pop() {
        world.fixed.overlapping(lo, hi, margin, |i| {
            let c = &entries[i as usize];
            if c.asleep && !woken[i as usize] {
                woken[i as usize] = true;
                list.push(c.owner);
                disturbed.push((c.aabb_min, c.aabb_max));
            }
        });
    }
    for &entity in list.iter() {
        world.fixed.remove(entity);
        if let Ok(mut e) = commands.get_entity(entity) {
            e.remove::<(Sleeping, InFixedSet)>().insert(SleepTimer(0.0));
        }
    }
}
