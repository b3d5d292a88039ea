//! [`TumblePlugin`] and the [`PhysicsSystems`] stages. This file only wires systems.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Collider;
use crate::events;
use crate::settings::{GlobalForce, Gravity, Integrator, SleepSettings, SolverSettings};
use crate::step::{broad_phase, integrate, narrow_phase, prepare, sleep, solve, writeback};
use crate::timings::{StepTimings, stamp};
use crate::world::PhysicsWorld;

/// The stages of one physics step, chained in `FixedUpdate` in this order. Order your own
/// systems against them, e.g. `.after(PhysicsSystems::Writeback)` to read this step's
/// velocities or `.before(PhysicsSystems::Prepare)` to set forces for it.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhysicsSystems {
    /// ECS → contiguous solver arrays; invalid bodies are rejected here.
    Prepare,
    /// Free motion (forces, drag, rotation) with the chosen [`Integrator`].
    Integrate,
    /// Candidate pairs from swept bounding boxes.
    BroadPhase,
    /// Contact manifolds for the candidate pairs.
    NarrowPhase,
    /// Contact impulses (substepped soft step, friction, restitution).
    Solve,
    /// Solver arrays → `Transform` / `Velocity`; collision messages.
    Writeback,
    /// Still islands fall asleep; touched sleepers wake.
    Sleep,
}

/// Adds rigid-body physics. Steps in `FixedUpdate` at `hz` (60 by default); a
/// `Time<Fixed>` inserted after adding the plugin wins.
#[derive(Clone, Debug)]
pub struct TumblePlugin {
    pub hz: f64,
}

impl Default for TumblePlugin {
    fn default() -> Self {
        Self { hz: 60.0 }
    }
}

impl Plugin for TumblePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(Time::<Fixed>::from_hz(self.hz))
            .init_resource::<Gravity>()
            .init_resource::<Integrator>()
            .init_resource::<SolverSettings>()
            .init_resource::<SleepSettings>()
            .init_resource::<StepTimings>()
            .init_resource::<GlobalForce>()
            .add_message::<events::CollisionStarted>()
            .add_message::<events::CollisionEnded>()
            .init_resource::<PhysicsWorld>()
            .register_type::<RigidBody>()
            .register_type::<Velocity>()
            .register_type::<Mass>()
            .register_type::<Restitution>()
            .register_type::<Friction>()
            .register_type::<ExternalForce>()
            .register_type::<LinearDamping>()
            .register_type::<AngularDamping>()
            .register_type::<Collider>()
            .register_type::<Gravity>()
            .register_type::<Integrator>()
            .register_type::<SolverSettings>()
            .register_type::<SleepSettings>()
            .register_type::<SleepTimer>()
            .configure_sets(
                FixedUpdate,
                (
                    PhysicsSystems::Prepare,
                    PhysicsSystems::Integrate,
                    PhysicsSystems::BroadPhase,
                    PhysicsSystems::NarrowPhase,
                    PhysicsSystems::Solve,
                    PhysicsSystems::Writeback,
                    PhysicsSystems::Sleep,
                )
                    .chain(),
            )
            .add_systems(
                FixedUpdate,
                (
                    (stamp::<0>, prepare::prepare_bodies)
                        .chain()
                        .in_set(PhysicsSystems::Prepare),
                    (stamp::<1>, integrate::integrate_free_motion)
                        .chain()
                        .in_set(PhysicsSystems::Integrate),
                    (stamp::<2>, broad_phase::find_pairs)
                        .chain()
                        .in_set(PhysicsSystems::BroadPhase),
                    (stamp::<3>, narrow_phase::collide_pairs)
                        .chain()
                        .in_set(PhysicsSystems::NarrowPhase),
                    (stamp::<4>, solve::solve_contacts)
                        .chain()
                        .in_set(PhysicsSystems::Solve),
                    (
                        stamp::<5>,
                        writeback::writeback_bodies,
                        events::write_collision_messages,
                    )
                        .chain()
                        .in_set(PhysicsSystems::Writeback),
                    (stamp::<6>, sleep::update_sleep, stamp::<7>)
                        .chain()
                        .in_set(PhysicsSystems::Sleep),
                ),
            );
    }
}
