//! Static colliders and sleepers are kept in a fixed set between steps instead of being
//! gathered every step, and are looked at again only when they change. These tests make
//! sure every kind of change still reaches the simulation on the next step: a static that
//! is moved, despawned, spawned late or turned dynamic in place, and sleepers woken by
//! switching sleeping off.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const G: f32 = 9.81;

/// Distance fallen from rest after `t` s, with the bound on the semi-implicit error
/// (½·g·hs·t, hs = h/4) doubled, plus 1 mm for the start of the fall inside a step.
fn assert_free_fall(drop: f32, t: f32) {
    let exact = 0.5 * G * t * t;
    let bound = G * (H / 4.0) * t + 1e-3;
    assert!(
        (drop - exact).abs() < bound,
        "fell {drop} m in {t} s, free fall is {exact} ± {bound}"
    );
}

/// A static 10 × 1 × 10 m box whose top is at y = 0.
fn floor(app: &mut App, kind: Option<RigidBody>) -> Entity {
    let mut e = app.world_mut().spawn((
        Collider::cuboid(5.0, 0.5, 5.0),
        Transform::from_xyz(0.0, -0.5, 0.0),
    ));
    if let Some(kind) = kind {
        e.insert(kind);
    }
    e.id()
}

fn resting_ball(app: &mut App) -> Entity {
    let b = ball(app, 0.5, 1.0, Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO);
    step(app, 30);
    assert!((pos(app, b).y - 0.5).abs() < 2e-3, "rests on the floor");
    b
}

#[test]
fn a_static_floor_moved_down_lets_the_ball_fall_freely() {
    for kind in [None, Some(RigidBody::Static)] {
        let mut app = app();
        let f = floor(&mut app, kind);
        let b = resting_ball(&mut app);
        let y0 = pos(&app, b).y;
        app.world_mut()
            .get_mut::<Transform>(f)
            .unwrap()
            .translation
            .y = -5.5;
        step(&mut app, 30);
        assert_free_fall(y0 - pos(&app, b).y, 0.5);
    }
}

#[test]
fn a_static_floor_moved_up_lifts_the_ball() {
    let mut app = app();
    let f = floor(&mut app, None);
    let b = resting_ball(&mut app);
    app.world_mut()
        .get_mut::<Transform>(f)
        .unwrap()
        .translation
        .y = -0.2;
    step(&mut app, 60);
    assert!(
        (pos(&app, b).y - 0.8).abs() < 5e-3,
        "the ball stands on the raised floor: {}",
        pos(&app, b)
    );
}

#[test]
fn a_despawned_floor_lets_the_ball_fall_freely() {
    let mut app = app();
    let f = floor(&mut app, None);
    let b = resting_ball(&mut app);
    let y0 = pos(&app, b).y;
    app.world_mut().despawn(f);
    step(&mut app, 30);
    assert_free_fall(y0 - pos(&app, b).y, 0.5);
}

#[test]
fn a_floor_spawned_under_a_falling_ball_catches_it() {
    let mut app = app();
    let b = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO);
    step(&mut app, 10);
    floor(&mut app, Some(RigidBody::Static));
    step(&mut app, 90);
    assert!((pos(&app, b).y - 0.5).abs() < 5e-3, "{}", pos(&app, b));
}

#[test]
fn a_static_box_made_dynamic_in_place_falls() {
    let mut app = app();
    let e = app
        .world_mut()
        .spawn((
            RigidBody::Static,
            Collider::cuboid(0.5, 0.5, 0.5),
            Transform::from_xyz(0.0, 10.0, 0.0),
        ))
        .id();
    step(&mut app, 10);
    assert_eq!(pos(&app, e).y, 10.0, "static stays");
    *app.world_mut().get_mut::<RigidBody>(e).unwrap() = RigidBody::Dynamic;
    step(&mut app, 30);
    assert_free_fall(10.0 - pos(&app, e).y, 0.5);
}

#[test]
fn switching_sleeping_off_wakes_a_stack_that_then_falls_with_its_floor() {
    let mut app = app_with_sleeping();
    let f = floor(&mut app, None);
    let boxes: Vec<Entity> = (0..3)
        .map(|i| {
            cuboid(
                &mut app,
                Vec3::splat(0.5),
                1.0,
                Vec3::new(0.0, 0.5 + i as f32, 0.0),
            )
        })
        .collect();
    step(&mut app, 150);
    assert!(
        boxes
            .iter()
            .all(|&b| app.world().get::<Sleeping>(b).is_some())
    );
    let y0 = pos(&app, boxes[0]).y;
    app.world_mut().resource_mut::<Effects>().sleeping = false;
    app.world_mut().despawn(f);
    step(&mut app, 30);
    assert!(
        boxes
            .iter()
            .all(|&b| app.world().get::<Sleeping>(b).is_none())
    );
    assert_free_fall(y0 - pos(&app, boxes[0]).y, 0.5);
}
