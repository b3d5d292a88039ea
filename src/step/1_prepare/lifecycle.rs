//! Lifecycle that survives any frame pacing. A game renders at 30–1000 Hz while physics
//! steps at 60 Hz, so most frames run no fixed step and some run two. Bevy keeps
//! `RemovedComponents` messages for two frames only, so a removal read in `FixedUpdate`
//! is lost whenever more than two frames pass between steps (a 240 Hz render, say).
//!
//! Instead, observers on the lifecycle events (`On<Remove, …>`, which a despawn also
//! triggers) write the entity into [`PendingRechecks`] the moment it happens, on any
//! frame, from any schedule; the next step's [`sync_fixed_set`](super::sync_fixed_set)
//! drains it. A scene where nothing is removed pays nothing: no system scans anything.
//!
//! The same file readmits rejected bodies: a body left out for bad input comes back
//! when the user changes one of its inputs ([`readmit_rejected`]).

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Collider;
use crate::effects::{GravityScale, LockRotation};
use crate::events::CollisionEventsEnabled;
use crate::layers::{CollisionLayers, Sensor};

use super::InFixedSet;

/// Entities that lost a component the fixed set depends on since the last step
/// (`Sleeping`, `Collider`, `RigidBody`, the [`InFixedSet`] marker, `CollisionLayers`,
/// `Sensor`, `CollisionEventsEnabled`), or were despawned.
/// Filled by observers at the moment of removal; drained by the next step.
#[derive(Resource, Default, Debug)]
pub struct PendingRechecks {
    pub(crate) entities: Vec<Entity>,
}

/// Observer: a component the fixed set depends on was removed (or its entity despawned).
pub fn record_removal(
    event: On<
        Remove,
        (
            Sleeping,
            Collider,
            RigidBody,
            InFixedSet,
            CollisionLayers,
            Sensor,
            CollisionEventsEnabled,
        ),
    >,
    mut pending: ResMut<PendingRechecks>,
) {
    pending.entities.push(event.event().entity);
}

/// Observer: a marker the fixed set depends on was inserted (`Sensor`,
/// `CollisionEventsEnabled`: markers are inserted or removed, never edited in place).
pub fn record_marker(
    event: On<Insert, (Sensor, CollisionEventsEnabled)>,
    mut pending: ResMut<PendingRechecks>,
) {
    pending.entities.push(event.event().entity);
}

/// The next [`SpawnOrder`] to hand out.
#[derive(Resource, Default, Debug)]
pub struct SpawnCounter(u64);

/// Observer: a collider appeared; number it in order of appearance.
pub fn number_collider(
    event: On<Add, Collider>,
    mut counter: ResMut<SpawnCounter>,
    mut commands: Commands,
) {
    commands
        .entity(event.event().entity)
        .insert(SpawnOrder(counter.0));
    counter.0 += 1;
}

/// A rejected body whose inputs changed since it was rejected.
type Edited = (
    With<PhysicsRejected>,
    Or<(
        Changed<Transform>,
        Changed<Velocity>,
        Changed<Mass>,
        Changed<ColliderDensity>,
        Changed<AngularInertia>,
        Changed<CenterOfMass>,
        Changed<Collider>,
        Changed<RigidBody>,
        Changed<ExternalForce>,
        Changed<Friction>,
        Changed<Restitution>,
        Changed<LinearDamping>,
        Changed<AngularDamping>,
        Changed<GravityScale>,
        Changed<LockRotation>,
    )>,
);

/// Rejection is not forever: a body left out for bad input (or frozen after a blow-up)
/// is checked again once the user changes any of its inputs. If the input is still bad
/// it is rejected again (and logged again); if it is good the body rejoins this step.
/// Tumble itself never writes to a rejected body's components, so only the user's hand
/// brings one back.
pub fn readmit_rejected(mut commands: Commands, edited: Query<Entity, Edited>) {
    for entity in &edited {
        debug!("tumble: body {entity} changed after rejection; checking it again");
        commands.entity(entity).remove::<PhysicsRejected>();
    }
}
