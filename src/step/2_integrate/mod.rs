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

use bevy::prelude::*;

use crate::math::{Inertial, ballistic, free_substep, linear_substep, semi_implicit};
use crate::settings::{Integrator, SolverSettings};
use crate::world::PhysicsWorld;

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
        if *integrator == Integrator::SemiImplicitEuler
            && body.is_dynamic()
            && !body.rotation_locked
        {
            // Linear and angular motion are independent here: the linear substeps, then
            // the angular ones with the spin kept in the body frame throughout.
            let (dp, v) = (0..n).fold((Vec3::ZERO, body.v0), |(dp, v), _| {
                let (dx, v) = linear_substep(*integrator, f, v, h);
                (dp + dx, v)
            });
            let (q, w) =
                semi_implicit::angular_substeps(&Inertial::of(body), body.q0, body.w0, h, n);
            sb.dp = dp;
            sb.dq = (q * body.q0.inverse()).normalize();
            sb.v = v.clamp_length_max(settings.max_linear_speed);
            sb.w = w;
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
