//! Keeping the fixed set in step with the ECS. Static colliders and sleeping bodies are not
//! gathered every step: they enter the [`FixedSet`](crate::step::broad_phase::FixedSet)
//! once, carry the [`InFixedSet`] marker (so the per-step gather skips them by archetype),
//! and are looked at again only when something about them changes:
//! - a new static collider or a body that fell asleep (no marker yet);
//! - a marked entity whose `Transform`, `Collider`, `RigidBody`, `Friction`,
//!   `Restitution`, `Velocity` or `ExternalForce` changed (for a sleeper that is the
//!   user's hand, and it wakes);
//! - a removed `Sleeping` (woken), `Collider`, `RigidBody` or marker (despawned);
//! - every sleeper, when sleeping is switched off or the global push is on.
//!
//! It runs before [`prepare_bodies`](super::prepare_bodies) with a command flush in
//! between, so a body woken here is gathered in the same step.

use bevy::ecs::query::QueryData;
use bevy::prelude::*;

use super::{fixed_entry, reject, validate};
use crate::body::*;
use crate::collider::Collider;
use crate::effects::Effects;
use crate::settings::GlobalForce;
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
}

/// Marked entities with a change that may move them, resize them or wake them.
type ChangedFilter = (
    With<InFixedSet>,
    Or<(
        Changed<Transform>,
        Changed<Collider>,
        Changed<RigidBody>,
        Changed<Friction>,
        Changed<Restitution>,
        Changed<Velocity>,
        Changed<ExternalForce>,
    )>,
);

/// Not yet in the fixed set, and not rejected.
type Unmarked = (Without<InFixedSet>, Without<PhysicsRejected>);

/// Entities that can leave or need re-entering the fixed set.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Removed<'w, 's> {
    sleeping: RemovedComponents<'w, 's, Sleeping>,
    collider: RemovedComponents<'w, 's, Collider>,
    body: RemovedComponents<'w, 's, RigidBody>,
    marker: RemovedComponents<'w, 's, InFixedSet>,
}

/// Brings the fixed set up to date with what changed since the last step (see the module
/// docs), and wakes sleepers the user touched.
#[allow(clippy::too_many_arguments)]
pub fn sync_fixed_set(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    effects: Res<Effects>,
    global: Res<GlobalForce>,
    unmarked: Query<Entity, (With<Collider>, Without<RigidBody>, Unmarked)>,
    fell_asleep: Query<Entity, (With<Sleeping>, Unmarked)>,
    changed: Query<(Entity, Has<Sleeping>), ChangedFilter>,
    sleepers: Query<Entity, (With<Sleeping>, With<InFixedSet>)>,
    mut removed: Removed,
    items: Query<FixedItem>,
    mut recheck: Local<Vec<(Entity, bool)>>,
) {
    let world = &mut *world;
    // (entity, wake it if asleep)
    recheck.clear();
    let wake_all = !effects.sleeping || (effects.global_force && global.0 != Vec3::ZERO);
    if wake_all {
        recheck.extend(sleepers.iter().map(|e| (e, true)));
    }
    recheck.extend(changed.iter());
    recheck.extend(unmarked.iter().map(|e| (e, false)));
    recheck.extend(fell_asleep.iter().map(|e| (e, wake_all)));
    recheck.extend(removed.sleeping.read().map(|e| (e, false)));
    recheck.extend(removed.collider.read().map(|e| (e, false)));
    recheck.extend(removed.body.read().map(|e| (e, false)));
    recheck.extend(removed.marker.read().map(|e| (e, false)));
    if recheck.is_empty() {
        return;
    }
    // One decision per entity; waking wins.
    recheck.sort_unstable_by_key(|&(e, wake)| (e, !wake));
    recheck.dedup_by_key(|&mut (e, _)| e);

    for &(entity, wake) in recheck.iter() {
        let Ok(item) = items.get(entity) else {
            world.fixed.remove(entity);
            if let Ok(mut e) = commands.get_entity(entity) {
                e.try_remove::<InFixedSet>();
            }
            continue;
        };
        let was_asleep = world.fixed.get(entity).is_some_and(|c| c.asleep);
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
            world.fixed.remove(entity);
            if item.marked {
                commands.entity(entity).remove::<InFixedSet>();
            }
            continue;
        }
        match item.collider {
            Some(c) => {
                let kind = RigidBody::Static;
                match validate(item.transform, &Velocity::ZERO, kind, None, Some(&c.shape)) {
                    Ok(()) => {
                        let entry =
                            fixed_entry(entity, item.transform, c, item.friction, item.restitution);
                        world.fixed.insert(entry(item.sleeping));
                    }
                    Err(e) => {
                        world.fixed.remove(entity);
                        reject(&mut commands, entity, e);
                        continue;
                    }
                }
            }
            None => {
                world.fixed.remove(entity);
            }
        }
        if !item.marked {
            commands.entity(entity).insert(InFixedSet);
        }
    }
}
