//! Explicit (forward) Euler, the 2015 engine's method: every update uses the state at the
//! start of the substep. x += h·v, q += h·q̇(ω), then v += h·a(v), ω += h·α(q, ω).
//! First order; the explicit gyroscopic term makes a spinning body gain energy.

use bevy::prelude::*;

use super::{FreeStep, Inertial, angular_accel, linear_accel, rotate};

pub fn step(body: Inertial, q: Quat, v: Vec3, w: Vec3, h: f32) -> FreeStep {
    FreeStep {
        dx: v * h,
        q: rotate(q, w, h),
        v: v + linear_accel(body.forces, v) * h,
        w: w + angular_accel(&body, q, w) * h,
    }
}
