#![deny(missing_docs)]
//! # tumble — 3D rigid-body physics for Bevy
//!
//! Bodies are ordinary entities with a [`Transform`](bevy::prelude::Transform) plus the
//! components in [`prelude`]. [`TumblePlugin`] steps them in `FixedUpdate` as the chain
//! of [`PhysicsSystems`] sets, in [`PhysicsSystems::ORDER`] (prepare → forces →
//! integrate → broad phase → narrow phase → solve → writeback → sleep).
//!
//! Inside, the tree shows the pipeline: `world` is the data layer (the contiguous arrays
//! of [`PhysicsWorld`], manifolds, constraints, the fixed set) and imports no stage;
//! `step/` holds one folder or file per stage, each importing the data layer and never
//! another stage; `geometry` (shape-pair contacts) and `math` (integrators, soft-step
//! coefficients) are plain functions over slices, tested without Bevy. Only prepare and
//! writeback touch the ECS. [`PhysicsWorld`] exposes counts and contacts; its arrays are
//! the crate's own.

#[cfg(feature = "bench-internals")]
#[doc(hidden)]
pub mod bench_api;
pub mod body;
pub mod collider;
pub mod diagnostics;
pub mod effects;
pub mod events;
mod geometry;
#[cfg(feature = "demo")]
pub mod interaction;
pub mod interpolation;
pub mod joint;
pub mod layers;
pub mod limits;
mod math;
#[cfg(feature = "mesh")]
pub mod mesh_colliders;
#[cfg(feature = "picking")]
pub mod picking;
pub mod plugin;
pub mod query;
#[cfg(any(test, feature = "bench-internals"))]
mod rng;
pub mod scene;
pub mod settings;
pub mod state_hash;
pub(crate) mod step;
#[cfg(feature = "study")]
pub mod study;
pub mod timings;
#[cfg(feature = "viz")]
pub mod viz;
mod world;

pub use plugin::{PhysicsSystems, TumblePlugin};
pub use world::PhysicsWorld;

/// Everything a game needs: `use tumble::prelude::*;`
pub mod prelude {
    pub use crate::body::{
        AngularDamping, AngularInertia, CenterOfMass, CoefficientCombine, ColliderDensity,
        ExternalForce, ExternalImpulse, Friction, FrictionCombine, LinearDamping, Mass,
        PhysicsRejected, Restitution, RestitutionCombine, RigidBody, Sleeping, Velocity,
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
    pub use crate::joint::{Joint, JointBroken, JointForces, JointKind, JointMotor, JointSpring};
    pub use crate::layers::{CollisionLayers, LayerMask, PhysicsLayer, Sensor};
    #[cfg(feature = "mesh")]
    pub use crate::mesh_colliders::{ColliderConstructor, ColliderConstructorHierarchy};
    pub use crate::plugin::{PhysicsSystems, TumblePlugin};
    pub use crate::query::{
        PointProjection, RayHitData, ShapeHitData, SpatialQuery, SpatialQueryFilter,
    };
    pub use crate::settings::{Gravity, Integrator, SleepSettings, SolverSettings};
    pub use crate::timings::StepTimings;
    pub use crate::world::PhysicsWorld;
}
