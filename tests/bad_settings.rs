//! One bad global value must not freeze the world: a NaN or ∞ in `Gravity`,
//! `GlobalForce`, `Wind`, `SolverSettings` or `SleepSettings` for a couple of steps (a bad
//! slider, a bad scene file) is refused, the last good value stays in force, and no body
//! is rejected. Since the last good value is exactly the value before, the run is
//! bit-identical to one that never saw the bad value. Counts and rates are clamped
//! instead (substeps, iterations 1..=64; the fixed rate 1 Hz–10 kHz), so nothing hangs.

mod common;
use std::time::Duration;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;
use tumble::scene::{SceneDesc, SceneError};
use tumble::settings::GlobalForce;

/// A floor, a ball resting on it and a ball in free fall; 30 steps; then `bad` before
/// step 31, `good` after step 32; 30 more steps. Returns the final snapshot.
fn run(bad: &dyn Fn(&mut App), good: &dyn Fn(&mut App)) -> Vec<(Entity, [u32; 13])> {
    let mut app = app();
    app.insert_resource(Effects {
        wind: true,
        ..Effects::ALL
    });
    app.world_mut().resource_mut::<Effects>().sleeping = false;
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let resting = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO);
    let falling = ball(&mut app, 0.5, 1.0, Vec3::new(3.0, 20.0, 0.0), Vec3::ZERO);
    step(&mut app, 30);
    bad(&mut app);
    step(&mut app, 2);
    good(&mut app);
    step(&mut app, 30);
    for b in [resting, falling] {
        assert!(rejected_field(&app, b).is_none(), "a body was rejected");
    }
    assert_near(
        pos(&app, resting).y,
        0.5,
        2e-3,
        "the resting ball stays on the floor",
    );
    snapshot(&mut app)
}

fn nothing(_: &mut App) {}

#[test]
fn a_bad_global_for_two_steps_changes_nothing() {
    let reference = run(&nothing, &nothing);
    type Case = (&'static str, fn(&mut App), fn(&mut App));
    let cases: [Case; 10] = [
        (
            "Gravity NaN",
            |a| {
                a.insert_resource(Gravity(Vec3::new(0.0, f32::NAN, 0.0)));
            },
            |a| {
                a.insert_resource(Gravity::default());
            },
        ),
        (
            "Gravity 1e30",
            |a| {
                a.insert_resource(Gravity(Vec3::new(0.0, -1e30, 0.0)));
            },
            |a| {
                a.insert_resource(Gravity::default());
            },
        ),
        (
            "GlobalForce ∞",
            |a| {
                a.insert_resource(GlobalForce(Vec3::new(f32::INFINITY, 0.0, 0.0)));
            },
            |a| {
                a.insert_resource(GlobalForce::default());
            },
        ),
        (
            "Wind NaN velocity",
            |a| a.world_mut().resource_mut::<Wind>().velocity.x = f32::NAN,
            |a| {
                a.insert_resource(Wind::default());
            },
        ),
        (
            "Wind negative drag",
            |a| a.world_mut().resource_mut::<Wind>().drag = -5.0,
            |a| {
                a.insert_resource(Wind::default());
            },
        ),
        (
            "SolverSettings NaN speculative margin",
            |a| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .speculative_margin = f32::NAN
            },
            |a| {
                a.insert_resource(SolverSettings::default());
            },
        ),
        (
            "SolverSettings zero contact stiffness",
            |a| a.world_mut().resource_mut::<SolverSettings>().contact_hertz = 0.0,
            |a| {
                a.insert_resource(SolverSettings::default());
            },
        ),
        (
            "SolverSettings ∞ speed cap",
            |a| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .max_linear_speed = f32::INFINITY
            },
            |a| {
                a.insert_resource(SolverSettings::default());
            },
        ),
        (
            "SolverSettings NaN push-out",
            |a| a.world_mut().resource_mut::<SolverSettings>().max_push_out = f32::NAN,
            |a| {
                a.insert_resource(SolverSettings::default());
            },
        ),
        (
            "SleepSettings NaN",
            |a| a.world_mut().resource_mut::<SleepSettings>().time_to_sleep = f32::NAN,
            |a| {
                a.insert_resource(SleepSettings::default());
            },
        ),
    ];
    for (what, bad, good) in cases {
        assert!(run(&bad, &good) == reference, "{what}: the run changed");
    }
}

#[test]
fn absurd_counts_are_clamped_and_the_step_ends() {
    for (substeps, iterations) in [(u32::MAX, 1), (4, u32::MAX), (0, 0)] {
        let mut app = app();
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let b = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO);
        let mut s = app.world_mut().resource_mut::<SolverSettings>();
        (s.substeps, s.iterations) = (substeps, iterations);
        step(&mut app, 10);
        let s = *app.world().resource::<SolverSettings>();
        assert!((1..=64).contains(&s.substeps) && (1..=64).contains(&s.iterations));
        assert_near(pos(&app, b).y, 0.5, 2e-3, "resting ball");
    }
}

