//! Classic fourth-order Runge–Kutta on the full free-motion state (x, q, v, ω): position,
//! unit-quaternion orientation, linear and angular velocity. Each stage evaluates gravity,
//! user forces, drag and Euler's equations (with the gyroscopic term ω × Iω, world inertia
//! R·I·Rᵀ) on the stage state. The orientation is renormalised at the end.

use bevy::prelude::*;

use super::{FreeStep, Inertial, angular_accel, linear_accel};

#[derive(Clone, Copy)]
struct Deriv {
    dx: Vec3,
    dq: Quat,
    dv: Vec3,
    dw: Vec3,
}

fn deriv(body: &Inertial, q: Quat, v: Vec3, w: Vec3) -> Deriv {
    Deriv {
        dx: v,
        dq: Quat::from_xyzw(w.x, w.y, w.z, 0.0) * q * 0.5,
        dv: linear_accel(body.forces, v),
        dw: angular_accel(body, q, w),
    }
}

pub fn step(body: Inertial, q: Quat, v: Vec3, w: Vec3, h: f32) -> FreeStep {
    let stage = |d: &Deriv, s: f32| ((q + d.dq * s).normalize(), v + d.dv * s, w + d.dw * s);
    let k1 = deriv(&body, q, v, w);
    let (q2, v2, w2) = stage(&k1, 0.5 * h);
    let k2 = deriv(&body, q2, v2, w2);
    let (q3, v3, w3) = stage(&k2, 0.5 * h);
    let k3 = deriv(&body, q3, v3, w3);
    let (q4, v4, w4) = stage(&k3, h);
    let k4 = deriv(&body, q4, v4, w4);
    let sixth = h / 6.0;
    FreeStep {
        dx: (k1.dx + 2.0 * k2.dx + 2.0 * k3.dx + k4.dx) * sixth,
        q: (q + (k1.dq + k2.dq * 2.0 + k3.dq * 2.0 + k4.dq) * sixth).normalize(),
        v: v + (k1.dv + 2.0 * k2.dv + 2.0 * k3.dv + k4.dv) * sixth,
        w: w + (k1.dw + 2.0 * k2.dw + 2.0 * k3.dw + k4.dw) * sixth,
    }
}
