//! Global simulation settings: gravity, the integrator, and the solver's knobs.

use bevy::prelude::*;

/// Uniform gravitational acceleration, m/s². Default (0, −9.81, 0).
#[derive(Resource, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Resource)]
pub struct Gravity(pub Vec3);

impl Default for Gravity {
    fn default() -> Self {
        Self(Vec3::new(0.0, -9.81, 0.0))
    }
}

/// A force (N) pushing every dynamic body, on top of gravity: the seed engine's
/// six-direction push. Zero by default; while it is non-zero nothing sleeps.
#[derive(Resource, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Resource)]
pub struct GlobalForce(pub Vec3);

/// The time integrator for the free motion (forces, drag, rotation). Switchable at run time.
///
/// Contacts are velocity impulses in every case; see `step/2_integrate` for how each
/// integrator composes with the contact solve.
#[derive(
    Resource,
    Reflect,
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
)]
#[reflect(Resource)]
pub enum Integrator {
    /// The 2015 engine's method: position from the old velocity, velocity from the old
    /// state. First order; gains energy on rotation and oscillation.
    ExplicitEuler,
    /// Symplectic Euler: velocity first, then position with the new velocity. First order,
    /// bounded energy. Rotation uses an implicit-midpoint gyroscopic solve.
    #[default]
    SemiImplicitEuler,
    /// Classic fourth-order Runge–Kutta on position, orientation, velocity and spin.
    Rk4,
}

impl Integrator {
    /// Every integrator, in declaration order.
    pub const ALL: [Integrator; 3] = [
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::Rk4,
    ];
}

/// The solver's knobs. Defaults follow the soft-step solver's usual numbers.
#[derive(Resource, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Resource)]
pub struct SolverSettings {
    /// Substeps per fixed step. Each substep integrates, solves contacts and relaxes.
    /// Free motion is integrated with the substep size h/substeps too. Contacts that
    /// need more (heavy loads, small bodies: see `max_sag`) take more, up to
    /// `max_substeps`.
    pub substeps: u32,
    /// The most substeps a step takes for stiff contacts (1..=64; at or below
    /// `substeps`, the count never adapts).
    pub max_substeps: u32,
    /// Resting sag each contact is tuned for, as a fraction of the smaller body's size
    /// (0.002: 2 mm for a 1 m box, 0.04 mm for a 2 cm cube). The stiffness this asks for
    /// beyond a quarter of the substep rate is what raises the substep count.
    pub max_sag: f32,
    /// Extra velocity iterations per substep (the soft step needs 1).
    pub iterations: u32,
    /// Contact stiffness as a frequency, Hz. Capped at a quarter of the substep rate.
    pub contact_hertz: f32,
    /// Contact damping ratio (heavily over-damped by default).
    pub contact_damping_ratio: f32,
    /// Fastest speed, m/s, at which overlapping bodies are pushed apart.
    pub max_push_out: f32,
    /// Normal approach speed, m/s, below which contacts don't bounce, at most: each step
    /// uses the lesser of this and twice the speed gravity adds in a step (what a resting
    /// contact approaches at), so in zero gravity every approach bounces. Default 1.
    pub restitution_threshold: f32,
    /// Contacts are created this far (m) before touching, on top of the distance the
    /// bodies can close in one step, so fast bodies don't tunnel. A pair whose thinner
    /// body is thinner than twice this uses half that body's thickness instead
    /// ([`SolverSettings::margin_for`]): a 1 cm marble's margin is 5 mm.
    pub speculative_margin: f32,
    /// Speeds are clamped to this (m/s) so a blow-up cannot run away.
    pub max_linear_speed: f32,
}

/// The speculative margin of a pair as a fraction of its thinner body's thickness, when
/// that is less than [`SolverSettings::speculative_margin`].
pub const MARGIN_OF_THICKNESS: f32 = 0.5;

/// How much deeper than it started a body may end a step in a fixed collider, as a
/// fraction of the speculative margin (5 mm at the default 2 cm): the sweep's tolerance.
pub const CONTINUOUS_SLOP: f32 = 0.25;

/// The most of its thinnest side a body may end a step deeper in a fixed collider than
/// it started: for small bodies this, not [`CONTINUOUS_SLOP`], sets the tolerance.
pub const SLOP_OF_THICKNESS: f32 = 0.1;

