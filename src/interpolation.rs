//! Smooth motion between fixed steps, in the core: usable headless and with any
//! renderer. Physics steps at a fixed rate (60 Hz by default) while a game renders at
//! 30–240 Hz, so without easing a body's `Transform` moves in steps.
//!
//! tumble uses [`bevy_transform_interpolation`] (the crate avian3d uses) rather than its
//! own: add [`TransformInterpolationPlugin`] and put [`TransformInterpolation`] on the
//! bodies to ease (or `TransformInterpolationPlugin::interpolate_all()`), or
//! [`PhysicsExtrapolationPlugin`] with [`TransformExtrapolation`] to extrapolate from
//! each body's [`Velocity`] (no lag; a stutter when a contact changes the velocity).
//!
//! ```no_run
//! use bevy::prelude::*;
//! use tumble::prelude::*;
//! App::new()
//!     .add_plugins((DefaultPlugins, TumblePlugin::default()))
//!     .add_plugins(TransformInterpolationPlugin::default())
//!     .add_systems(Startup, |mut commands: Commands| {
//!         commands.spawn((RigidBody::Dynamic, Collider::sphere(0.5), TransformInterpolation));
//!     })
//!     .run();
//! ```
//!
//! The crate restores the true pose before every fixed step by writing `Transform`, which
//! marks it changed even when the value is the same. tumble therefore takes a changed
//! `Transform` of a sleeping or static body for a move only when the pose differs
//! (measured: taking every changed `Transform` for a move, a ball at rest under
//! interpolation slept in 14 of 240 steps, woken by every restore; comparing the pose,
//! 211, as without interpolation).

use bevy::ecs::query::QueryData;
use bevy::prelude::*;
use bevy_transform_interpolation::VelocitySource;
pub use bevy_transform_interpolation::prelude::*;

use crate::body::Velocity;

/// The linear part of [`Velocity`], for extrapolation.
#[derive(QueryData)]
pub struct LinearVelocitySource;

impl VelocitySource for LinearVelocitySource {
    type Previous = Velocity;
    type Current = Velocity;

    fn previous(previous: &Velocity) -> Vec3 {
        previous.linear
    }

    fn current(current: &Velocity) -> Vec3 {
        current.linear
    }
}

/// The angular part of [`Velocity`] (world frame), for extrapolation.
#[derive(QueryData)]
pub struct AngularVelocitySource;

impl VelocitySource for AngularVelocitySource {
    type Previous = Velocity;
    type Current = Velocity;

    fn previous(previous: &Velocity) -> Vec3 {
        previous.angular
    }

    fn current(current: &Velocity) -> Vec3 {
        current.angular
    }
}

/// Extrapolation from tumble's [`Velocity`]: put [`TransformExtrapolation`] on a body.
pub type PhysicsExtrapolationPlugin =
    TransformExtrapolationPlugin<LinearVelocitySource, AngularVelocitySource>;