#[test]
fn a_plugin_rate_of_zero_is_clamped_not_a_panic() {
    for (hz, expected) in [(0.0, 1.0), (-60.0, 1.0), (f64::NAN, 60.0), (1e9, 10_000.0)] {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin { hz }));
        app.update();
        let step = app
            .world()
            .resource::<Time<Fixed>>()
            .timestep()
            .as_secs_f64();
        assert!(
            (1.0 / step - expected).abs() < 1e-6 * expected,
            "hz {hz}: {} Hz",
            1.0 / step
        );
    }
}

#[test]
fn a_nanosecond_fixed_step_is_clamped_before_the_loop_runs() {
    let mut app = app();
    app.world_mut()
        .resource_mut::<Time<Fixed>>()
        .set_timestep(Duration::from_nanos(1));
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(
        Duration::from_millis(16),
    ));
    let before = steps_taken(&app);
    app.update(); // Would be 16 million steps at 1 ns.
    let step = app.world().resource::<Time<Fixed>>().timestep();
    assert_eq!(step, Duration::from_secs_f64(1e-4), "clamped to 10 kHz");
    assert!(
        steps_taken(&app) - before <= 161,
        "{} steps",
        steps_taken(&app) - before
    );
}

#[test]
fn a_scene_file_with_a_zero_rate_fails_to_load_with_its_position() {
    let text = "(\n    name: \"bad rate\",\n    settings: (\n        hz: 0.0,\n    ),\n)\n";
    match SceneDesc::from_ron(text, "bad.scene.ron") {
        Err(SceneError::Parse {
            path,
            line,
            message,
            ..
        }) => {
            assert_eq!((path.as_str(), line), ("bad.scene.ron", 4), "{message}");
            assert!(message.contains("hz"), "{message}");
        }
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn scene_fields_are_checked_with_their_names() {
    let cases = [
        ("settings: (substeps: 0)", "substeps"),
        ("settings: (gravity: (0.0, -1e30, 0.0))", "gravity"),
        ("settings: (wind: (drag: -1.0))", "drag"),
        ("bodies: [Single((shape: Sphere(-0.5)))]", "size"),
        (
            "bodies: [Single((shape: Cuboid((0.5, 0.0, 0.5))))]",
            "half extents",
        ),
        ("bodies: [Single((mass: Some(0.0)))]", "mass"),
        ("bodies: [Single((restitution: Some(2.0)))]", "restitution"),
        ("bodies: [Single((velocity: (1e30, 0.0, 0.0)))]", "velocity"),
        ("planes: [(normal: (0.0, 0.0, 0.0))]", "normal"),
        ("planes: [(friction: -1.0)]", "friction"),
        (
            "bodies: [Grid(body: (), count: (1000, 1000, 1000), spacing: (1.0, 1.0, 1.0))]",
            "count",
        ),
    ];
    for (field, name) in cases {
        let text = format!("(name: \"x\", {field})");
        let err = SceneDesc::from_ron(&text, "f.scene.ron")
            .expect_err(field)
            .to_string();
        assert!(err.starts_with("f.scene.ron:1:"), "{field}: {err}");
        assert!(err.contains(name), "{field}: {err}");
    }
}

#[test]
fn a_rejected_body_comes_back_when_its_input_is_fixed() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(GravityScale(f32::NAN));
    step(&mut app, 10);
    assert_eq!(rejected_field(&app, b), Some("GravityScale"));
    assert_eq!(pos(&app, b).y, 5.0, "left out, not moved");
    app.world_mut().entity_mut(b).insert(GravityScale(1.0));
    step(&mut app, 30);
    assert!(rejected_field(&app, b).is_none(), "readmitted");
    // It fell for 30 steps from rest: ½·g·t², within the substep error.
    let t = 30.0 * H;
    assert_near(
        5.0 - pos(&app, b).y,
        0.5 * G * t * t,
        G * H / 4.0 * t + 1e-3,
        "fall",
    );
}

#[test]
fn a_rejected_static_comes_back_when_fixed() {
    let mut app = app();
    let floor = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    app.world_mut().entity_mut(floor).insert(Friction(f32::NAN));
    let b = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO);
    step(&mut app, 2);
    assert_eq!(rejected_field(&app, floor), Some("Friction"));
    app.world_mut().entity_mut(floor).insert(Friction(0.5));
    step(&mut app, 60);
    assert_near(
        pos(&app, b).y,
        0.5,
        2e-3,
        "the ball lands on the readmitted floor",
    );
}

#[test]
fn a_tiny_sphere_without_mass_is_refused_and_its_support_is_unharmed() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let support = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.5, 0.5),
            Transform::from_xyz(0.0, 0.5, 0.0),
        ))
        .id();
    // 1e-14 m: its volume times water's density underflows f32 to zero mass.
    let tiny = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(1e-14),
            Transform::from_xyz(0.0, 1.0, 0.0),
        ))
        .id();
    step(&mut app, 60);
    assert_eq!(rejected_field(&app, tiny), Some("Collider"));
    assert!(rejected_field(&app, support).is_none());
    assert_near(pos(&app, support).y, 0.5, 2e-3, "the support rests");
}
