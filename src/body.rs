//! The components that make an entity a rigid body.
//!
//! A body is an entity with a `Transform`, a [`RigidBody`] kind and (usually) a
//! [`Collider`](crate::collider::Collider). An entity with a `Collider` and no `RigidBody`
//! is a static collider. Material and mass components are optional; their defaults are
//! documented on each type.

use bevy::prelude::*;

/// How a body takes part in the simulation.
#[derive(
    Component,
    Reflect,
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
)]
#[reflect(Component)]
#[require(Transform, Velocity, SleepTimer)]
pub enum RigidBody {
    /// Moved by forces and contacts; its mass comes from [`Mass`] or the collider's volume.
    #[default]
    Dynamic,
    /// Never moves; infinite mass. Same as a collider without `RigidBody`.
    Static,
    /// Moves with its [`Velocity`] exactly, pushes dynamic bodies, is never pushed back.
    Kinematic,
}

/// Linear (m/s) and angular (rad/s) velocity, both in the world frame.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct Velocity {
    /// Velocity of the centre of mass, m/s.
    pub linear: Vec3,
    /// Angular velocity, rad/s (axis × rate).
    pub angular: Vec3,
}

impl Velocity {
    /// At rest.
    pub const ZERO: Self = Self {
        linear: Vec3::ZERO,
        angular: Vec3::ZERO,
    };

    /// Moving at `linear` m/s without turning.
    pub fn linear(linear: Vec3) -> Self {
        Self {
            linear,
            angular: Vec3::ZERO,
        }
    }
}

/// Mass in kg. The inertia tensor follows from the collider's shape (solid sphere, solid
/// box). Without `Mass`, the collider's volume times [`DEFAULT_DENSITY`] gives the mass.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct Mass(pub f32);

/// Density used when a dynamic body has no [`Mass`]: water, 1000 kg/m³.
pub const DEFAULT_DENSITY: f32 = 1000.0;

/// Coefficient of restitution, 0 (no bounce) to 1 (elastic). Default 0.
///
/// Two bodies combine by **max**: a bouncy ball bounces on any floor. Bounces slower than
/// [`SolverSettings::restitution_threshold`](crate::settings::SolverSettings) are treated
/// as inelastic so resting contacts stay at rest.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct Restitution(pub f32);

/// Coulomb friction coefficient μ. Default 0.5.
///
/// Two bodies combine by the **geometric mean** √(μa·μb): ice (0) on anything is frictionless.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct Friction(pub f32);

/// Friction when a body has no [`Friction`] component.
pub const DEFAULT_FRICTION: f32 = 0.5;

/// How two colliders' coefficients combine into the pair's. When the two colliders ask
/// for different rules, the one later in this list wins (as in PhysX and rapier), so
/// `Max` on either side gives the larger coefficient.
#[derive(Reflect, Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CoefficientCombine {
    /// (a + b) / 2: avian3d's and rapier's default for both.
    Average,
    /// √(a·b): tumble's default for friction (ice, 0, on anything is frictionless).
    #[default]
    GeometricMean,
    /// min(a, b).
    Min,
    /// a·b.
    Multiply,
    /// tumble's default for restitution (a bouncy ball bounces on any floor).
    Max,
}

impl CoefficientCombine {
    /// The rule of a pair whose colliders ask for `self` and `other`.
    pub fn pair(self, other: Self) -> Self {
        self.max(other)
    }

    /// Combines two coefficients.
    pub fn apply(self, a: f32, b: f32) -> f32 {
        match self {
            Self::Average => 0.5 * (a + b),
            Self::GeometricMean => (a * b).max(0.0).sqrt(),
            Self::Min => a.min(b),
            Self::Multiply => a * b,
            Self::Max => a.max(b),
        }
    }
}

/// The rule this collider asks for when its [`Friction`] meets another's. Default
/// [`CoefficientCombine::GeometricMean`].
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq, Eq)]
#[reflect(Component)]
pub struct FrictionCombine(pub CoefficientCombine);

/// The rule this collider asks for when its [`Restitution`] meets another's. Default
/// [`CoefficientCombine::Max`].
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq, Eq)]
#[reflect(Component)]
pub struct RestitutionCombine(pub CoefficientCombine);

/// Density of a body's collider, kg/m³, for its mass when it has no [`Mass`]
/// (default [`DEFAULT_DENSITY`], water; avian3d's default is 1 kg/m³, rapier's 1 too).
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct ColliderDensity(pub f32);

/// Principal moments of inertia, kg·m², in the body's frame, instead of those of its
/// collider's solid shape (a hollow shell, a weighted wheel).
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct AngularInertia(pub Vec3);

/// Where a dynamic body's centre of mass sits in its own frame, m (default: the origin,
/// the collider's centre): a car's low centre, a self-righting toy. The body turns about
/// it, gravity pulls at it, and its [`Velocity`] is that of this point. The mass and the
/// inertia (about this point) stay those of the shape or of [`Mass`] and
/// [`AngularInertia`]; the offset moves no mass (as avian3d's `CenterOfMass`).
/// Kinematic and static bodies ignore it.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct CenterOfMass(pub Vec3);

impl CenterOfMass {
    /// The centre of mass in the world for a body at `tf`, m: for
    /// [`ExternalForce::at_point`] and [`ExternalImpulse::at_point`].
    pub fn world(&self, tf: &Transform) -> Vec3 {
        tf.translation + tf.rotation * self.0
    }
}

