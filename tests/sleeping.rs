//! Sleeping: a still stack falls asleep and stays exactly put, wakes when something hits
//! it or the user pushes it, and the switch keeps everything awake.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn asleep(app: &App, e: Entity) -> bool {
    app.world().get::<Sleeping>(e).is_some()
}

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
    let mut app = app_with_sleeping();
    let boxes = stack(&mut app, 3);
    step(&mut app, 120);
    assert!(boxes.iter().all(|&b| asleep(&app, b)), "asleep after 2 s");
    let before: Vec<_> = boxes.iter().map(|&b| pos(&app, b)).collect();
    step(&mut app, 120);
    for (&b, p) in boxes.iter().zip(before) {
        assert_eq!(pos(&app, b), p, "a sleeping body does not move at all");
        assert_eq!(vel(&app, b), Velocity::ZERO);
    }
}

#[test]
fn falling_ball_wakes_the_stack_it_hits() {
    let mut app = app_with_sleeping();
    let boxes = stack(&mut app, 2);
    step(&mut app, 120);
    assert!(asleep(&app, boxes[1]));
    let b = ball(&mut app, 0.3, 5.0, Vec3::new(0.4, 4.0, 0.0), Vec3::ZERO);
    let mut woke = false;
    for _ in 0..60 {
        step(&mut app, 1);
        woke |= !asleep(&app, boxes[1]);
    }
    assert!(woke, "the top box woke when the ball hit it");
    assert!(
        pos(&app, b).y < 3.0 && pos(&app, b).y > 1.5,
        "the ball landed on the stack, not through it: {}",
        pos(&app, b)
    );
}

#[test]
fn changing_a_sleeping_bodys_velocity_wakes_it() {
    let mut app = app_with_sleeping();
    let boxes = stack(&mut app, 1);
    step(&mut app, 120);
    assert!(asleep(&app, boxes[0]));
    app.world_mut()
        .get_mut::<Velocity>(boxes[0])
        .unwrap()
        .linear = Vec3::new(2.0, 0.0, 0.0);
    step(&mut app, 10);
    assert!(!asleep(&app, boxes[0]));
    assert!(
        pos(&app, boxes[0]).x > 0.1,
        "it slid: {}",
        pos(&app, boxes[0])
    );
}

#[test]
fn sleeping_off_keeps_everything_awake() {
    let mut app = app();
    let boxes = stack(&mut app, 2);
    step(&mut app, 180);
    assert!(boxes.iter().all(|&b| !asleep(&app, b)));
}
