//! [`TumblePlugin`] and the [`PhysicsSystems`] stages. This file only wires systems.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Collider;
use crate::effects::{Effects, GravityScale, LockRotation, Wind, effect};
use crate::events;
use crate::settings::{GlobalForce, Gravity, Integrator, SleepSettings, SolverSettings};
use crate::step::{broad_phase, forces, integrate, narrow_phase, prepare, sleep, solve, writeback};
use crate::timings::{StepTimings, stamp};

/// The stages of one physics step, chained in `FixedUpdate` in this order. Order your own
/// systems against them, e.g. `.after(PhysicsSystems::Writeback)` to read this step's
/// velocities or `.before(PhysicsSystems::Prepare)` to set forces for it.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhysicsSystems {
    /// ECS → contiguous solver arrays; invalid bodies are rejected here.
    Prepare,
    /// Gravity, drag, wind, the global push: one system per effect, each only when on.
    Forces,
    /// Free motion (forces, drag, rotation) with the chosen [`Integrator`].
    Integrate,
    /// Candidate pairs from swept bounding boxes.
    BroadPhase,
    /// Contact manifolds for the candidate pairs.
    NarrowPhase,
    /// Contact impulses (substepped soft step, friction, restitution), then the sweep
    /// that stops bodies an impact drove into a fixed collider.
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
        let (hz, why) = crate::limits::clamp_rate(self.hz);
        if let Some(why) = why {
            error!("tumble: TumblePlugin.hz: {why}");
        }
        app.insert_resource(Time::<Fixed>::from_hz(hz))
            .init_resource::<Gravity>()
            .init_resource::<Integrator>()
            .init_resource::<SolverSettings>()
            .init_resource::<SleepSettings>()
            .init_resource::<Effects>()
            .init_resource::<Wind>()
            .init_resource::<GlobalForce>()
            .init_resource::<StepTimings>()
            .init_resource::<crate::PhysicsWorld>()
            .init_resource::<prepare::PendingRechecks>()
            .init_resource::<prepare::SpawnCounter>()
            .add_observer(prepare::record_removal)
            .add_observer(prepare::record_marker)
            .add_observer(prepare::number_collider)
            .add_message::<events::CollisionStart>()
            .add_message::<events::CollisionEnd>();
        app.register_type::<RigidBody>()
            .register_type::<Velocity>()
            .register_type::<Mass>()
            .register_type::<Restitution>()
            .register_type::<Friction>()
            .register_type::<ExternalForce>()
            .register_type::<LinearDamping>()
            .register_type::<AngularDamping>()
            .register_type::<SleepTimer>()
            .register_type::<GravityScale>()
            .register_type::<LockRotation>()
            .register_type::<Collider>()
            .register_type::<Gravity>()
            .register_type::<Integrator>()
            .register_type::<SolverSettings>()
            .register_type::<SleepSettings>()
            .register_type::<Effects>()
            .register_type::<Wind>()
            .register_type::<GlobalForce>();

        use PhysicsSystems as S;
        app.configure_sets(
            FixedUpdate,
            (
                S::Prepare,
                S::Forces,
                S::Integrate,
                S::BroadPhase,
                S::NarrowPhase,
                S::Solve,
                S::Writeback,
                S::Sleep,
            )
                .chain(),
        );
        app.add_systems(
            RunFixedMainLoop,
            prepare::guard_fixed_rate.in_set(RunFixedMainLoopSystems::BeforeFixedMainLoop),
        );
        let collisions = effect(|e| e.collisions);
        app.add_systems(
            FixedUpdate,
            (
                (
                    stamp::<0>,
                    prepare::validate_settings,
                    prepare::readmit_rejected,
                    prepare::sync_fixed_set,
                    prepare::apply_impulses,
                    prepare::prepare_bodies,
                )
                    .chain()
                    .in_set(S::Prepare),
                (
                    stamp::<1>,
                    forces::apply_gravity.run_if(effect(|e| e.gravity)),
                    forces::apply_global_force.run_if(effect(|e| e.global_force)),
                    forces::apply_damping.run_if(effect(|e| e.damping)),
                    forces::apply_wind.run_if(effect(|e| e.wind)),
                )
                    .chain()
                    .in_set(S::Forces),
                (stamp::<2>, integrate::integrate_free_motion)
                    .chain()
                    .in_set(S::Integrate),
                (
                    stamp::<3>,
                    broad_phase::find_pairs.run_if(collisions.clone()),
                )
                    .chain()
                    .in_set(S::BroadPhase),
                (
                    stamp::<4>,
                    narrow_phase::collide_pairs.run_if(collisions.clone()),
                )
                    .chain()
                    .in_set(S::NarrowPhase),
                (
                    stamp::<5>,
                    solve::solve_contacts.run_if(collisions.clone()),
                    solve::sweep_against_fixed.run_if(collisions),
                )
                    .chain()
                    .in_set(S::Solve),
                (
                    stamp::<6>,
                    writeback::writeback_bodies,
                    events::report_collisions,
                )
                    .chain()
                    .in_set(S::Writeback),
                (
                    stamp::<7>,
                    sleep::update_sleep.run_if(effect(|e| e.sleeping)),
                    stamp::<8>,
                )
                    .chain()
                    .in_set(S::Sleep),
            ),
        );
    }
}
