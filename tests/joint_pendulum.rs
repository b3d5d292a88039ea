//! Pendulums on joints against their analytic periods: a point mass on a rigid rod (a
//! distance joint at its centre of mass) at small amplitude, 2π√(L/g); the same at 90°,
//! 4√(L/g)·K(sin 45°) with K the complete elliptic integral of the first kind; and a
//! solid ball on a ball joint above its centre (a physical pendulum),
//! 2π√((L² + ⅖r²)/(gL)). 60 Hz, 4 substeps (the defaults), no air.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// The pivot, m (world).
const PIVOT: Vec3 = Vec3::new(0.0, 5.0, 0.0);

/// A pendulum of length `l` let go at `angle` rad from the vertical, its bob a ball of
/// radius `r` held by `joint` (given the bob). Returns the app and the bob.
fn pendulum(l: f32, angle: f32, r: f32, joint: impl Fn(Entity) -> Joint) -> (App, Entity) {
    let mut app = app();
    let at = PIVOT + Vec3::new(l * angle.sin(), -l * angle.cos(), 0.0);
    let bob = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(r),
            Mass(1.0),
            Transform::from_translation(at),
        ))
        .id();
    app.world_mut().spawn(joint(bob));
    (app, bob)
}

/// The mean period over the first `swings` full swings, s: from the times the bob
/// crosses the vertical going the same way (interpolated within a step).
fn period(app: &mut App, bob: Entity, swings: usize) -> f32 {
    let mut crossings = Vec::new();
    let mut last = pos(app, bob).x - PIVOT.x;
    let mut t = 0.0;
    while crossings.len() <= swings {
        step(app, 1);
        t += H;
        let x = pos(app, bob).x - PIVOT.x;
        if last > 0.0 && x <= 0.0 {
            crossings.push(t - H * x / (x - last));
        }
        last = x;
        assert!(t < 60.0, "the pendulum stopped swinging");
    }
    (crossings[swings] - crossings[0]) / swings as f32
}

/// The complete elliptic integral of the first kind K(k), by the arithmetic–geometric
/// mean: π / (2·agm(1, √(1 − k²))).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn a_small_swing_keeps_the_simple_pendulums_period() {
    let (l, angle) = (2.0, 0.05);
    let (mut app, bob) = pendulum(l, angle, 0.05, |bob| {
        Joint::distance(None, bob, l).with_local_anchors(PIVOT, Vec3::ZERO)
    });
    let t = period(&mut app, bob, 5);
    // 2π√(L/g), with the first amplitude terms (1 + θ²/16): 1.6e-4 here.
    let expected = std::f32::consts::TAU * (l / G).sqrt() * (1.0 + angle * angle / 16.0);
    assert_near(t, expected, 0.005 * expected, "period at 0.05 rad, s");
    // The rod holds its length.
    let length = pos(&app, bob).distance(PIVOT);
    assert_near(length, l, 0.001 * l, "rod length, m");
}

#[test]
fn a_swing_from_the_horizontal_keeps_the_elliptic_period() {
    let (l, angle) = (1.0, std::f32::consts::FRAC_PI_2);
    let (mut app, bob) = pendulum(l, angle, 0.05, |bob| {
        Joint::distance(None, bob, l).with_local_anchors(PIVOT, Vec3::ZERO)
    });
    let t = period(&mut app, bob, 3);
    let k = elliptic_k((angle as f64 / 2.0).sin()) as f32;
    let expected = 4.0 * (l / G).sqrt() * k;
    assert_near(t, expected, 0.005 * expected, "period from 90°, s");
}

#[test]
fn a_ball_on_a_ball_joint_swings_as_a_physical_pendulum() {
    // The joint holds the ball at a point l above its centre: the ball turns as it swings,
    // so its own inertia ⅖mr² adds to ml².
    let (l, r, angle) = (1.5, 0.3, 0.05);
    let (mut app, bob) = pendulum(l, angle, r, |bob| {
        // The anchor on the ball: l from its centre toward the pivot.
        let toward = Vec3::new(-angle.sin(), angle.cos(), 0.0) * l;
        Joint::spherical(None, bob).with_local_anchors(PIVOT, toward)
    });
    let t = period(&mut app, bob, 5);
    let expected = std::f32::consts::TAU
        * ((l * l + 0.4 * r * r) / (G * l)).sqrt()
        * (1.0 + angle * angle / 16.0);
    assert_near(t, expected, 0.005 * expected, "physical pendulum period, s");
}

#[test]
fn more_substeps_never_cost_a_pendulum_energy() {
    // 1 m from 60°, 20 s at 60 Hz: the swing energy's drift at 4, 16 and 64 substeps. The
    // joint stiffens with the substep rate (at half the contacts' cap): at a fixed 60 Hz
    // its damping would work on the compliance it leaves, and the drift grows from
    // −9.9e-5 at 16 substeps to −8.0e-4 at 64.
    let drift = |substeps: u32| {
        let mut app = app();
        app.world_mut().resource_mut::<SolverSettings>().substeps = substeps;
        let (l, angle) = (1.0f32, 60f32.to_radians());
        let at = PIVOT + Vec3::new(l * angle.sin(), -l * angle.cos(), 0.0);
        let bob = ball(&mut app, 0.05, 1.0, at, Vec3::ZERO);
        app.world_mut()
            .spawn(Joint::distance(None, bob, l).with_local_anchors(PIVOT, Vec3::ZERO));
        let lowest = PIVOT.y - l;
        let energy = |app: &App| {
            0.5 * vel(app, bob).linear.length_squared() + G * (pos(app, bob).y - lowest)
        };
        let e0 = energy(&app);
        step(&mut app, 1200);
        (energy(&app) / e0 - 1.0).abs()
    };
    let (d4, d16, d64) = (drift(4), drift(16), drift(64));
    assert!(d4 < 2e-3, "4 substeps: {d4:.2e}");
    assert!(
        d16 <= d4 && d64 <= d16,
        "drift {d4:.2e}, {d16:.2e}, {d64:.2e} at 4, 16, 64"
    );
}
