//! Stage 6, writeback: the solver arrays back into `Transform` and `Velocity`, and the
//! joints' forces into [`JointForces`].
//! A body whose state became non-finite is frozen where it was and reported, so a
//! blow-up never reaches the ECS or other bodies' next step.

use bevy::prelude::*;

use crate::body::{PhysicsRejected, RigidBody, Velocity};
use crate::joint::{Joint, JointBroken, JointForces};
use crate::math::to_parent_frame;
use crate::world::{KinematicPose, PhysicsWorld};

pub fn writeback_bodies(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    mut query: Query<(&mut Transform, &mut Velocity)>,
) {
    let world = &mut *world;
    world.step_count += 1;
    for i in 0..world.bodies.len() {
        let body = world.bodies[i];
        if body.kind == RigidBody::Static {
            continue;
        }
        let Ok((mut tf, mut vel)) = query.get_mut(body.entity) else {
            continue;
        };
        let (pos, rot) = world.body_pose(i);
        let s = &world.solver_bodies[i];
        if !(pos.is_finite() && rot.is_finite() && s.v.is_finite() && s.w.is_finite()) {
            error!(
                "tumble: body {} became non-finite during step {}; frozen",
                body.entity, world.step_count
            );
            commands.entity(body.entity).insert(PhysicsRejected {
                field: "Transform",
                reason: format!("non-finite state after step {}", world.step_count),
            });
            // Frozen at rest without counting as the user's edit, which would readmit it.
            *vel.bypass_change_detection() = Velocity::ZERO;
            continue;
        }
        // The solver's pose is the principal frame's at the centre of mass.
        let f = world.body_frames[i];
        let rot = if f.frame == Quat::IDENTITY {
            rot
        } else {
            (rot * f.frame.inverse()).normalize()
        };
        let origin = if f.com == Vec3::ZERO {
            pos
        } else {
            pos - rot * f.com
        };
        (tf.translation, tf.rotation) = match world.parent_frames.get(f.parent as usize) {
            Some(frame) => to_parent_frame(frame, origin, rot),
            None => (origin, rot),
        };
        vel.linear = s.v;
        vel.angular = s.w;
        if body.kind == RigidBody::Kinematic {
            let (driven, target) = (body.driven, body.target);
            let pose = KinematicPose {
                pos,
                rot,
                driven,
                target,
            };
            world.kinematic_poses.insert(body.entity, pose);
        }
    }
}

/// Each joint's state back on its entity ([`JointForces`]: the force and torque it
/// applied, and the impulses next step warm starts from); a joint whose force passed its
/// [`Joint::break_force`] breaks: its `Joint` is removed and [`JointBroken`] sent and
/// triggered on it. A scene without joints returns at once.
pub fn writeback_joints(
    mut commands: Commands,
    world: Res<PhysicsWorld>,
    mut joints: Query<(&Joint, &mut JointForces)>,
    mut broken: MessageWriter<JointBroken>,
) {
    for j in &world.joints {
        let Ok((joint, mut forces)) = joints.get_mut(j.entity) else {
            continue;
        };
        let state = &mut forces.state;
        (state.linear, state.angular, state.axial, state.h) = (j.linear, j.angular, j.axial, j.h);
        (forces.force, forces.torque) = (j.force, j.torque);
        let force = j.force.length();
        if force > joint.break_force {
            let event = JointBroken {
                entity: j.entity,
                body1: joint.body1,
                body2: joint.body2,
                force,
            };
            broken.write(event);
            commands.trigger(event);
            commands.entity(j.entity).remove::<Joint>();
        }
    }
}
