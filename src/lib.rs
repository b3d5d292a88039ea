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
//!
//! ## Quick start
//!
//! A game adds [`TumblePlugin`] beside `DefaultPlugins`; a headless test adds it beside
//! `MinimalPlugins`, as here (the guide, `docs/guide.md`, covers the rest):
//!
//! ```
//! use bevy::prelude::*;
//! use bevy::time::TimeUpdateStrategy;
//! use tumble::prelude::*;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
//!     // One 60 Hz physics step per `update()`, whatever the wall clock says.
//!     .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
//! // A collider without a `RigidBody` is static; a plane faces its local +Y.
//! app.world_mut().spawn((Collider::plane(), Transform::default()));
//! // Box sizes are half extents: a 1 m cube of 50 kg, dropped from 2 m.
//! let crate_ = app
//!     .world_mut()
//!     .spawn((
//!         RigidBody::Dynamic,
//!         Collider::cuboid(0.5, 0.5, 0.5),
//!         Mass(50.0),
//!         Transform::from_xyz(0.0, 2.0, 0.0),
//!     ))
//!     .id();
//! for _ in 0..120 {
//!     app.update();
//! }
//! // Two seconds later it rests on the ground, its centre half a metre up.
//! let y = app.world().get::<Transform>(crate_).unwrap().translation.y;
//! assert!((y - 0.5).abs() < 0.01, "resting at {y}");
//! ```

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
mod systems;
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
