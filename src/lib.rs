//! # tumble — 3D rigid-body physics for Bevy
//!
//! Bodies are ordinary entities with a [`Transform`](bevy::prelude::Transform) plus the
//! components in [`prelude`]. [`TumblePlugin`] steps them in `FixedUpdate` as a chain of
//! [`PhysicsSystems`] stages, in this order (the folder tree of `src/step/` follows it):
//!
//! 1. **prepare** — validate bodies and gather them from the ECS into contiguous arrays
//! 2. **integrate** — advance every body's free motion with the chosen [`Integrator`](settings::Integrator)
//! 3. **broad phase** — candidate pairs from swept, fattened bounding boxes
//! 4. **narrow phase** — contact manifolds, dispatched over shape pairs
//! 5. **solve** — soft-step contact impulses with substeps, friction and restitution
//! 6. **writeback** — arrays back to `Transform` / `Velocity`, collision messages
//! 7. **sleep** — still islands fall asleep, touched sleepers wake
//!
//! Everything between prepare and writeback works on plain slices in [`PhysicsWorld`]
//! and is tested without Bevy.

pub mod body;
pub mod collider;
pub mod diagnostics;
pub mod effects;
pub mod events;
pub mod interaction;
pub mod interpolation;
pub mod layers;
pub mod limits;
pub mod plugin;
pub mod scene;
pub mod settings;
pub mod state_hash;
pub mod step;
#[cfg(feature = "study")]
pub mod study;
pub mod timings;
#[cfg(feature = "viz")]
pub mod viz;
pub mod world;

pub use plugin::{PhysicsSystems, TumblePlugin};
pub use world::PhysicsWorld;

/// Everything a game needs: `use tumble::prelude::*;`
pub mod prelude {
    pub use crate::body::{
        AngularDamping, AngularInertia, CoefficientCombine, ColliderDensity, ExternalForce,
        ExternalImpulse, Friction, FrictionCombine, LinearDamping, Mass, PhysicsRejected,
        Restitution, RestitutionCombine, RigidBody, SleepTimer, Sleeping, Velocity,
    };
    pub use crate::collider::Collider;
    pub use crate::diagnostics::PhysicsDiagnosticsPlugin;
    pub use crate::effects::{Effects, GravityScale, LockRotation, Wind};
    pub use crate::events::{
        CollisionEnd, CollisionEventsEnabled, CollisionStart, Contact, ContactData,
    };
    pub use crate::interpolation::{
        PhysicsExtrapolationPlugin, TransformExtrapolation, TransformInterpolation,
        TransformInterpolationPlugin,
    };
    pub use crate::layers::{CollisionLayers, LayerMask, PhysicsLayer, Sensor};
    pub use crate::plugin::{PhysicsSystems, TumblePlugin};
    pub use crate::settings::{GlobalForce, Gravity, Integrator, SleepSettings, SolverSettings};
    pub use crate::timings::StepTimings;
    pub use crate::world::PhysicsWorld;
}
