//! Continuous collision against fixed colliders (`src/step/5_solve/continuous.rs`): a
//! body that an impact speeds up during a step, toward a wall it had no contact with at
//! the start of that step, stops at the wall instead of ending the step inside it.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// A 1 kg cube 10 cm from a wall, hit toward it by a 1000 kg cube at `speed`, in zero
/// gravity, at `substeps`. Returns how far the light cube's face got past the wall, m
/// (negative: it never reached it), and the most it went deeper in one step, m (from
/// the wall's face when it started outside).
fn deepest_into_wall(speed: f32, pacing: Pacing, substeps: u32) -> (f32, f32) {
    let mut app = paced_app(pacing, false);
    app.insert_resource(Gravity(Vec3::ZERO));
    app.world_mut().resource_mut::<SolverSettings>().substeps = substeps;
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
    let (mut deepest, mut gain, mut last) = (f32::MIN, f32::MIN, f32::MIN);
    for _ in 0..30 {
        step(&mut app, 1);
        let depth = pos(&app, light).x + h - 10.0;
        (deepest, gain) = (deepest.max(depth), gain.max(depth - last.max(0.0)));
        last = depth;
    }
    (deepest, gain)
}

/// The sweep's tolerance, then the soft contact's give under a 1000:1 squeeze.
fn allowed_depth() -> f32 {
    tumble::settings::CONTINUOUS_SLOP * SolverSettings::default().speculative_margin + 0.0086
}

#[test]
fn a_light_box_hit_toward_a_wall_stops_at_it() {
    for pacing in [Pacing::OneStep, Pacing::Render(240.0), Pacing::Render(30.0)] {
        for speed in [20.0, 50.0, 100.0] {
            let (d, _) = deepest_into_wall(speed, pacing, SolverSettings::default().substeps);
            eprintln!("{pacing:?} {speed} m/s: {d} m");
            assert!(
                d <= allowed_depth(),
                "{pacing:?}, {speed} m/s: {d} m into the wall"
            );
        }
    }
}

/// A regression. At 16 substeps the light box, struck in one step, flew at the wall at
/// 20 m/s from the start of the next, its wall contact already found; the heavy box
/// drove it through that contact (Gauss–Seidel hands the light box the heavy one's
/// speed again at every pass) along its own free path, which the sweep took for a path
/// no contact had changed: 0.22 m into the wall in one step. At 4 substeps the contact
/// held it back enough to leave that path, and the sweep caught it. Bodies that a
/// heavier one touches are now swept whenever they moved more than the slop (a quarter
/// of the margin), so in any step the light box goes about the slop deeper at most
/// (measured 5.7 mm at the face's centre, which a slight tilt puts past the slop that
/// bounds the deepest corner); asserted: less than the margin, which the 0.22 m broke.
/// Where the squeeze leaves it after is the soft contact's: 11 mm at 1, 2 and 4
/// substeps, 13–22 mm at 8 and 24–28 mm at 16 (printed below, not asserted: a limit of
/// the soft contact, not of the sweep).
#[test]
fn a_light_box_hit_toward_a_wall_stops_at_it_at_any_substeps() {
    let margin = SolverSettings::default().speculative_margin;
    for substeps in [1, 2, 8, 16] {
        for pacing in [Pacing::OneStep, Pacing::Render(30.0)] {
            for speed in [20.0, 50.0] {
                let (d, gain) = deepest_into_wall(speed, pacing, substeps);
                eprintln!("{substeps} substeps, {pacing:?} {speed} m/s: {d} m, {gain} m a step");
                assert!(
                    gain <= margin,
                    "{substeps} substeps, {pacing:?}, {speed} m/s: {gain} m deeper in a step"
                );
            }
        }
    }
}
