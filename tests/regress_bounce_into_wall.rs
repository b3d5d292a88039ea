//! Regression (found by `tests/random_scenes.rs`, seed 1): a 1.4 kg ball resting on the
//! floor 8 cm from a wall was hit toward the wall by a 56 kg ball (e = 0.62). It ended
//! the step 5 mm inside the wall still moving into it at 12.7 m/s, and sank 1.5 cm.
//!
//! Restitution runs last in a step, after the wall's contact has had its last word; the
//! heavy ball's bounce sent the light one into the wall after that. Fixed: after
//! restitution, contacts with fixed colliders that touch and still approach are stopped
//! (`stop_approach`); nothing is taken back, so a bounce off the wall itself stays.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_ball_knocked_into_a_wall_by_a_bounce_stops_at_it() {
    for speed in [5.0, 10.0, 20.0] {
        let mut app = app_without_gravity();
        // The wall: the plane x = 0, facing +x.
        let rot = Quat::from_rotation_arc(Vec3::Y, Vec3::X);
        app.world_mut()
            .spawn((Collider::plane(), Transform::from_rotation(rot)));
        let r = 0.5;
        // 1 cm from the wall: its speculative contact is there from the start.
        let light = ball(&mut app, r, 1.0, Vec3::X * (r + 0.01), Vec3::ZERO);
        let heavy = ball(
            &mut app,
            r,
            50.0,
            Vec3::X * (3.0 * r + 0.5),
            Vec3::NEG_X * speed,
        );
        app.world_mut().entity_mut(heavy).insert(Restitution(0.6));
        for k in 0..60 {
            step(&mut app, 1);
            let (x, vx) = (pos(&app, light).x - r, vel(&app, light).linear.x);
            // A step may end with the ball touching the wall, never moving into it.
            assert!(
                x > 0.0 || vx >= -1e-3,
                "{speed} m/s, step {k}: {x} m from the wall at {vx} m/s"
            );
        }
    }
}
