//! Kinematic bodies driven by their Transform: the solver sees the velocity the move
//! implies, so a platform moved by setting its Transform every frame carries what
//! stands on it, at any frame pacing; when the moves stop, it stops.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// Platform acceleration, m/s²: below μ·g (0.5 · 9.81), so the box never slips.
const A: f32 = 1.0;

#[derive(Resource)]
struct Platform(Entity, bool);

/// Game code: moves the platform along x as ½·A·t², every frame, while it is on.
fn drive(platform: Res<Platform>, time: Res<Time<Virtual>>, mut q: Query<&mut Transform>) {
    if platform.1 {
        let t = time.elapsed_secs();
        q.get_mut(platform.0).unwrap().translation.x = 0.5 * A * t * t;
    }
}

#[test]
fn a_platform_moved_by_its_transform_carries_a_box_and_stops_when_the_moves_stop() {
    for pacing in Pacing::GAME {
        let what = format!("{pacing:?}");
        let mut app = paced_app(pacing, true);
        let platform = app
            .world_mut()
            .spawn((
                RigidBody::Kinematic,
                Collider::cuboid(2.0, 0.1, 2.0),
                Transform::from_xyz(0.0, 0.1, 0.0),
            ))
            .id();
        let bx = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::Y * 0.45);
        app.insert_resource(Platform(platform, true))
            .add_systems(Update, drive);
        // 121 steps: at 30 Hz the first frame runs one and every later frame two, so no
        // frame is cut short (a short frame would carry a whole frame's move in one step).
        step(&mut app, 121);
        let t = app.world().resource::<Time<Virtual>>().elapsed_secs();
        // Where the last step left the platform (the Transform may already hold the
        // game's next move): behind the game's ½·A·t² by at most two 30 Hz frames.
        let at = app
            .world()
            .resource::<PhysicsWorld>()
            .kinematic_pose(platform)
            .unwrap()
            .0;
        let frame = 1.0 / 30.0;
        let lag = 0.5 * A * t * t - at.x;
        assert!(
            lag >= 0.0 && lag <= A * t * 2.0 * frame,
            "{what}: platform lags {lag} m"
        );
        // It moved at the speed its moves imply. One step per update, the game's move
        // of frame k is stepped in frame k + 1: v = A·(t − 1.5·h).
        let v = vel(&app, platform).linear.x;
        if pacing == Pacing::OneStep {
            assert_near(v, A * (t - 1.5 * H), 1e-4, &format!("{what}: implied v"));
        }
        // The box rode along (static friction): it moved with the platform, less the
        // creep of soft friction, within 5 mm over 2 m.
        assert_near(pos(&app, bx).x, at.x, 5e-3, &format!("{what}: carried"));
        assert_near(pos(&app, bx).y, 0.45, 2e-3, &format!("{what}: on top"));
        // The game stops moving it: the platform finishes the last move, lands exactly
        // where the game last put it, stops, and stays.
        app.world_mut().resource_mut::<Platform>().1 = false;
        let last = app.world().get::<Transform>(platform).unwrap().translation;
        step(&mut app, 3);
        assert_near_vec(pos(&app, platform), last, 1e-5, &format!("{what}: arrived"));
        assert_eq!(vel(&app, platform).linear, Vec3::ZERO, "{what}: stopped");
        step(&mut app, 30);
        assert_near_vec(pos(&app, platform), last, 1e-5, &format!("{what}: stays"));
    }
}

#[test]
fn a_kinematic_body_driven_by_velocity_is_unchanged() {
    let mut app = app();
    let k = app
        .world_mut()
        .spawn((
            RigidBody::Kinematic,
            Collider::cuboid(1.0, 0.1, 1.0),
            Transform::default(),
            Velocity {
                linear: Vec3::X * 2.0,
                angular: Vec3::Y * 0.5,
            },
        ))
        .id();
    step(&mut app, 60);
    assert_near_vec(pos(&app, k), Vec3::X * 2.0, 1e-4, "x = v·t");
    assert_near_vec(vel(&app, k).linear, Vec3::X * 2.0, 0.0, "v kept");
    let turned = rot(&app, k).to_axis_angle().1;
    assert_near(turned, 0.5, 1e-3, "θ = ω·t");
}

#[test]
fn a_teleport_is_not_a_velocity() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let k = app
        .world_mut()
        .spawn((
            RigidBody::Kinematic,
            Collider::cuboid(0.5, 0.5, 0.5),
            Transform::from_xyz(0.0, 3.0, 0.0),
        ))
        .id();
    step(&mut app, 2);
    // 1 km in a step is past the speed limit: it jumps there, with no velocity.
    app.world_mut()
        .get_mut::<Transform>(k)
        .unwrap()
        .translation
        .x = 1000.0;
    step(&mut app, 1);
    assert_eq!(pos(&app, k).x, 1000.0);
    assert_eq!(vel(&app, k).linear, Vec3::ZERO);
}

#[test]
fn a_platform_that_starts_moving_wakes_the_crate_asleep_on_it() {
    let mut app = app_with_sleeping();
    let platform = app
        .world_mut()
        .spawn((
            RigidBody::Kinematic,
            Collider::cuboid(2.0, 0.1, 2.0),
            Transform::from_xyz(0.0, 0.1, 0.0),
        ))
        .id();
    let bx = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::Y * 0.45);
    step(&mut app, 120);
    assert!(asleep(&app, bx), "the crate sleeps on the still platform");
    // The platform sets off at 0.5 m/s (an acceleration friction can follow in a step:
    // μ·g·h = 0.08 m/s... so it slips for a few steps, then rides).
    app.world_mut()
        .entity_mut(platform)
        .insert(Velocity::linear(Vec3::X * 0.5));
    step(&mut app, 60);
    assert!(!asleep(&app, bx), "woken by its moving support");
    assert_near(
        vel(&app, bx).linear.x,
        0.5,
        1e-3,
        "riding at the platform's speed",
    );
}

#[test]
fn diagnostics_report_the_step() {
    use bevy::diagnostic::{DiagnosticsPlugin, DiagnosticsStore};
    let mut app = paced_app_with(Pacing::OneStep, false, |app| {
        app.add_plugins((DiagnosticsPlugin, PhysicsDiagnosticsPlugin));
    });
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    for i in 0..3 {
        ball(
            &mut app,
            0.3,
            1.0,
            Vec3::new(i as f32, 0.3, 0.0),
            Vec3::ZERO,
        );
    }
    step(&mut app, 10);
    let store = app.world().resource::<DiagnosticsStore>();
    let value = |path: &str| {
        store
            .get(&bevy::diagnostic::DiagnosticPath::new(path.to_string()))
            .and_then(|d| d.value())
            .unwrap_or(f64::NAN)
    };
    assert_eq!(value("physics/awake_bodies"), 3.0);
    assert_eq!(value("physics/fixed_colliders"), 1.0);
    assert_eq!(value("physics/contacts"), 3.0);
    assert_eq!(value("physics/substeps"), 4.0);
    assert!(value("physics/step") > 0.0 && value("physics/solve") >= 0.0);
}
