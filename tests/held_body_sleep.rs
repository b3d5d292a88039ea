//! Regression: a body held still in the air by the drag spring fell asleep, and after the
//! release it hung there asleep (seen in a real window with `scripts/drag_check.sh`). Two
//! causes: a held body counted as still, and a woken body kept its old sleep timer, so one
//! quiet step put it back to sleep. Now a held body never sleeps, and a woken body must be
//! still for the whole `time_to_sleep` again. Each case runs under every pacing of
//! `Pacing::GAME` and must give bit-identical physics under all.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::interaction::{DragPullPlugin, Dragged};
use tumble::prelude::*;

#[test]
fn a_body_held_in_the_air_stays_awake_and_falls_when_released() {
    // Sleeping on is the case under test; with it off the hold, release and fall must
    // come out the same way (the "held body slept" check then holds trivially).
    under_every_pacing(&Pacing::GAME, &[true, false], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.add_plugins(DragPullPlugin);
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = cuboid(app, Vec3::splat(0.5), 3.0, Vec3::Y * 0.5);
        app.world_mut().entity_mut(b).insert(Dragged {
            local_anchor: Vec3::ZERO,
            target: Vec3::Y * 4.0,
            plane_normal: Vec3::Z,
        });
        // Held still for 3 s: six times the time to sleep.
        for _ in 0..180 {
            step(app, 1);
            assert!(!asleep(app, b), "{what}: held body slept");
        }
        // Release as the demo does: no more pull, the force back to zero.
        let mut e = app.world_mut().entity_mut(b);
        e.remove::<Dragged>();
        *e.get_mut::<ExternalForce>().unwrap() = ExternalForce::default();
        let y0 = pos(app, b).y;
        step(app, 30);
        let drop = y0 - pos(app, b).y;
        let exact = 0.5 * G * 0.25;
        assert!(
            (drop - exact).abs() < 0.03,
            "{what}: fell {drop} m in 0.5 s after release; free fall is {exact} m"
        );
    });
}

#[test]
fn a_woken_body_needs_the_full_time_to_sleep_again() {
    // Sleeping is the thing under test: on only.
    under_every_pacing(&Pacing::GAME, &[true], |app, _, pacing| {
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = cuboid(app, Vec3::splat(0.5), 1.0, Vec3::Y * 0.5);
        step(app, 60);
        assert!(asleep(app, b), "{pacing:?}: asleep after 1 s");
        // Wake it without moving it (under a 240 Hz render, on a frame that runs no step).
        app.world_mut().entity_mut(b).remove::<Sleeping>();
        let time_to_sleep = app.world().resource::<SleepSettings>().time_to_sleep;
        let mut awake_steps = 0;
        while !asleep(app, b) && awake_steps < 600 {
            step(app, 1);
            awake_steps += 1;
        }
        let awake_for = awake_steps as f32 * H;
        assert!(
            awake_for >= time_to_sleep && awake_for < time_to_sleep + 0.1,
            "{pacing:?}: slept again after {awake_for} s; time to sleep is {time_to_sleep} s"
        );
    });
}
