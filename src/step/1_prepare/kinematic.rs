//! Kinematic bodies driven by their `Transform`: the velocity that reaches the user's
//! pose over the steps left in the frame.

use bevy::prelude::*;

use crate::body::Velocity;
use crate::world::KinematicPose;

/// How a kinematic body moves this step.
pub(super) enum Drive {
    /// Toward the user's Transform (the pose given) from last step's pose, at this
    /// velocity.
    ToTarget(Velocity, (Vec3, Quat)),
    /// It was moved by its Transform last step and not since: it stops there.
    Stopped,
    /// Moved by its `Velocity`, as usual.
    ByVelocity,
}

/// Reads a kinematic body's Transform against the pose tumble wrote last step (`last`).
/// A change is the user's: the body travels there over `span` seconds (the steps left in
/// this frame), with the velocity that implies, so what stands on it is carried along.
/// Set it in `FixedUpdate` (before [`PhysicsSystems::Prepare`](crate::PhysicsSystems))
/// for motion as smooth as the game's: set in `Update` at a render rate above the step
/// rate, each step takes the moves of two or three frames, and the velocity follows that
/// beat (±25 % at 144 Hz).
/// No change while a frame's target is not reached yet: it carries on toward it. A move
/// faster than `max_speed` is a teleport: it goes there at once, with its own `Velocity`.
#[inline]
pub(super) fn drive_kinematic(
    last: &KinematicPose,
    tf: &Transform,
    span: f32,
    max_speed: f32,
) -> Drive {
    let unchanged = last.pos == tf.translation && last.rot == tf.rotation;
    let (goal_pos, goal_rot) = match (unchanged, last.target) {
        (false, _) => (tf.translation, tf.rotation.normalize()),
        (true, Some(target)) => target,
        (true, None) if last.driven => return Drive::Stopped,
        (true, None) => return Drive::ByVelocity,
    };
    let linear = (goal_pos - last.pos) / span;
    if !(linear.length() <= max_speed) || span <= 0.0 {
        return Drive::ByVelocity;
    }
    let mut turn = goal_rot * last.rot.inverse();
    if turn.w < 0.0 {
        turn = -turn;
    }
    let (axis, angle) = turn.to_axis_angle();
    let angular = if angle.is_finite() && axis.is_finite() {
        axis * (angle / span)
    } else {
        Vec3::ZERO
    };
    Drive::ToTarget(Velocity { linear, angular }, (goal_pos, goal_rot))
}
