//! Sensors: trigger volumes that report overlaps and never push, are never pushed, and
//! never wake a sleeper. Under every game pacing, sleeping on and off.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// Overlap events a sensor's observer saw: (step, start?, other).
#[derive(Resource, Default)]
struct Seen(Vec<(u64, bool, Entity)>);

fn watch(app: &mut App, sensor: Entity) {
    app.world_mut()
        .entity_mut(sensor)
        .insert(CollisionEventsEnabled)
        .observe(
            |hit: On<CollisionStart>, w: Res<PhysicsWorld>, mut seen: ResMut<Seen>| {
                assert!(hit.sensor, "a sensor's events say so");
                seen.0.push((w.step_count(), true, hit.collider2));
            },
        )
        .observe(
            |end: On<CollisionEnd>, w: Res<PhysicsWorld>, mut seen: ResMut<Seen>| {
                seen.0.push((w.step_count(), false, end.collider2));
            },
        );
}

/// The first step whose start pose puts a ball dropped from rest at `y0` below `y`:
/// overlaps are seen at the start of a step (and reported at its end).
fn first_step_below(y0: f32, y: f32) -> u64 {
    // Semi-implicit Euler at 4 substeps: after k steps the drop is g·hs²·n(n+1)/2, n = 4k.
    let hs = H / 4.0;
    (1u64..)
        .find(|&k| {
            let n = 4.0 * k as f32;
            y0 - G * hs * hs * n * (n + 1.0) / 2.0 < y
        })
        .unwrap()
        + 1
}

#[test]
fn a_ball_falls_through_a_static_trigger_untouched_and_is_reported_in_and_out() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.init_resource::<Seen>();
        // A 2 m trigger box spanning y = 1..3; a 0.25 m ball dropped from y = 5.
        let trigger = app
            .world_mut()
            .spawn((
                Collider::cuboid(1.0, 1.0, 1.0),
                Sensor,
                Transform::from_xyz(0.0, 2.0, 0.0),
            ))
            .id();
        watch(app, trigger);
        let (r, y0) = (0.25, 5.0);
        let b = ball(app, r, 1.0, Vec3::Y * y0, Vec3::ZERO);
        step(app, 60);
        // Free fall all the way: the trigger never pushed.
        assert_free_fall(y0 - pos(app, b).y, 1.0, &format!("{what}: free fall"));
        let seen = &app.world().resource::<Seen>().0;
        let enter = first_step_below(y0, 3.0 + r);
        let leave = first_step_below(y0, 1.0 - r);
        assert_eq!(
            seen.as_slice(),
            &[(enter, true, b), (leave, false, b)],
            "{what}: in at step {enter}, out at step {leave}"
        );
    });
}

#[test]
fn a_kinematic_trigger_sweeping_over_a_sleeper_reports_it_and_leaves_it_asleep() {
    for pacing in Pacing::GAME {
        let what = format!("{pacing:?}");
        let mut app = paced_app(pacing, true);
        app.init_resource::<Seen>();
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let b = ball(&mut app, 0.3, 1.0, Vec3::Y * 0.3, Vec3::ZERO);
        // The trigger skims 1 cm above the floor: it reports only the ball.
        step(&mut app, 120);
        assert!(asleep(&app, b), "{what}: asleep first");
        let rest = pos(&app, b);
        // A 1 m kinematic trigger passing through the ball at 3 m/s.
        let trigger = app
            .world_mut()
            .spawn((
                RigidBody::Kinematic,
                Collider::cuboid(0.5, 0.5, 0.5),
                Sensor,
                Transform::from_xyz(-3.0, 0.51, 0.0),
                Velocity::linear(Vec3::X * 3.0),
            ))
            .id();
        watch(&mut app, trigger);
        step(&mut app, 120);
        assert!(asleep(&app, b), "{what}: still asleep");
        assert_eq!(pos(&app, b), rest, "{what}: not moved");
        let seen = &app.world().resource::<Seen>().0;
        let kinds: Vec<(bool, Entity)> = seen.iter().map(|s| (s.1, s.2)).collect();
        assert_eq!(kinds, [(true, b), (false, b)], "{what}: {seen:?}");
    }
}

#[test]
fn a_dynamic_sensor_falls_through_the_floor_and_two_sensors_ignore_each_other() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.init_resource::<Seen>();
        // A 20 cm slab of floor (an infinite plane is a half-space: below it is inside).
        let floor = app
            .world_mut()
            .spawn((
                Collider::cuboid(5.0, 0.1, 5.0),
                Transform::from_xyz(0.0, -0.1, 0.0),
            ))
            .id();
        let falling = ball(app, 0.5, 1.0, Vec3::Y * 0.6, Vec3::ZERO);
        app.world_mut().entity_mut(falling).insert(Sensor);
        watch(app, falling);
        // A static sensor it passes through: no event for that pair.
        app.world_mut().spawn((
            Collider::cuboid(1.0, 0.2, 1.0),
            Sensor,
            Transform::from_xyz(0.0, -1.0, 0.0),
        ));
        step(app, 45);
        assert_free_fall(
            0.6 - pos(app, falling).y,
            0.75,
            &format!("{what}: free fall"),
        );
        let seen = &app.world().resource::<Seen>().0;
        let others: Vec<Entity> = seen.iter().map(|s| s.2).collect();
        assert_eq!(
            others,
            [floor, floor],
            "{what}: in and out of the floor: {seen:?}"
        );
    });
}
