//! Simulate only the effects a scene calls for. Each effect is its own system or solver
//! pass behind a run condition on [`Effects`]: an effect that is off is never run, so it
//! costs nothing. Bodies opt out per effect with [`GravityScale`] and [`LockRotation`].

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

/// Which effects the simulation runs. Settable from code, the demo's panel and scene files
/// (`effects: (wind: true, friction: false)`); fields left out keep their default.
#[derive(Resource, Reflect, Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[reflect(Resource)]
#[serde(default, deny_unknown_fields)]
pub struct Effects {
    /// [`Gravity`](crate::settings::Gravity), scaled per body by [`GravityScale`].
    pub gravity: bool,
    /// `LinearDamping` / `AngularDamping` on the bodies that have them.
    pub damping: bool,
    /// The [`Wind`] field. Off by default.
    pub wind: bool,
    /// [`GlobalForce`](crate::settings::GlobalForce), the six-direction push.
    pub global_force: bool,
    /// Friction rows in the contact solver.
    pub friction: bool,
    /// The restitution pass of the contact solver.
    pub restitution: bool,
    /// Angular motion. Off: no body turns; no angular integration runs.
    pub rotation: bool,
    /// Broad phase, narrow phase and contact solver. Off: bodies fly through each other.
    pub collisions: bool,
    /// Still islands fall asleep ([`SleepSettings`](crate::settings::SleepSettings)).
    pub sleeping: bool,
}

impl Default for Effects {
    /// Everything but wind (a scene has to ask for a wind field).
    fn default() -> Self {
        Self {
            wind: false,
            ..Self::ALL
        }
    }
}

impl Effects {
    /// Only free flight under gravity: no contacts, no drag, no sleeping.
    pub const FREE_FLIGHT: Effects = Effects {
        gravity: true,
        damping: false,
        wind: false,
        global_force: false,
        friction: false,
        restitution: false,
        rotation: true,
        collisions: false,
        sleeping: false,
    };

    /// Every effect on.
    pub const ALL: Effects = Effects {
        gravity: true,
        damping: true,
        wind: true,
        global_force: true,
        friction: true,
        restitution: true,
        rotation: true,
        collisions: true,
        sleeping: true,
    };

    /// The effects by name, for tables and panels.
    pub fn toggles(&mut self) -> [(&'static str, &mut bool); 9] {
        [
            ("gravity", &mut self.gravity),
            ("damping", &mut self.damping),
            ("wind", &mut self.wind),
            ("global force", &mut self.global_force),
            ("friction", &mut self.friction),
            ("restitution", &mut self.restitution),
            ("rotation", &mut self.rotation),
            ("collisions", &mut self.collisions),
            ("sleeping", &mut self.sleeping),
        ]
    }
}

/// Run condition: the effect picked by `f` is on.
pub fn effect(f: fn(&Effects) -> bool) -> impl Fn(Res<Effects>) -> bool + Clone {
    move |effects: Res<Effects>| f(&effects)
}

/// A uniform wind: bodies are dragged towards `velocity` with coefficient `drag` (1/s),
/// a = drag·(wind − v). `gust` > 0 makes it gust: the wind speed swings by that fraction
/// at `gust_hz`.
#[derive(Resource, Reflect, Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[reflect(Resource)]
#[serde(default, deny_unknown_fields)]
pub struct Wind {
    /// The wind's velocity, m/s (world). Default (4, 0, 0).
    pub velocity: Vec3,
    /// Drag coefficient towards the wind's velocity, 1/s. Default 0.2.
    pub drag: f32,
    /// How far the wind speed swings, as a fraction of `velocity`, 0..=10. Default 0
    /// (steady).
    pub gust: f32,
    /// Frequency of the gusts, Hz. Default 0.5.
    pub gust_hz: f32,
}

impl Default for Wind {
    fn default() -> Self {
        Self {
            velocity: Vec3::new(4.0, 0.0, 0.0),
            drag: 0.2,
            gust: 0.0,
            gust_hz: 0.5,
        }
    }
}

impl Wind {
    /// The wind velocity at time `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.velocity * (1.0 + self.gust * (std::f32::consts::TAU * self.gust_hz * t).sin())
    }
}

/// Scales gravity for one body: 0 floats, −1 falls up. Default 1.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct GravityScale(pub f32);

/// The body never turns: no angular integration, zero angular velocity, infinite inertia
/// in contacts.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub struct LockRotation;

impl Wind {
    /// Velocity within ±[`MAX_SPEED`](crate::limits::MAX_SPEED), drag and gust rate
    /// finite and ≥ 0, gust fraction within 0..=10.
    pub fn check(&self) -> Result<(), crate::limits::Invalid> {
        use crate::limits::{MAX_RATE, MAX_SPEED, scalar, vector};
        vector("velocity", self.velocity, MAX_SPEED)?;
        scalar("drag", self.drag, 0.0..=MAX_RATE)?;
        scalar("gust", self.gust, 0.0..=10.0)?;
        scalar("gust_hz", self.gust_hz, 0.0..=MAX_RATE)?;
        Ok(())
    }
}

impl GravityScale {
    /// Finite, within ±[`MAX_COEFFICIENT`](crate::limits::MAX_COEFFICIENT).
    pub fn check(&self) -> Result<(), crate::limits::Invalid> {
        let max = crate::limits::MAX_COEFFICIENT;
        crate::limits::scalar("GravityScale", self.0, -max..=max)
    }
}
