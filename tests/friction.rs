//! Coulomb friction: boxes on a ramp stick or slide by μ against tan θ, a sliding box stops
//! at v²/(2μg) in every direction (a round friction cone), and a sliding ball turns its
//! slide into rolling at 5/7 of its speed; a box spun flat on the floor stops at the rate
//! its corners' friction gives.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const G: f32 = 9.81;

#[test]
fn boxes_on_a_ramp_stick_or_slide_by_their_friction() {
    let theta = 0.25f32;
    let tilt_q = Quat::from_rotation_z(theta);
    let (n, down) = (tilt_q * Vec3::Y, tilt_q * Vec3::NEG_X);
    let mut app = app();
    let ramp = ground(&mut app, Vec3::ZERO, tilt_q);
    app.world_mut().entity_mut(ramp).insert(Friction(1.0));
    let mus = [0.4f32, 0.3, 0.26, 0.2, 0.1, 0.0];
    let boxes: Vec<_> = mus
        .iter()
        .enumerate()
        .map(|(i, &mu)| {
            let p = n * 0.5 + Vec3::Z * (i as f32 * 2.0);
            let e = cuboid(&mut app, Vec3::splat(0.5), 1.0, p);
            // The ramp has μ = 1, so the combined √(μ_box·1) equals μ when the box has μ².
            app.world_mut().entity_mut(e).insert((
                Friction(mu * mu),
                Transform::from_translation(p).with_rotation(tilt_q),
            ));
            e
        })
        .collect();
    // Settle, then measure over 5 s.
    step(&mut app, 30);
    let start: Vec<_> = boxes
        .iter()
        .map(|&e| (pos(&app, e), vel(&app, e).linear.dot(down)))
        .collect();
    step(&mut app, 300);
    for ((&mu, &e), (p0, v0)) in mus.iter().zip(&boxes).zip(start) {
        let travelled = (pos(&app, e) - p0).dot(down);
        if mu > theta.tan() {
            assert!(travelled.abs() < 1e-3, "μ={mu}: crept {travelled} m");
        } else {
            // Constant acceleration from v0 over 5 s: d = v0·t + ½·a·t².
            let a = (travelled - v0 * 5.0) * 2.0 / 25.0;
            let expected = G * (theta.sin() - mu * theta.cos());
            assert!(
                (a - expected).abs() < 0.01 * expected,
                "μ={mu}: a = {a}, expected {expected}"
            );
        }
    }
}

#[test]
fn sliding_box_stops_at_the_same_distance_in_every_direction() {
    let (v0, mu) = (5.0f32, 0.5f32);
    let expected = v0 * v0 / (2.0 * mu * G);
    let mut app = app();
    let g = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    app.world_mut().entity_mut(g).insert(Friction(mu));
    let runs: Vec<_> = (0..12)
        .map(|k| {
            let dir = Quat::from_rotation_y(k as f32 * 30f32.to_radians()) * Vec3::X;
            let p = Vec3::new(0.0, 0.5, 0.0)
                + Quat::from_rotation_y(k as f32 * 30f32.to_radians()) * Vec3::new(0.0, 0.0, 30.0);
            let e = cuboid(&mut app, Vec3::splat(0.5), 1.0, p);
            app.world_mut()
                .entity_mut(e)
                .insert((Friction(mu), Velocity::linear(dir * v0)));
            (e, p, dir)
        })
        .collect();
    step(&mut app, 120);
    let dists: Vec<f32> = runs
        .iter()
        .map(|&(e, p, dir)| (pos(&app, e) - p).dot(dir))
        .collect();
    for (k, d) in dists.iter().enumerate() {
        assert!(
            (d - expected).abs() < 0.02 * expected,
            "direction {}°: stopped after {d} m, expected {expected}",
            k * 30
        );
    }
    let (lo, hi) = dists
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &d| (lo.min(d), hi.max(d)));
    assert!((hi - lo) < 0.02 * lo, "distances spread {lo}..{hi}");
}

#[test]
fn sliding_ball_rolls_at_five_sevenths_of_its_speed() {
    let (v0, mu, r) = (7.0f32, 0.3f32, 0.5f32);
    let mut app = app();
    let g = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    app.world_mut().entity_mut(g).insert(Friction(mu));
    let b = ball(&mut app, r, 1.0, Vec3::Y * r, Vec3::X * v0);
    app.world_mut().entity_mut(b).insert(Friction(mu));
    let t_star = 2.0 * v0 / (7.0 * mu * G);
    let first_rolling_step = (t_star / H).ceil() as usize + 3;
    for k in 1..=60 {
        step(&mut app, 1);
        let v = vel(&app, b);
        let slip = (v.linear + v.angular.cross(Vec3::NEG_Y * r)).length();
        if k >= first_rolling_step {
            assert!(slip < 0.05, "step {k}: slip {slip} m/s");
        }
    }
    let speed = vel(&app, b).linear.length();
    assert!((speed - 5.0).abs() < 0.05, "speed after 1 s: {speed}");
}

#[test]
fn spinning_box_on_the_floor_stops_at_the_rate_its_corners_friction_gives() {
    // A cube of half extent h rests on its four corners, each carrying m·g/4 at h·√2
    // from the centre: friction μ·m·g·h·√2 about the vertical against the inertia
    // m·(2h)²/6 = (2/3)·m·h², so the spin falls at α = 1.5·√2·μ·g/h and stops at ω0/α.
    let (omega0, mu, h) = (10.0f32, 0.5f32, 0.5f32);
    let alpha = 1.5 * 2f32.sqrt() * mu * G / h;
    let mut app = app();
    let g = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    app.world_mut().entity_mut(g).insert(Friction(mu));
    let start = Vec3::Y * h;
    let e = cuboid(&mut app, Vec3::splat(h), 1.0, start);
    step(&mut app, 10);
    let spin = |app: &App| vel(app, e).angular.y;
    assert!(spin(&app).abs() < 1e-3, "at rest: {}", spin(&app));
    app.world_mut().entity_mut(e).insert((
        Friction(mu),
        Velocity {
            linear: Vec3::ZERO,
            angular: Vec3::Y * omega0,
        },
    ));
    let stop = omega0 / alpha;
    // Over the first 60 % of the stop time the spin falls at α (the first step runs
    // with last step's impulses, so measure from the second).
    step(&mut app, 1);
    let (w1, t1) = (spin(&app), H);
    let steps = (0.6 * stop / H) as usize;
    step(&mut app, steps);
    let (w2, t2) = (spin(&app), H * (steps + 1) as f32);
    let measured = (w1 - w2) / (t2 - t1);
    // The four loads are equal by symmetry, so only rounding and the soft contacts'
    // settling separate the rate from α (measured: 1e-5 of it).
    assert_near(measured, alpha, 1e-3 * alpha, "spin-down rate, rad/s²");
    // It stops, and stays stopped (friction never turns it back), where it was.
    step(&mut app, (0.6 * stop / H) as usize);
    assert!(spin(&app).abs() < 1e-2, "still spinning at {}", spin(&app));
    let drift = (pos(&app, e) - start) * Vec3::new(1.0, 0.0, 1.0);
    assert!(drift.length() < 1e-3, "walked {drift} while spinning");
    let tilt = vel(&app, e).angular.xz().length();
    assert!(tilt < 1e-2, "rocking at {tilt} rad/s");
}