/// A force (N) and torque (N·m) in the world frame applied at the centre of mass on every
/// step until changed. Set it back to zero to stop pushing.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct ExternalForce {
    /// Force at the centre of mass, N, world frame.
    pub force: Vec3,
    /// Torque, N·m, world frame.
    pub torque: Vec3,
}

impl ExternalForce {
    /// A force (N) at the centre of mass.
    pub fn new(force: Vec3) -> Self {
        Self {
            force,
            torque: Vec3::ZERO,
        }
    }

    /// A force (N) applied at a world `point` of a body whose centre of mass is at
    /// `center` (its `Transform::translation`): the force, and the torque
    /// (point − center) × force, so a push off-centre also turns the body.
    pub fn at_point(force: Vec3, point: Vec3, center: Vec3) -> Self {
        Self {
            force,
            torque: (point - center).cross(force),
        }
    }

    /// Adds a force (N) at a world `point` (see [`at_point`](Self::at_point)).
    pub fn apply_at_point(&mut self, force: Vec3, point: Vec3, center: Vec3) -> &mut Self {
        let f = Self::at_point(force, point, center);
        self.force += f.force;
        self.torque += f.torque;
        self
    }
}

/// A one-shot impulse (N·s) and angular impulse (N·m·s), world frame: at the start of
/// the next physics step the body's velocity changes by `impulse / m` and its angular
/// velocity by `I⁻¹ · torque_impulse`, and the component is zeroed. Impulses added in
/// frames that run no step add up until one does; under any frame pacing each is applied
/// exactly once. It wakes a sleeping body. Static and kinematic bodies ignore it; a
/// non-finite impulse, or one that would take the body past the speed limits, is logged
/// and dropped.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct ExternalImpulse {
    /// Impulse at the centre of mass, N·s, world frame.
    pub impulse: Vec3,
    /// Angular impulse, N·m·s, world frame.
    pub torque_impulse: Vec3,
}

impl ExternalImpulse {
    /// An impulse (N·s) at the centre of mass: a jump, a shot.
    pub fn new(impulse: Vec3) -> Self {
        Self {
            impulse,
            torque_impulse: Vec3::ZERO,
        }
    }

    /// An impulse (N·s) at a world `point` of a body whose centre of mass is at `center`:
    /// the impulse, and the angular impulse (point − center) × impulse.
    pub fn at_point(impulse: Vec3, point: Vec3, center: Vec3) -> Self {
        Self {
            impulse,
            torque_impulse: (point - center).cross(impulse),
        }
    }

    /// Adds an impulse (N·s) at the centre of mass.
    pub fn apply(&mut self, impulse: Vec3) -> &mut Self {
        self.impulse += impulse;
        self
    }

    /// Adds an impulse (N·s) at a world `point` (see [`at_point`](Self::at_point)).
    pub fn apply_at_point(&mut self, impulse: Vec3, point: Vec3, center: Vec3) -> &mut Self {
        let j = Self::at_point(impulse, point, center);
        self.impulse += j.impulse;
        self.torque_impulse += j.torque_impulse;
        self
    }

    /// Whether there is anything to apply.
    pub fn is_zero(&self) -> bool {
        self.impulse == Vec3::ZERO && self.torque_impulse == Vec3::ZERO
    }
}

/// Linear drag: acceleration −c·v (c in 1/s). Terminal velocity under gravity is g/c.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct LinearDamping(pub f32);

/// Angular drag: angular acceleration −c·ω (c in 1/s).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct AngularDamping(pub f32);

/// Inserted on a body that was left out of the simulation because its input was invalid
/// (a non-finite transform or velocity, a non-positive mass or size) or because it became
/// non-finite during a step. The body is frozen where it was; the message says why.
/// Remove the component after fixing the input to bring the body back.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct PhysicsRejected {
    /// The offending field, e.g. `"Transform.translation"` or `"Mass"`.
    pub field: &'static str,
    /// What was wrong with it, with the value.
    pub reason: String,
}

/// Marks a body that is asleep: it keeps its place and costs only a wake check. Tumble adds
/// and removes it (see [`SleepSettings`](crate::settings::SleepSettings)); remove it to
/// wake a body, insert `Sleeping` to start one asleep. Changing a sleeping
/// body's `Transform`, `Velocity` or `ExternalForce` wakes it.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sleeping;

/// Tumble's bookkeeping: when this collider first appeared, counting every collider
/// ever added. The step visits pairs of colliders in this order, so the physics of a
/// scene does not depend on where its entities sit in the ECS tables, on recycled entity
/// ids, or on what else was spawned and despawned meanwhile. Added by tumble.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SpawnOrder(pub(crate) u64);

impl SpawnOrder {
    /// The collider's place in the order (0 for the first collider ever added).
    pub fn get(self) -> u64 {
        self.0
    }
}

/// How long (s) a body has been slow enough to sleep. Kept by tumble: read it, don't
/// write it (to wake a body, remove [`Sleeping`]; to keep one awake, move it).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct SleepTimer(pub(crate) f32);

impl SleepTimer {
    /// Seconds the body has been still.
    pub fn seconds(self) -> f32 {
        self.0
    }
}
