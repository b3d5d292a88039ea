//! Continuous collision against fixed colliders (`src/step/5_solve/continuous.rs`): a
//! body that an impact speeds up during a step, toward a wall it had no contact with at
//! the start of that step, stops at the wall instead of ending the step inside it.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// A 1 kg cube 10 cm from a wall, hit toward it by a 1000 kg cube at `speed`, in zero
/// gravity. Returns how far the light cube's face got past the wall, m (negative: it
/// never reached it).
fn deepest_into_wall(speed: f32, pacing: Pacing) -> f32 {
    let mut app = paced_app(pacing, false);
    app.insert_resource(Gravity(Vec3::ZERO));
    // The wall: the plane x = 10, facing −x.
    let wall = Quat::from_rotation_arc(Vec3::Y, Vec3::NEG_X);
    app.world_mut().spawn((
        Collider::plane(),
        Transform::from_xyz(10.0, 0.0, 0.0).with_rotation(wall),
    ));
    let h = 0.25;
    let light = cuboid(
        &mut app,
        Vec3::splat(h),
        1.0,
        Vec3::new(10.0 - h - 0.1, 0.0, 0.0),
    );
    // The heavy cube starts a metre short of the light one.
    let heavy = cuboid(
        &mut app,
        Vec3::splat(h),
        1000.0,
        Vec3::new(10.0 - 3.0 * h - 1.1, 0.0, 0.0),
    );
    app.world_mut()
        .entity_mut(heavy)
        .insert((Velocity::linear(Vec3::X * speed), Restitution(0.0)));
    let mut deepest = f32::MIN;
    for _ in 0..30 {
        step(&mut app, 1);
        deepest = deepest.max(pos(&app, light).x + h - 10.0);
    }
    deepest
}

#[test]
fn a_light_box_hit_toward_a_wall_stops_at_it() {
    let margin = SolverSettings::default().speculative_margin;
    for pacing in [Pacing::OneStep, Pacing::Render(240.0), Pacing::Render(30.0)] {
        for speed in [20.0, 50.0, 100.0] {
            let d = deepest_into_wall(speed, pacing);
            eprintln!("{pacing:?} {speed} m/s: {d} m");
            // The sweep's tolerance, then the soft contact's give under a 1000:1 squeeze.
            assert!(
                d <= tumble::settings::CONTINUOUS_SLOP * margin + 0.0086,
                "{pacing:?}, {speed} m/s: {d} m into the wall"
            );
        }
    }
}

#[test]
fn a_small_body_stops_within_a_tenth_of_its_size() {
    // A 2 cm cube 5 cm from the wall (beyond the speculative margin: no wall contact at
    // the start of the step), hit toward it at 20 and 50 m/s by a 100 kg cube: at the end
    // of the step it reaches the wall, it is at most a tenth of its size in
    // (SLOP_OF_THICKNESS; the fixed 5 mm would be a quarter of it). Later steps' squeeze
    // is the soft contact's, not the sweep's.
    let h = 0.01;
    for speed in [20.0, 50.0] {
        let mut app = app_without_gravity();
        let wall = Quat::from_rotation_arc(Vec3::Y, Vec3::NEG_X);
        app.world_mut().spawn((
            Collider::plane(),
            Transform::from_xyz(10.0, 0.0, 0.0).with_rotation(wall),
        ));
        let light = cuboid(
            &mut app,
            Vec3::splat(h),
            1.0,
            Vec3::new(10.0 - h - 0.05, 0.0, 0.0),
        );
        let heavy = cuboid(&mut app, Vec3::splat(h), 100.0, Vec3::new(9.0, 0.0, 0.0));
        app.world_mut()
            .entity_mut(heavy)
            .insert(Velocity::linear(Vec3::X * speed));
        let first = (0..60)
            .map(|_| {
                step(&mut app, 1);
                pos(&app, light).x + h - 10.0
            })
            .find(|&d| d > -1e-4)
            .expect("reaches the wall");
        let bound = tumble::settings::SLOP_OF_THICKNESS * 2.0 * h;
        assert!(
            first <= bound + 1e-5,
            "{speed} m/s: {first} m into the wall (bound {bound})"
        );
    }
}