impl SolverSettings {
    /// The speculative margin, m, of a pair whose thinner body is `thickness` thick (a
    /// sphere's diameter, a box's thinnest side): the setting, or half the thickness
    /// when that is less. Everything measured against the margin (the sweep's trigger,
    /// the touching slop of collision events) scales with it.
    #[inline]
    pub fn margin_for(&self, thickness: f32) -> f32 {
        self.speculative_margin.min(MARGIN_OF_THICKNESS * thickness)
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            substeps: 4,
            max_substeps: 16,
            max_sag: 0.002,
            iterations: 1,
            contact_hertz: 30.0,
            contact_damping_ratio: 10.0,
            max_push_out: 3.0,
            restitution_threshold: 1.0,
            speculative_margin: 0.02,
            max_linear_speed: 400.0,
        }
    }
}

/// When bodies fall asleep. A body whose speed stays below `linear_threshold` (m/s) and
/// spin below `angular_threshold` (rad/s) for `time_to_sleep` seconds, together with every
/// body it touches, stops being integrated and solved until something touches or pushes
/// it, or its `Transform`, `Velocity` or `ExternalForce` is changed. The switch is
/// [`Effects::sleeping`](crate::effects::Effects).
#[derive(Resource, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Resource)]
pub struct SleepSettings {
    /// Speed below which a body counts as still, m/s. Default 0.05.
    pub linear_threshold: f32,
    /// Angular speed below which a body counts as still, rad/s. Default 0.05.
    pub angular_threshold: f32,
    /// How long every body of an island must stay still before it sleeps, s. Default 0.5.
    pub time_to_sleep: f32,
}

impl Default for SleepSettings {
    fn default() -> Self {
        Self {
            linear_threshold: 0.05,
            angular_threshold: 0.05,
            time_to_sleep: 0.5,
        }
    }
}

use crate::limits::{self, Invalid};

impl Gravity {
    /// Finite, each component within ±[`MAX_ACCELERATION`](limits::MAX_ACCELERATION).
    pub fn check(&self) -> Result<(), Invalid> {
        limits::vector("0", self.0, limits::MAX_ACCELERATION)
    }
}

impl GlobalForce {
    /// Finite, each component within ±[`MAX_FORCE`](limits::MAX_FORCE).
    pub fn check(&self) -> Result<(), Invalid> {
        limits::vector("0", self.0, limits::MAX_FORCE)
    }
}

impl SolverSettings {
    /// Every float field finite and in range. `substeps` and `iterations` are not
    /// refused but clamped ([`clamp_counts`](Self::clamp_counts)).
    pub fn check(&self) -> Result<(), Invalid> {
        use limits::{MAX_COEFFICIENT, MAX_RATE, MAX_SIZE, MAX_SPEED, positive, scalar};
        // Stiffness below 0.1 Hz or a speed cap below 1 m/s are not a contact or a cap.
        scalar("contact_hertz", self.contact_hertz, 0.1..=MAX_RATE)?;
        scalar(
            "contact_damping_ratio",
            self.contact_damping_ratio,
            0.0..=MAX_COEFFICIENT,
        )?;
        positive("max_push_out", self.max_push_out, MAX_SPEED)?;
        scalar(
            "restitution_threshold",
            self.restitution_threshold,
            0.0..=MAX_SPEED,
        )?;
        scalar(
            "speculative_margin",
            self.speculative_margin,
            0.0..=MAX_SIZE,
        )?;
        scalar("max_linear_speed", self.max_linear_speed, 1.0..=MAX_SPEED)?;
        positive("max_sag", self.max_sag, 1.0)?;
        Ok(())
    }

    /// `substeps` and `iterations` clamped into 1..=64. Returns what was clamped.
    pub fn clamp_counts(&mut self) -> Option<String> {
        let (s, m, i) = (self.substeps, self.max_substeps, self.iterations);
        let (lo, hi) = (*limits::SUBSTEPS.start(), *limits::SUBSTEPS.end());
        self.substeps = s.clamp(lo, hi);
        self.max_substeps = m.clamp(lo, hi);
        self.iterations = i.clamp(*limits::ITERATIONS.start(), *limits::ITERATIONS.end());
        ((s, m, i) != (self.substeps, self.max_substeps, self.iterations)).then(|| {
            format!(
                "substeps {s} → {}, max_substeps {m} → {}, iterations {i} → {} (each must \
                 be within 1..=64)",
                self.substeps, self.max_substeps, self.iterations
            )
        })
    }
}

impl SleepSettings {
    /// Thresholds and time finite and ≥ 0.
    pub fn check(&self) -> Result<(), Invalid> {
        use limits::{MAX_RATE, MAX_SPEED, scalar};
        scalar("linear_threshold", self.linear_threshold, 0.0..=MAX_SPEED)?;
        scalar("angular_threshold", self.angular_threshold, 0.0..=MAX_RATE)?;
        scalar("time_to_sleep", self.time_to_sleep, 0.0..=1.0e9)?;
        Ok(())
    }
}
