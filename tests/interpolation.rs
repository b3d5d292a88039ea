//! Smooth motion in the core: with interpolation a body's `Transform` in `Update` is the
//! blend of its last two physics poses by the fixed clock's overstep; with extrapolation
//! it runs ahead on its velocity. Physics itself is unchanged, and sleeping still works.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[derive(Resource)]
struct Watch {
    body: Entity,
    /// The last two physics poses (after writeback).
    poses: [Vec3; 2],
    /// The worst gap between the shown and the expected pose, m.
    worst: f32,
    frames: u32,
}

fn record(mut w: ResMut<Watch>, q: Query<&Transform>) {
    let p = q.get(w.body).unwrap().translation;
    w.poses = [w.poses[1], p];
}

fn check_interpolated(mut w: ResMut<Watch>, q: Query<&Transform>, time: Res<Time<Fixed>>) {
    let shown = q.get(w.body).unwrap().translation;
    let expected = w.poses[0].lerp(w.poses[1], time.overstep_fraction());
    w.worst = w.worst.max(shown.distance(expected));
    w.frames += 1;
}

fn app_watching(pacing: Pacing, sleeping: bool, velocity: Vec3) -> (App, Entity) {
    let mut app = paced_app_with(pacing, sleeping, |app| {
        app.add_plugins(TransformInterpolationPlugin::default());
    });
    let b = ball(&mut app, 0.5, 1.0, Vec3::Y * 5.0, velocity);
    app.world_mut().entity_mut(b).insert(TransformInterpolation);
    let p = pos(&app, b);
    app.insert_resource(Watch {
        body: b,
        poses: [p, p],
        worst: 0.0,
        frames: 0,
    })
    .add_systems(FixedUpdate, record.after(PhysicsSystems::Writeback))
    .add_systems(Update, check_interpolated);
    (app, b)
}

#[test]
fn the_shown_pose_blends_the_last_two_steps_and_physics_is_unchanged() {
    for pacing in [
        Pacing::Render(240.0),
        Pacing::Render(144.0),
        Pacing::Render(30.0),
    ] {
        let (mut app, b) = app_watching(pacing, false, Vec3::X);
        step(&mut app, 60);
        let w = app.world().resource::<Watch>();
        assert!(w.frames >= 30, "{pacing:?}: {} frames", w.frames);
        // lerp in f32 of poses a few metres apart.
        assert!(
            w.worst < 1e-5,
            "{pacing:?}: shown pose off by {} m",
            w.worst
        );
        // The physics pose (what the last step wrote) is that of a plain app.
        let mut plain = paced_app(pacing, false);
        let p = ball(
            &mut plain,
            0.5,
            1.0,
            Vec3::Y * 5.0,
            Vec3::new(1.0, 0.0, 0.0),
        );
        step(&mut plain, 60);
        let physics = app.world().resource::<Watch>().poses[1];
        assert_eq!(physics, pos(&plain, p), "{pacing:?}: physics changed");
        let _ = b;
    }
}

#[test]
fn a_body_at_rest_under_interpolation_still_falls_asleep_and_stays_asleep() {
    let (mut app, b) = app_watching(Pacing::Render(240.0), true, Vec3::ZERO);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    step(&mut app, 240);
    assert!(asleep(&app, b), "asleep after 4 s");
    let mut awake_steps = 0;
    for _ in 0..120 {
        step(&mut app, 1);
        awake_steps += !asleep(&app, b) as u32;
    }
    // Before tumble compared poses, every restore of the true pose woke it.
    assert_eq!(awake_steps, 0, "woken by the interpolation's writes");
}

#[derive(Resource)]
struct Ahead(Entity, f32);

fn check_extrapolated(
    mut a: ResMut<Ahead>,
    q: Query<&Transform>,
    time: Res<Time<Virtual>>,
    world: Res<PhysicsWorld>,
) {
    // Before the first step there is nothing to extrapolate from.
    if world.step_count() == 0 {
        return;
    }
    // Zero gravity, constant velocity: the true pose at the frame's time is exact.
    let shown = q.get(a.0).unwrap().translation;
    let truth = Vec3::new(2.0 * time.elapsed_secs(), 1.0, 0.0);
    a.1 = a.1.max(shown.distance(truth));
}

#[test]
fn extrapolation_runs_ahead_on_the_velocity() {
    for pacing in [Pacing::Render(240.0), Pacing::Render(144.0)] {
        let mut app = paced_app_with(pacing, false, |app| {
            app.add_plugins(PhysicsExtrapolationPlugin::default());
        });
        app.insert_resource(Gravity(Vec3::ZERO));
        let b = ball(&mut app, 0.5, 1.0, Vec3::Y, Vec3::X * 2.0);
        app.world_mut().entity_mut(b).insert(TransformExtrapolation);
        app.insert_resource(Ahead(b, 0.0))
            .add_systems(Update, check_extrapolated);
        step(&mut app, 60);
        let worst = app.world().resource::<Ahead>().1;
        // Exact up to f32 round-off of positions near 2 m.
        assert!(worst < 1e-5, "{pacing:?}: {worst} m from where it truly is");
    }
}
