//! [`TumblePlugin`] and the [`PhysicsSystems`] stages. This file only wires systems.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Collider;
use crate::effects::{Effects, GravityScale, LockRotation, Wind, effect};
use crate::events;
use crate::settings::{GlobalForce, Gravity, Integrator, SleepSettings, SolverSettings};
use crate::step::{broad_phase, forces, integrate, narrow_phase, prepare, sleep, solve, writeback};
use crate::timings::{StepTimings, stamp};

pub use crate::systems::PhysicsSystems;

/// Adds rigid-body physics. Steps in `FixedUpdate` at `hz` (60 by default); a
/// `Time<Fixed>` inserted after adding the plugin wins.
#[derive(Clone, Debug)]
pub struct TumblePlugin {
    /// Fixed steps per second, Hz, clamped into 1..=10000 (not finite: 60). Default 60.
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
            .init_resource::<crate::query::SpatialQueryCache>()
            .init_resource::<prepare::PendingRechecks>()
            .init_resource::<prepare::SpawnCounter>()
            .add_observer(prepare::record_removal)
            .add_observer(prepare::record_marker)
            .add_observer(prepare::number_collider)
            .add_message::<events::CollisionStart>()
            .add_message::<events::CollisionEnd>()
            .add_message::<crate::joint::JointBroken>();
        app.register_type::<RigidBody>()
            .register_type::<Velocity>()
            .register_type::<Mass>()
            .register_type::<CenterOfMass>()
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
            .register_type::<GlobalForce>()
            .register_type::<crate::joint::Joint>()
            .register_type::<crate::joint::JointForces>();

        // Colliders built from meshes as they load (before the frame's fixed steps).
        #[cfg(feature = "mesh")]
        app.register_type::<crate::mesh_colliders::ColliderConstructor>()
            .register_type::<crate::mesh_colliders::ColliderConstructorHierarchy>()
            .add_systems(PreUpdate, crate::mesh_colliders::construct_colliders);

        use PhysicsSystems as S;
        for pair in S::ORDER.windows(2) {
            app.configure_sets(FixedUpdate, pair[1].after(pair[0]));
        }
        app.add_systems(
            RunFixedMainLoop,
            prepare::guard_fixed_rate.in_set(RunFixedMainLoopSystems::BeforeFixedMainLoop),
        );
        let collisions = effect(|e| e.collisions);
        app.add_systems(
            FixedUpdate,
            (
                (
                    stamp::<{ S::Prepare as usize }>,
                    prepare::validate_settings,
                    prepare::readmit_rejected,
                    prepare::sync_fixed_set,
                    prepare::wake_reached_sleepers,
                    prepare::prepare_bodies,
                    prepare::prepare_joints,
                    prepare::clear_impulses,
                )
                    .chain()
                    .in_set(S::Prepare),
                (
                    stamp::<{ S::Forces as usize }>,
                    forces::apply_gravity.run_if(effect(|e| e.gravity)),
                    forces::apply_global_force.run_if(effect(|e| e.global_force)),
                    forces::apply_damping.run_if(effect(|e| e.damping)),
                    forces::apply_wind.run_if(effect(|e| e.wind)),
                )
                    .chain()
                    .in_set(S::Forces),
                (
                    stamp::<{ S::Integrate as usize }>,
                    integrate::integrate_free_motion,
                )
                    .chain()
                    .in_set(S::Integrate),
                (
                    stamp::<{ S::BroadPhase as usize }>,
                    broad_phase::find_pairs.run_if(collisions.clone()),
                )
                    .chain()
                    .in_set(S::BroadPhase),
                (
                    stamp::<{ S::NarrowPhase as usize }>,
                    narrow_phase::collide_pairs.run_if(collisions.clone()),
                )
                    .chain()
                    .in_set(S::NarrowPhase),
                (
                    stamp::<{ S::Solve as usize }>,
                    // Also without collisions: joints (it returns at once with neither).
                    solve::solve_contacts,
                    solve::sweep_against_fixed.run_if(collisions),
                )
                    .chain()
                    .in_set(S::Solve),
                (
                    stamp::<{ S::Writeback as usize }>,
                    writeback::writeback_bodies,
                    writeback::writeback_joints,
                    events::report_collisions,
                )
                    .chain()
                    .in_set(S::Writeback),
                (
                    stamp::<{ S::Sleep as usize }>,
                    sleep::update_sleep.run_if(effect(|e| e.sleeping)),
                    stamp::<{ S::ORDER.len() }>,
                )
                    .chain()
                    .in_set(S::Sleep),
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::PhysicsSystems;

    #[test]
    fn the_order_is_the_discriminants_order() {
        for (i, stage) in PhysicsSystems::ORDER.iter().enumerate() {
            assert_eq!(*stage as usize, i, "{stage:?}");
        }
    }
}
