//! A user's system ordered after the writeback stage sees this step's velocities.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[derive(Resource, Default)]
struct Seen(Vec<f32>);

fn record(mut seen: ResMut<Seen>, q: Query<&Velocity>) {
    for v in &q {
        seen.0.push(v.linear.y);
    }
}

#[test]
fn system_after_writeback_reads_this_steps_velocity() {
    let mut app = app();
    app.init_resource::<Seen>()
        .add_systems(FixedUpdate, record.after(PhysicsSystems::Writeback));
    ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 10);
    let seen = &app.world().resource::<Seen>().0;
    assert_eq!(seen.len(), 10);
    for (k, v) in seen.iter().enumerate() {
        let expected = -9.81 * H * (k + 1) as f32;
        assert!(
            (v - expected).abs() < 1e-5,
            "step {}: saw {v}, expected {expected}",
            k + 1
        );
    }
}

#[test]
fn time_fixed_inserted_after_the_plugin_sets_the_step() {
    let mut app = app();
    app.insert_resource(Time::<Fixed>::from_hz(120.0));
    let e = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 12);
    // 12 steps of 1/120 s: v = −g·0.1 s.
    assert!(
        (vel(&app, e).linear.y + 0.981).abs() < 1e-5,
        "{}",
        vel(&app, e).linear.y
    );
}

#[test]
fn integrator_switches_between_steps() {
    // Explicit Euler moves with the old velocity, so its first step leaves a body at rest
    // where it was; semi-implicit moves it at once.
    let mut app = app();
    app.insert_resource(Integrator::ExplicitEuler);
    app.world_mut().resource_mut::<SolverSettings>().substeps = 1;
    let e = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 1);
    assert_eq!(pos(&app, e).y, 0.0);
    app.insert_resource(Integrator::SemiImplicitEuler);
    step(&mut app, 1);
    // v1 = −gh after the first step; semi-implicit: v2 = −2gh, y = −2gh².
    let expected = -2.0 * 9.81 * H * H;
    assert!(
        (pos(&app, e).y - expected).abs() < 1e-6,
        "{} vs {expected}",
        pos(&app, e).y
    );
}
