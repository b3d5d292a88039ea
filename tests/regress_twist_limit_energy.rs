//! Regression: a ball joint's twist limit measured its angle about body 1's axis but
//! pushed along that same axis, where a swing also turns body 2 without twisting it. In
//! the ragdoll pile (shoulders and hips swinging up to 90°, twist ±0.5 rad) the limits
//! pushed the wrong way and the scene gained 2,300 J in 146 steps. The twist's rows now
//! lie midway between the two bodies' axes.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_twist_limit_under_a_wide_swing_adds_no_energy() {
    // A 1 kg, 1 m bar on a ball joint at its top end, its axis along −y; let go from the
    // horizontal spinning at 6 rad/s about its own axis, so it swings 90° and presses its
    // ±0.3 rad twist limits on the way.
    let mut app = app();
    let pivot = Vec3::new(0.0, 4.0, 0.0);
    let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let bar = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.05, 0.5, 0.05),
            Mass(1.0),
            Transform::from_translation(pivot + turn * Vec3::new(0.0, -0.5, 0.0))
                .with_rotation(turn),
            Velocity {
                linear: Vec3::ZERO,
                angular: turn * Vec3::Y * 6.0,
            },
        ))
        .id();
    app.world_mut().spawn(
        Joint::spherical(None, bar)
            .with_local_anchors(pivot, Vec3::Y * 0.5)
            .with_cone_limit(Vec3::NEG_Y, std::f32::consts::PI)
            .with_twist_limits(-0.3, 0.3),
    );
    // Inertia about the bar's centre (box 0.1 × 1 × 0.1 m): (1 + 0.01)/12 across, 0.02/12
    // along.
    let inertia = Vec3::new(1.01, 0.02, 1.01) / 12.0;
    let energy = |app: &App| {
        let (q, v) = (rot(app, bar), vel(app, bar));
        let w = q.inverse() * v.angular;
        0.5 * v.linear.length_squared() + 0.5 * w.dot(inertia * w) + G * pos(app, bar).y
    };
    let e0 = energy(&app);
    let mut highest = e0;
    for _ in 0..180 {
        step(&mut app, 1);
        highest = highest.max(energy(&app));
    }
    assert!(
        highest <= e0 + 1e-3 * e0.abs(),
        "energy rose from {e0} J to {highest} J"
    );
}
