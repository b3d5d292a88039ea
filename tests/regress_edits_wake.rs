//! Edits a game makes to a sleeping body must wake it. A velocity written in the very
//! frame the body fell asleep was lost (the body went into the fixed set as it lay, and
//! the edit was older than the next look at it), and a changed `Mass` or `GravityScale`
//! on a sleeper did nothing at all.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// A 1 kg box resting on the floor, stepped until the frame it falls asleep.
fn box_just_asleep(pacing: Pacing) -> (App, Entity) {
    let mut app = paced_app(pacing, true);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::new(0.0, 0.25, 0.0));
    for _ in 0..2000 {
        app.update();
        if asleep(&app, b) {
            return (app, b);
        }
    }
    panic!("{pacing:?}: the box never fell asleep");
}

#[test]
fn a_velocity_set_in_the_frame_a_body_falls_asleep_moves_it() {
    for pacing in Pacing::GAME {
        let (mut app, b) = box_just_asleep(pacing);
        let v = Vec3::new(0.0, 3.0, 0.0);
        app.world_mut().entity_mut(b).insert(Velocity::linear(v));
        let y0 = pos(&app, b).y;
        step(&mut app, 6);
        let t = 6.0 * H;
        let risen = pos(&app, b).y - y0;
        // Thrown up at 3 m/s: v·t − ½·g·t², within the substep error.
        let expect = v.y * t - 0.5 * G * t * t;
        assert_near(
            risen,
            expect,
            G * (H / 4.0) * t + 1e-3,
            &format!("{pacing:?}: rise"),
        );
    }
}

#[test]
fn a_changed_gravity_scale_wakes_a_sleeper() {
    for pacing in Pacing::GAME {
        let (mut app, b) = box_just_asleep(pacing);
        step(&mut app, 10);
        assert!(asleep(&app, b), "{pacing:?}: still asleep");
        // Gravity turned upside down for it: it falls up.
        app.world_mut().entity_mut(b).insert(GravityScale(-1.0));
        let y0 = pos(&app, b).y;
        step(&mut app, 30);
        let t = 30.0 * H;
        assert_free_fall(pos(&app, b).y - y0, t, &format!("{pacing:?}: fall upward"));
    }
}
