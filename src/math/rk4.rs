//! Classic fourth-order Runge–Kutta on the free motion. Translation and rotation are
//! independent here (forces don't depend on orientation, torques don't depend on position),
//! so each runs its own four stages: (x, v) with gravity, user forces and drag; (q, ω)
//! with Euler's equations — gyroscopic term ω × Iω, world inertia R·I·Rᵀ — on the stage
//! orientation, renormalised at every stage and at the end.

use bevy::prelude::*;

use super::ForceModel;
use super::{Inertial, angular_accel, linear_accel};

pub fn linear(f: &ForceModel, v: Vec3, h: f32) -> (Vec3, Vec3) {
    let a1 = linear_accel(f, v);
    let v2 = v + a1 * (0.5 * h);
    let a2 = linear_accel(f, v2);
    let v3 = v + a2 * (0.5 * h);
    let a3 = linear_accel(f, v3);
    let v4 = v + a3 * h;
    let a4 = linear_accel(f, v4);
    let sixth = h / 6.0;
    (
        (v + 2.0 * v2 + 2.0 * v3 + v4) * sixth,
        v + (a1 + 2.0 * a2 + 2.0 * a3 + a4) * sixth,
    )
}

pub fn angular(body: &Inertial, q: Quat, w: Vec3, h: f32) -> (Quat, Vec3) {
    let qdot = |q: Quat, w: Vec3| Quat::from_xyzw(w.x, w.y, w.z, 0.0) * q * 0.5;
    let (dq1, dw1) = (qdot(q, w), angular_accel(body, q, w));
    let (q2, w2) = ((q + dq1 * (0.5 * h)).normalize(), w + dw1 * (0.5 * h));
    let (dq2, dw2) = (qdot(q2, w2), angular_accel(body, q2, w2));
    let (q3, w3) = ((q + dq2 * (0.5 * h)).normalize(), w + dw2 * (0.5 * h));
    let (dq3, dw3) = (qdot(q3, w3), angular_accel(body, q3, w3));
    let (q4, w4) = ((q + dq3 * h).normalize(), w + dw3 * h);
    let (dq4, dw4) = (qdot(q4, w4), angular_accel(body, q4, w4));
    let sixth = h / 6.0;
    (
        (q + (dq1 + dq2 * 2.0 + dq3 * 2.0 + dq4) * sixth).normalize(),
        w + (dw1 + 2.0 * dw2 + 2.0 * dw3 + dw4) * sixth,
    )
}
