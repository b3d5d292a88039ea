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
    app.init_resource::<Seen>().add_systems(FixedUpdate, record.after(PhysicsSystems::Writeback));
    ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 10);
    let seen = &app.world().resource::<Seen>().0;
    assert_eq!(seen.len(), 10);
    for (k, v) in seen.iter().enumerate() {
        let expected = -9.81 * H * (k + 1) as f32;
        assert!((v - expected).abs() < 1e-5, "step {}: saw {v}, expected {expected}", k + 1);
    }
}
