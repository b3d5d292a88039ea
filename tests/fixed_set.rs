//! Static colliders and sleepers are kept in a fixed set between steps instead of being
//! gathered every step, and are looked at again only when they change. These tests make
//! sure every kind of change still reaches the simulation on the next step: a static that
//! is moved, despawned, spawned late or turned dynamic in place, and sleepers woken by
//! switching sleeping off. Each case runs under every pacing of `Pacing::GAME` (under a
//! 240 Hz render the change lands on a frame that runs no step), with sleeping on and off
//! unless sleeping is what it tests, and must give bit-identical physics under all.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

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

/// A unit ball resting on the floor for 30 steps (0.5 s, the time to sleep: asleep by
/// then when sleeping is on, so the change that follows must wake it).
fn resting_ball(app: &mut App, sleeping: bool, what: &str) -> Entity {
    let b = ball(app, 0.5, 1.0, Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO);
    step(app, 30);
    assert!(
        (pos(app, b).y - 0.5).abs() < 2e-3,
        "{what}: rests on the floor"
    );
    assert_eq!(
        asleep(app, b),
        sleeping,
        "{what}: asleep iff sleeping is on"
    );
    b
}

#[test]
fn a_static_floor_moved_down_lets_the_ball_fall_freely() {
    for kind in [None, Some(RigidBody::Static)] {
        under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
            let what = format!("{kind:?} {pacing:?} sleeping {sleeping}");
            let f = floor(app, kind);
            let b = resting_ball(app, sleeping, &what);
            let y0 = pos(app, b).y;
            app.world_mut()
                .get_mut::<Transform>(f)
                .unwrap()
                .translation
                .y = -5.5;
            step(app, 30);
            assert_free_fall(y0 - pos(app, b).y, 0.5, &what);
        });
    }
}

#[test]
fn a_static_floor_moved_up_lifts_the_ball() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let f = floor(app, None);
        let b = resting_ball(app, sleeping, &format!("{pacing:?} sleeping {sleeping}"));
        app.world_mut()
            .get_mut::<Transform>(f)
            .unwrap()
            .translation
            .y = -0.2;
        step(app, 60);
        assert!(
            (pos(app, b).y - 0.8).abs() < 5e-3,
            "{pacing:?} sleeping {sleeping}: the ball stands on the raised floor: {}",
            pos(app, b)
        );
    });
}

#[test]
fn a_despawned_floor_lets_the_ball_fall_freely() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        let f = floor(app, None);
        let b = resting_ball(app, sleeping, &what);
        let y0 = pos(app, b).y;
        app.world_mut().despawn(f);
        step(app, 30);
        assert_free_fall(y0 - pos(app, b).y, 0.5, &what);
    });
}

#[test]
fn a_floor_spawned_under_a_falling_ball_catches_it() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let b = ball(app, 0.5, 1.0, Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO);
        step(app, 10);
        floor(app, Some(RigidBody::Static));
        step(app, 90);
        assert!(
            (pos(app, b).y - 0.5).abs() < 5e-3,
            "{pacing:?} sleeping {sleeping}: {}",
            pos(app, b)
        );
    });
}

#[test]
fn a_static_box_made_dynamic_in_place_falls() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        let e = app
            .world_mut()
            .spawn((
                RigidBody::Static,
                Collider::cuboid(0.5, 0.5, 0.5),
                Transform::from_xyz(0.0, 10.0, 0.0),
            ))
            .id();
        step(app, 10);
        assert_eq!(pos(app, e).y, 10.0, "{what}: static stays");
        *app.world_mut().get_mut::<RigidBody>(e).unwrap() = RigidBody::Dynamic;
        step(app, 30);
        assert_free_fall(10.0 - pos(app, e).y, 0.5, &what);
    });
}

#[test]
fn switching_sleeping_off_wakes_a_stack_that_then_falls_with_its_floor() {
    // Starts with sleeping on: switching it off is the thing under test.
    under_every_pacing(&Pacing::GAME, &[true], |app, _, pacing| {
        let f = floor(app, None);
        let boxes: Vec<Entity> = (0..3)
            .map(|i| {
                cuboid(
                    app,
                    Vec3::splat(0.5),
                    1.0,
                    Vec3::new(0.0, 0.5 + i as f32, 0.0),
                )
            })
            .collect();
        step(app, 150);
        assert!(boxes.iter().all(|&b| asleep(app, b)), "{pacing:?}: asleep");
        let y0 = pos(app, boxes[0]).y;
        app.world_mut().resource_mut::<Effects>().sleeping = false;
        app.world_mut().despawn(f);
        step(app, 30);
        assert!(boxes.iter().all(|&b| !asleep(app, b)), "{pacing:?}: awake");
        assert_free_fall(y0 - pos(app, boxes[0]).y, 0.5, &format!("{pacing:?}"));
    });
}
