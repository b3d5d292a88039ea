//! Stage 2, integrate: advance every body's free motion (no contacts) over the step with
//! the selected [`Integrator`], in `substeps` substeps of h/substeps.
//!
//! ## How each integrator composes with the contact solve
//! The free motion of one substep is a [`FreeStep`]: a position increment, a rotation and
//! the end velocities. Bodies that touch nothing keep the result of this stage. Bodies in
//! contact are re-run by the solver (stage 5) from the start of the step, substep by
//! substep: it takes the [`FreeStep`]'s velocities, applies contact impulses Δv, Δω, and
//! then moves the body by the free increment plus the impulse's correction h·Δv
//! (rotation: h·Δω). So contacts are velocity impulses for every integrator:
//! - semi-implicit Euler: increment = h·v_new, so the body moves by h·(v_new + Δv) — the
//!   usual symplectic step with the contact velocity;
//! - explicit Euler: increment = h·v_old, so the body moves by h·v_old + h·Δv — the seed
//!   engine's method with contact impulses applied as they happen;
//! - RK4: the four-stage free motion plus h·Δv. Fourth order away from contacts, first order
//!   across a contact event (an impulse is a discontinuity).

mod ballistic;
mod explicit_euler;
mod gyroscopic;
mod rk4;
mod semi_implicit;

use bevy::prelude::*;

use crate::body::RigidBody;
use crate::settings::{Integrator, SolverSettings};
use crate::world::{BodyState, ForceModel, PhysicsWorld};

pub use ballistic::ballistic;
pub use gyroscopic::solve_gyroscopic_midpoint;

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

/// What the integrators need to know about a body besides its state.
#[derive(Clone, Copy, Debug)]
pub struct Inertial<'a> {
    pub forces: &'a ForceModel,
    /// Principal moments (body frame) and their inverses.
    pub inertia: Vec3,
    pub inv_inertia: Vec3,
    pub rotation_locked: bool,
}

impl<'a> Inertial<'a> {
    pub fn of(body: &'a BodyState) -> Self {
        Self {
            forces: &body.forces,
            inertia: body.inertia,
            inv_inertia: body.inv_inertia,
            rotation_locked: body.rotation_locked,
        }
    }
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

/// Runs the free motion of every body over the whole step. Bodies in contact are
/// re-integrated with their contacts by the solver; all others keep this result.
pub fn integrate_free_motion(
    mut world: ResMut<PhysicsWorld>,
    integrator: Res<Integrator>,
    settings: Res<SolverSettings>,
) {
    let world = &mut *world;
    let n = settings.substeps.max(1);
    let h = world.dt / n as f32;
    for (body, sb) in world.bodies.iter().zip(world.solver_bodies.iter_mut()) {
        let f = &body.forces;
        let still = body.rotation_locked || (body.w0 == Vec3::ZERO && f.torque == Vec3::ZERO);
        if body.is_dynamic() && still {
            // Not turning: constant acceleration has a closed form; with drag, only the
            // linear substeps run.
            let (dp, v) = if f.linear_damping == 0.0 {
                ballistic(*integrator, body.v0, f.accel, h, n)
            } else {
                (0..n).fold((Vec3::ZERO, body.v0), |(dp, v), _| {
                    let (dx, v) = linear_substep(*integrator, f, v, h);
                    (dp + dx, v)
                })
            };
            sb.dp = dp;
            sb.dq = Quat::IDENTITY;
            sb.v = v.clamp_length_max(settings.max_linear_speed);
            sb.w = Vec3::ZERO;
            continue;
        }
        let (mut dp, mut q, mut v, mut w) = (Vec3::ZERO, body.q0, body.v0, body.w0);
        for _ in 0..n {
            let fs = free_substep(*integrator, body.kind, Inertial::of(body), q, v, w, h);
            dp += fs.dx;
            (q, v, w) = (fs.q, fs.v, fs.w);
        }
        sb.dp = dp;
        sb.dq = (q * body.q0.inverse()).normalize();
        sb.v = v.clamp_length_max(settings.max_linear_speed);
        sb.w = w;
    }
}
