//! Stage 6, writeback: the solver arrays back into `Transform` and `Velocity`.
//! A body whose state became non-finite is frozen where it was and reported, so a
//! blow-up never reaches the ECS or other bodies' next step.

use bevy::prelude::*;

use crate::body::{PhysicsRejected, RigidBody, Velocity};
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
