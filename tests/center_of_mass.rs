//! A centre of mass away from the collider's centre (`CenterOfMass`): the body turns
//! about it and gravity pulls at it. A ball weighted low (a self-righting toy) tipped
//! on the ground rocks back and forth like a physical pendulum about its contact point;
//! the same ball without the offset is neutral and stays where it is put. Under every
//! game pacing.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// Radius (m), mass (kg) and how far below the centre the centre of mass sits (m).
const R: f32 = 0.5;
const M: f32 = 1.0;
const D: f32 = 0.2;

/// Signed tilt about z, rad: positive when the body's +Y leans towards −x.
fn roll(app: &App, e: Entity) -> f32 {
    let up = rot(app, e) * Vec3::Y;
    (-up.x).atan2(up.y)
}

fn weeble(app: &mut App, tilt: f32, offset: bool) -> Entity {
    ground(app, Vec3::ZERO, Quat::IDENTITY);
    let e = ball(app, R, M, Vec3::Y * R, Vec3::ZERO);
    let mut body = app.world_mut().entity_mut(e);
    body.get_mut::<Transform>().unwrap().rotation = Quat::from_rotation_z(tilt);
    if offset {
        body.insert(CenterOfMass(Vec3::NEG_Y * D));
    }
    e
}

/// Rolling without slipping, the contact point P is an instantaneous pivot: the centre
/// of mass is R − D above it and D·sinθ to the side, so for small angles
/// θ'' = −m·g·D·θ / (I + m·(R − D)²), with I = 2/5·m·R² (the offset moves no mass).
#[test]
fn a_ball_weighted_low_rocks_with_the_physical_pendulum_period() {
    under_every_pacing(&Pacing::GAME, &[false], |app, _, pacing| {
        let what = format!("{pacing:?}");
        let theta0 = 0.1;
        let e = weeble(app, theta0, true);
        let inertia = 0.4 * M * R * R;
        let omega = (M * G * D / (inertia + M * (R - D) * (R - D))).sqrt();
        let period = std::f32::consts::TAU / omega;
        // Zero crossings of the tilt, interpolated between steps.
        let mut crossings = Vec::new();
        let mut peak = 0.0f32;
        let mut last = roll(app, e);
        for k in 1..=(3.2 * period / H) as usize {
            step(app, 1);
            let now = roll(app, e);
            peak = peak.max(now.abs());
            if (last > 0.0) != (now > 0.0) {
                crossings.push((k as f32 - now / (now - last)) * H);
            }
            last = now;
        }
        assert!(crossings.len() >= 5, "{what}: it rocks: {crossings:?}");
        // Two periods between the first and fifth crossing. Tolerance: 1 % — the
        // amplitude correction θ0²/16 is 0.06 %, the step interpolation error well under
        // a step over two periods (0.4 %), and the soft contact's sag (≈ 0.1 mm) moves
        // the pivot by far less.
        let measured = (crossings[4] - crossings[0]) / 2.0;
        assert_near(measured, period, 0.01 * period, &format!("{what}: period"));
        // Rolling on a rough floor loses nothing and gains nothing.
        assert!(peak <= theta0 * 1.01, "{what}: tilt grew to {peak}");
        assert!(
            roll(app, e).abs() <= theta0 * 1.01,
            "{what}: still rocking within the start"
        );
        // It rolls: its centre moves by R·Δθ, staying on the floor.
        assert_near(
            pos(app, e).y,
            R,
            1e-3,
            &format!("{what}: the ball's centre stays at R"),
        );
    });
}

/// Without the offset the ball is neutral: tipped, it stays put.
#[test]
fn the_same_ball_with_its_centre_of_mass_in_the_middle_stays_where_put() {
    let mut app = app();
    let e = weeble(&mut app, 0.1, false);
    step(&mut app, 120);
    assert_near(roll(&app, e), 0.1, 1e-4, "no restoring torque");
}

/// A weeble tipped 1 rad and dropped from 1 cm stands back up: released, its tilt swings
/// through zero at once (within a quarter period) and never exceeds the start.
#[test]
fn a_weeble_tipped_far_swings_back_upright() {
    let mut app = app();
    let e = weeble(&mut app, 1.0, true);
    let mut through_zero = None;
    let mut peak = 0.0f32;
    for k in 1..=120 {
        step(&mut app, 1);
        let now = roll(&app, e);
        peak = peak.max(now.abs());
        if now < 0.0 && through_zero.is_none() {
            through_zero = Some(k);
        }
    }
    let k = through_zero.expect("it swings through upright");
    // A quarter of the small-angle period is 0.49 s; a 1 rad swing takes a little longer.
    assert!(k as f32 * H < 0.7, "upright after {} s", k as f32 * H);
    assert!(peak <= 1.0 + 1e-3, "tilt grew to {peak}");
}

/// The body's Velocity is its centre of mass's: a weeble thrown with Velocity v spinning
/// at ω in zero gravity keeps its centre of mass moving in a straight line at v while its
/// origin circles it at distance D.
#[test]
fn velocity_and_the_path_are_the_centre_of_masss() {
    let mut app = app_without_gravity();
    let (v, w) = (Vec3::new(1.0, 0.5, 0.0), 2.0);
    let e = ball(&mut app, R, M, Vec3::ZERO, v);
    app.world_mut().entity_mut(e).insert((
        CenterOfMass(Vec3::NEG_Y * D),
        Velocity {
            linear: v,
            angular: Vec3::Z * w,
        },
    ));
    let com0 = Vec3::NEG_Y * D;
    step(&mut app, 60);
    let t = 60.0 * H;
    let tf = *app.world().get::<Transform>(e).unwrap();
    let com = CenterOfMass(Vec3::NEG_Y * D).world(&tf);
    assert_near_vec(com, com0 + v * t, 1e-4, "centre of mass in a straight line");
    assert_near(tf.translation.distance(com), D, 1e-5, "origin at D from it");
    assert_near_vec(vel(&app, e).linear, v, 1e-5, "Velocity is the centre's");
    let turned = 2.0 * (tf.rotation.z).atan2(tf.rotation.w);
    assert_near(turned, w * t, 1e-3, "turned by ω·t");
}

/// A bad offset is refused by name, and the body comes back when it is fixed.
#[test]
fn a_non_finite_centre_of_mass_is_refused_and_fixing_it_readmits_the_body() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let e = ball(&mut app, R, M, Vec3::Y * 2.0, Vec3::ZERO);
    app.world_mut()
        .entity_mut(e)
        .insert(CenterOfMass(Vec3::new(f32::NAN, 0.0, 0.0)));
    step(&mut app, 10);
    assert_eq!(rejected_field(&app, e), Some("CenterOfMass"));
    assert_near(pos(&app, e).y, 2.0, 0.0, "frozen while refused");
    app.world_mut()
        .entity_mut(e)
        .insert(CenterOfMass(Vec3::ZERO));
    step(&mut app, 10);
    assert_eq!(rejected_field(&app, e), None);
    assert!(pos(&app, e).y < 2.0, "falls once fixed");
}
