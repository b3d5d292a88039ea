//! What a joint did in the last step: the force and torque its accumulated impulses
//! applied to B, read back after the solve (for `JointForces`, breakable joints and the
//! stiffness of the next step).

use bevy::prelude::*;

use super::joint::{now, spherical_torque};
use crate::world::{JointConstraint, JointRows, SolverBody, body};

/// Each joint's force (on B, N, world) and torque (N·m) in the last substep of `h` s,
/// and the substep its impulses are per.
pub fn store_joint_forces(joints: &mut [JointConstraint], bodies: &[SolverBody], h: f32) {
    for j in joints.iter_mut() {
        (j.force, j.torque) = joint_force(j, bodies, h);
        j.h = h;
    }
}

fn joint_force(j: &JointConstraint, bodies: &[SolverBody], h: f32) -> (Vec3, Vec3) {
    let (a, b) = (body(bodies, j.a), body(bodies, j.b));
    let f = now(j, &a, &b);
    let axial = j.axial[0] + j.axial[1] - j.axial[2];
    let (mut force, mut torque) = (j.linear, j.angular);
    match j.rows {
        JointRows::Revolute => torque += f.axis * axial,
        JointRows::Spherical => torque += spherical_torque(j, &b, f.axis),
        JointRows::Prismatic => force += f.axis * axial,
        JointRows::Distance => force += f.d.normalize_or(f.axis) * axial,
        JointRows::Fixed => {}
    }
    (force / h, torque / h)
}
