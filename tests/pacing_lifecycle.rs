//! Lifecycle under real frame pacing. A game renders at 30–1000 Hz with physics at 60 Hz,
//! so most frames run no physics step and some run two. Every removal, despawn, kind
//! change and wake made on any frame must reach the next step, and a support that goes
//! away must wake what sleeps on it. Each case runs under one step per update, a 240 Hz
//! and a 1 kHz render (removals land several step-less frames before the next step:
//! Bevy's `RemovedComponents` would have dropped them), and a 30 Hz render (two steps a
//! frame), with sleeping on and off, and must give bit-identical physics under all of
//! them.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const PACINGS: [Pacing; 4] = [
    Pacing::OneStep,
    Pacing::Render(240.0),
    Pacing::Render(1000.0),
    Pacing::Render(30.0),
];

/// A static 10 × 1 × 10 m box whose top is at y = 0.
fn floor(app: &mut App) -> Entity {
    app.world_mut()
        .spawn((
            Collider::cuboid(5.0, 0.5, 5.0),
            Transform::from_xyz(0.0, -0.5, 0.0),
        ))
        .id()
}

/// A unit ball resting on the floor for 60 steps (asleep by then when sleeping is on).
fn resting_ball(app: &mut App, sleeping: bool) -> Entity {
    let b = ball(app, 0.5, 1.0, Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO);
    step(app, 60);
    assert_near(pos(app, b).y, 0.5, 2e-3, "ball resting on the floor");
    assert_eq!(asleep(app, b), sleeping, "asleep iff sleeping is on");
    b
}

#[test]
fn a_despawned_floor_is_gone_by_the_next_step() {
    under_every_pacing(&PACINGS, &[false, true], |app, sleeping, pacing| {
        let f = floor(app);
        let b = resting_ball(app, sleeping);
        let y0 = pos(app, b).y;
        app.world_mut().despawn(f);
        step(app, 30);
        assert_free_fall(y0 - pos(app, b).y, 0.5, &format!("{pacing:?} {sleeping}"));
    });
}

#[test]
fn a_removed_floor_collider_is_gone_by_the_next_step() {
    under_every_pacing(&PACINGS, &[false, true], |app, sleeping, pacing| {
        let f = floor(app);
        let b = resting_ball(app, sleeping);
        let y0 = pos(app, b).y;
        app.world_mut().entity_mut(f).remove::<Collider>();
        step(app, 30);
        assert_free_fall(y0 - pos(app, b).y, 0.5, &format!("{pacing:?} {sleeping}"));
    });
}

#[test]
fn a_static_floor_turned_dynamic_falls_with_the_ball() {
    under_every_pacing(&PACINGS, &[false, true], |app, sleeping, pacing| {
        let f = app
            .world_mut()
            .spawn((
                RigidBody::Static,
                Collider::cuboid(5.0, 0.5, 5.0),
                Transform::from_xyz(0.0, -0.5, 0.0),
            ))
            .id();
        let b = resting_ball(app, sleeping);
        let (y0, f0) = (pos(app, b).y, pos(app, f).y);
        *app.world_mut().get_mut::<RigidBody>(f).unwrap() = RigidBody::Dynamic;
        step(app, 30);
        let what = format!("{pacing:?} {sleeping}");
        // Floor and ball fall together (the ball rides on the floor).
        assert_free_fall(f0 - pos(app, f).y, 0.5, &what);
        assert_free_fall(y0 - pos(app, b).y, 0.5, &what);
    });
}

#[test]
fn a_floor_moved_down_wakes_and_drops_the_ball() {
    under_every_pacing(&PACINGS, &[false, true], |app, sleeping, pacing| {
        let f = floor(app);
        let b = resting_ball(app, sleeping);
        let y0 = pos(app, b).y;
        app.world_mut()
            .get_mut::<Transform>(f)
            .unwrap()
            .translation
            .y = -5.5;
        step(app, 30);
        assert_free_fall(y0 - pos(app, b).y, 0.5, &format!("{pacing:?} {sleeping}"));
    });
}

#[test]
fn a_ball_woken_by_removing_sleeping_falls() {
    for pacing in PACINGS {
        let mut app = paced_app(pacing, true);
        let b = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO);
        app.world_mut().entity_mut(b).insert(Sleeping);
        step(&mut app, 30);
        assert_eq!(
            pos(&app, b).y,
            5.0,
            "{pacing:?}: asleep in mid-air stays put"
        );
        app.world_mut().entity_mut(b).remove::<Sleeping>();
        step(&mut app, 30);
        assert_free_fall(5.0 - pos(&app, b).y, 0.5, &format!("{pacing:?}"));
    }
}

#[test]
fn a_sleeping_stack_wakes_when_its_bottom_box_is_despawned() {
    for pacing in PACINGS {
        let mut app = paced_app(pacing, true);
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let boxes: Vec<Entity> = (0..3)
            .map(|i| cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y * (0.5 + i as f32)))
            .collect();
        step(&mut app, 90);
        assert!(boxes.iter().all(|&b| asleep(&app, b)), "{pacing:?}: asleep");
        app.world_mut().despawn(boxes[0]);
        step(&mut app, 60);
        // The two boxes above dropped one box height and stand on the ground.
        for (i, &b) in boxes[1..].iter().enumerate() {
            assert_near(
                pos(&app, b).y,
                0.5 + i as f32,
                0.01,
                &format!("{pacing:?} box {i}"),
            );
        }
    }
}

#[test]
fn a_despawned_sleeping_support_ball_wakes_the_ball_above_at_every_pacing() {
    // Two balls asleep on a small static shelf; the shelf is despawned between steps.
    for pacing in PACINGS {
        let mut app = paced_app(pacing, true);
        let shelf = app
            .world_mut()
            .spawn((
                Collider::cuboid(0.6, 0.1, 0.6),
                Transform::from_xyz(0.0, 2.9, 0.0),
            ))
            .id();
        let low = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 3.5, 0.0), Vec3::ZERO);
        let high = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 4.5, 0.0), Vec3::ZERO);
        step(&mut app, 90);
        assert!(
            asleep(&app, low) && asleep(&app, high),
            "{pacing:?}: asleep"
        );
        let y0 = pos(&app, low).y;
        app.world_mut().despawn(shelf);
        step(&mut app, 30);
        let what = format!("{pacing:?}");
        assert_free_fall(y0 - pos(&app, low).y, 0.5, &what);
        assert!(!asleep(&app, high), "{what}: the ball above woke too");
        assert_near(pos(&app, high).y - pos(&app, low).y, 1.0, 0.01, &what);
    }
}
