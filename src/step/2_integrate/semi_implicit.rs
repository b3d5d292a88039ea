//! Semi-implicit (symplectic) Euler: velocities first, then positions with the new
//! velocities. Drag is taken implicitly, v' = (v + h·a)/(1 + h·c), so it is stable for any
//! drag coefficient. Rotation solves Euler's equations with the implicit midpoint rule
//! (see [`super::gyroscopic`]), which keeps |L| and kinetic energy of a free spinning body.

use bevy::prelude::*;

use super::{FreeStep, Inertial, rotate, solve_gyroscopic_midpoint};

pub fn step(body: Inertial, q: Quat, v: Vec3, w: Vec3, h: f32) -> FreeStep {
    let f = body.forces;
    let v = (v + f.accel * h) / (1.0 + h * f.linear_damping);
    let wb = q.inverse() * w;
    let tb = q.inverse() * f.torque;
    let wb = solve_gyroscopic_midpoint(body.inertia, wb, tb, h);
    let w = (q * wb) / (1.0 + h * f.angular_damping);
    FreeStep {
        dx: v * h,
        q: rotate(q, w, h),
        v,
        w,
    }
}
