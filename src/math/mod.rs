//! The step's math, as plain functions without Bevy's ECS: one substep of free motion
//! under each [`Integrator`] (how each composes with the contact solve is told in the
//! integrate stage), the closed-form ballistic step, the gyroscopic midpoint solve, and
//! the soft-step spring coefficients ([`Softness`]). The integrate and solve stages both
//! use them; neither imports the other.

mod ballistic;
pub(crate) mod block_ldl;
#[cfg(test)]
mod block_ldl_tests;
mod explicit_euler;
mod frames;
mod gyroscopic;
pub(crate) mod lanes;
mod principal;
mod rk4;
pub(crate) mod semi_implicit;
mod softness;

use bevy::prelude::*;

use crate::body::RigidBody;
use crate::settings::Integrator;

pub use ballistic::ballistic;
pub use frames::to_parent_frame;
pub use gyroscopic::{is_isotropic_moments, solve_gyroscopic_midpoint};
pub use principal::{part_tensor, principal_axes};
pub use softness::Softness;

/// One substep of free motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeStep {
    /// Position increment.
    pub dx: Vec3,
    /// Orientation at the end of the substep.
    pub q: Quat,
    /// Velocities at the end of the substep.
    pub v: Vec3,
    pub w: Vec3,
}

/// Accelerations and torques on a body from gravity, user forces and drag.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ForceModel {
    /// Constant part of the linear acceleration: gravity + force/mass.
    pub accel: Vec3,
    /// World-frame torque, N·m.
    pub torque: Vec3,
    /// Linear drag coefficient c: a −= c·v.
    pub linear_damping: f32,
    /// Angular drag coefficient: α −= c·ω.
    pub angular_damping: f32,
}

/// What the integrators need to know about a body besides its state.
#[derive(Clone, Copy, Debug)]
pub struct Inertial<'a> {
    pub forces: &'a ForceModel,
    /// Principal moments (body frame) and their inverses.
    pub inertia: Vec3,
    pub inv_inertia: Vec3,
    pub rotation_locked: bool,
}

/// Advances the free motion of one body by `h` from orientation `q`, velocities `v`, `w`.
/// Kinematic bodies move with constant velocity whatever the integrator; a body whose
/// rotation is locked runs no angular integration at all.
#[inline]
pub fn free_substep(
    integrator: Integrator,
    kind: RigidBody,
    body: Inertial,
    q: Quat,
    v: Vec3,
    w: Vec3,
    h: f32,
) -> FreeStep {
    if kind != RigidBody::Dynamic {
        return FreeStep {
            dx: v * h,
            q: rotate(q, w, h),
            v,
            w,
        };
    }
    let f = body.forces;
    let (dx, v) = linear_substep(integrator, f, v, h);
    // Locked, or not turning and no torque: the angular state stays exactly as it is
    // for every integrator (α = 0), so none of the angular math runs.
    let (q, w) = if body.rotation_locked || (w == Vec3::ZERO && f.torque == Vec3::ZERO) {
        (q, Vec3::ZERO)
    } else {
        match integrator {
            Integrator::ExplicitEuler => explicit_euler::angular(&body, q, w, h),
            Integrator::SemiImplicitEuler => semi_implicit::angular(&body, q, w, h),
            Integrator::Rk4 => rk4::angular(&body, q, w, h),
        }
    };
    FreeStep { dx, q, v, w }
}

/// One substep of the linear motion alone: position increment and end velocity.
#[inline]
pub fn linear_substep(integrator: Integrator, f: &ForceModel, v: Vec3, h: f32) -> (Vec3, Vec3) {
    match integrator {
        Integrator::ExplicitEuler => explicit_euler::linear(f, v, h),
        Integrator::SemiImplicitEuler => semi_implicit::linear(f, v, h),
        Integrator::Rk4 => rk4::linear(f, v, h),
    }
}

/// q + h·½(0, ω)⊗q, renormalised: the first-order quaternion update.
pub fn rotate(q: Quat, w: Vec3, h: f32) -> Quat {
    let dq = Quat::from_xyzw(w.x, w.y, w.z, 0.0) * q;
    (q + dq * (0.5 * h)).normalize()
}

/// Angular acceleration in the world frame from torque, gyroscopic term and drag:
/// α = I⁻¹(τ − ω × Iω) − c·ω, with I = R·I_body·Rᵀ.
pub fn angular_accel(body: &Inertial, q: Quat, w: Vec3) -> Vec3 {
    let wb = q.inverse() * w;
    let tb = q.inverse() * body.forces.torque;
    let ab = body.inv_inertia * (tb - wb.cross(body.inertia * wb));
    q * ab - body.forces.angular_damping * w
}

/// Linear acceleration: gravity + force/m − c·v.
pub fn linear_accel(forces: &ForceModel, v: Vec3) -> Vec3 {
    forces.accel - forces.linear_damping * v
}
