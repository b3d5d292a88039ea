//! Explicit (forward) Euler, the 2015 engine's method: every update uses the state at the
//! start of the substep. x += h·v, v += h·a(v); q += h·q̇(ω), and Euler's equations in the
//! body frame, ω_b += h·I⁻¹(τ_b − ω_b × Iω_b), all from the old state.
//!
//! First order. Each step adds ½h²·α·Iα of kinetic energy to a free spinning body, so it
//! gains energy without bound: the seed engine's known failure, kept here to show it.
//! (Written with the world-frame inertia instead, the same method loses energy; the
//! textbook body-frame form is the one we keep.)

use bevy::prelude::*;

use super::ForceModel;
use super::{Inertial, linear_accel, rotate};

pub fn linear(f: &ForceModel, v: Vec3, h: f32) -> (Vec3, Vec3) {
    (v * h, v + linear_accel(f, v) * h)
}

pub fn angular(body: &Inertial, q: Quat, w: Vec3, h: f32) -> (Quat, Vec3) {
    let f = body.forces;
    let wb = q.inverse() * w;
    let tb = q.inverse() * f.torque;
    let alpha = body.inv_inertia * (tb - wb.cross(body.inertia * wb)) - f.angular_damping * wb;
    let q_new = rotate(q, w, h);
    (q_new, q_new * (wb + alpha * h))
}
