//! Sleeping: a still stack falls asleep and stays exactly put, wakes when something hits
//! it or the user pushes it, and the switch keeps everything awake. Sleeping is the thing
//! under test, so each case runs with it on (or, for the switch, off) only; each runs
//! under every pacing of `Pacing::GAME` and must give bit-identical physics under all.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn stack(app: &mut App, n: usize) -> Vec<Entity> {
    ground(app, Vec3::ZERO, Quat::IDENTITY);
    (0..n)
        .map(|i| {
            cuboid(
                app,
                Vec3::splat(0.5),
                1.0,
                Vec3::new(0.0, 0.5 + i as f32, 0.0),
            )
        })
        .collect()
}

#[test]
fn still_stack_sleeps_and_stays_exactly_put() {
    under_every_pacing(&Pacing::GAME, &[true], |app, _, pacing| {
        let boxes = stack(app, 3);
        step(app, 120);
        assert!(
            boxes.iter().all(|&b| asleep(app, b)),
            "{pacing:?}: asleep after 2 s"
        );
        let before: Vec<_> = boxes.iter().map(|&b| pos(app, b)).collect();
        // 120 steps, and under a 240 Hz render also the step-less frames between them.
        step(app, 120);
        for (&b, p) in boxes.iter().zip(before) {
            assert_eq!(
                pos(app, b),
                p,
                "{pacing:?}: a sleeping body does not move at all"
            );
            assert_eq!(vel(app, b), Velocity::ZERO, "{pacing:?}");
        }
    });
}

#[test]
fn falling_ball_wakes_the_stack_it_hits() {
    under_every_pacing(&Pacing::GAME, &[true], |app, _, pacing| {
        let boxes = stack(app, 2);
        step(app, 120);
        assert!(asleep(app, boxes[1]), "{pacing:?}: asleep after 2 s");
        let b = ball(app, 0.3, 5.0, Vec3::new(0.4, 4.0, 0.0), Vec3::ZERO);
        let mut woke = false;
        for _ in 0..60 {
            step(app, 1);
            woke |= !asleep(app, boxes[1]);
        }
        assert!(woke, "{pacing:?}: the top box woke when the ball hit it");
        assert!(
            pos(app, b).y < 3.0 && pos(app, b).y > 1.5,
            "{pacing:?}: the ball landed on the stack, not through it: {}",
            pos(app, b)
        );
    });
}

#[test]
fn changing_a_sleeping_bodys_velocity_wakes_it() {
    under_every_pacing(&Pacing::GAME, &[true], |app, _, pacing| {
        let boxes = stack(app, 1);
        step(app, 120);
        assert!(asleep(app, boxes[0]), "{pacing:?}: asleep after 2 s");
        app.world_mut()
            .get_mut::<Velocity>(boxes[0])
            .unwrap()
            .linear = Vec3::new(2.0, 0.0, 0.0);
        step(app, 10);
        assert!(!asleep(app, boxes[0]), "{pacing:?}: woke");
        assert!(
            pos(app, boxes[0]).x > 0.1,
            "{pacing:?}: it slid: {}",
            pos(app, boxes[0])
        );
    });
}

#[test]
fn sleeping_off_keeps_everything_awake() {
    under_every_pacing(&Pacing::GAME, &[false], |app, _, pacing| {
        let boxes = stack(app, 2);
        step(app, 180);
        assert!(boxes.iter().all(|&b| !asleep(app, b)), "{pacing:?}");
    });
}
