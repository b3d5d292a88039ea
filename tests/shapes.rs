//! Capsules, cylinders and cones (collided by parry3d) against analytic answers: where
//! they rest, how a cylinder rolls down a slope, where a cone's centre of mass puts it.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::{FRAC_PI_2, PI};
use tumble::prelude::*;

/// A dynamic body of `collider` at `p` turned by `rot`.
fn body(app: &mut App, collider: Collider, p: Vec3, rot: Quat) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            collider,
            Transform::from_translation(p).with_rotation(rot),
        ))
        .id()
}

/// Soft contacts sag under load by design, at most `max_sag` of the smaller size
/// (1 % by default); a body this size resting on the ground sits within that of its
/// geometric height.
fn sag(size: f32) -> f32 {
    SolverSettings::default().max_sag * size
}

#[test]
fn a_capsule_rests_on_its_side_at_its_radius_and_on_its_end_at_its_half_length() {
    let (r, h) = (0.25, 0.5);
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let side = body(
            &mut app,
            Collider::capsule(r, h),
            Vec3::new(-2.0, 0.6, 0.0),
            Quat::from_rotation_z(FRAC_PI_2),
        );
        let end = body(
            &mut app,
            Collider::capsule(r, h),
            Vec3::new(2.0, h + r + 0.1, 0.0),
            Quat::IDENTITY,
        );
        frames(&mut app, 180);
        let what = format!("{pacing:?}");
        assert_near(
            pos(&app, side).y,
            r,
            sag(2.0 * r),
            &format!("{what}: on its side"),
        );
        assert_near(
            pos(&app, end).y,
            h + r,
            sag(2.0 * r),
            &format!("{what}: on its end"),
        );
        // Upright on a hemisphere is a balance point: nothing pushed it off.
        assert!(tilt(&app, end) < 1e-3, "{what}: tilt {}", tilt(&app, end));
        assert!(vel(&app, side).linear.length() < 1e-2, "{what}: still");
    }
}

#[test]
fn a_cylinder_rests_on_its_end_and_on_its_side() {
    let (r, h) = (0.3, 0.4);
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let up = body(
        &mut app,
        Collider::cylinder(r, h),
        Vec3::new(0.0, h + 0.05, 0.0),
        Quat::IDENTITY,
    );
    let lying = body(
        &mut app,
        Collider::cylinder(r, h),
        Vec3::new(3.0, r + 0.05, 0.0),
        Quat::from_rotation_x(FRAC_PI_2),
    );
    step(&mut app, 180);
    assert_near(pos(&app, up).y, h, sag(2.0 * r), "on its end");
    assert!(
        tilt(&app, up) < 1e-3,
        "flat on its end: tilt {}",
        tilt(&app, up)
    );
    assert_near(pos(&app, lying).y, r, sag(2.0 * r), "on its side");
}

/// A solid cylinder rolling without slipping down a slope of angle θ accelerates at
/// a = (2/3)·g·sinθ (its inertia about its axis is m r²/2), and spins at ω = v / r.
/// A sliding block would take g·sinθ, a rolling ball (5/7)·g·sinθ: 1.5 and 1.07 times
/// as fast, both far outside the tolerance. Semi-implicit Euler gives a constant
/// acceleration's velocity exactly, so the speed after t is a·t up to the contacts.
#[test]
fn a_cylinder_rolls_down_a_slope_at_two_thirds_g_sin_theta() {
    let theta = 15f32.to_radians();
    let (r, h) = (0.2, 0.3);
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        // The slope falls toward +x; the cylinder's axis lies along z, across it.
        let slope = Quat::from_rotation_z(-theta);
        ground(&mut app, Vec3::ZERO, slope);
        let normal = slope * Vec3::Y;
        let down = slope * Vec3::X;
        let e = body(
            &mut app,
            Collider::cylinder(r, h),
            normal * r,
            slope * Quat::from_rotation_x(FRAC_PI_2),
        );
        // Let it settle into contact, then time one second of rolling.
        frames(&mut app, 6);
        let (s0, v0) = (steps_taken(&app), vel(&app, e).linear.dot(down));
        frames(&mut app, 60);
        let t = (steps_taken(&app) - s0) as f32 / 60.0;
        let v = vel(&app, e);
        let a = (v.linear.dot(down) - v0) / t;
        let expected = 2.0 / 3.0 * 9.81 * theta.sin();
        let what = format!("{pacing:?}");
        assert_near(
            a,
            expected,
            0.005 * expected,
            &format!("{what}: acceleration"),
        );
        // Rolling: the contact point is at rest, ω·r = v about the axis.
        let spin = v.angular.dot(slope * Vec3::Z).abs();
        let speed = v.linear.length();
        assert_near(spin * r, speed, 0.02 * speed, &format!("{what}: ω r = v"));
        // It stays on the slope.
        assert_near(
            pos(&app, e).dot(normal),
            r,
            sag(2.0 * r),
            &format!("{what}: on the slope"),
        );
    }
}

/// A cone's centre of mass is a quarter of its height above its base: standing on its
/// base it is stable; tipped 30° onto the rim of its base (less than the tipping angle
/// atan(r / (H/4)) = 56° for r = 0.3 m, H = 0.8 m) it falls back onto its base.
#[test]
fn a_cone_stands_on_its_base_and_rights_itself_from_a_tilt() {
    let (r, h) = (0.3f32, 0.4f32);
    let tipping = (r / (0.5 * h)).atan();
    assert!(tipping > 30f32.to_radians());
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let standing = body(
        &mut app,
        Collider::cone(r, h),
        Vec3::new(-2.0, h + 0.01, 0.0),
        Quat::IDENTITY,
    );
    // Tilted 30° about z, its base's lowest rim point just on the ground.
    let tilt0 = 30f32.to_radians();
    let q = Quat::from_rotation_z(tilt0);
    let rim = q * Vec3::new(r, -h, 0.0);
    let tilted = body(
        &mut app,
        Collider::cone(r, h),
        Vec3::new(2.0, -rim.y + 0.005, 0.0),
        q,
    );
    step(&mut app, 240);
    assert_near(
        pos(&app, standing).y,
        h,
        sag(2.0 * r),
        "standing: the base on the ground",
    );
    assert!(tilt(&app, standing) < 1e-3, "standing: upright");
    assert!(
        tilt(&app, tilted) < 0.01,
        "the tilted cone rights itself: tilt {}",
        tilt(&app, tilted)
    );
    assert_near(
        pos(&app, tilted).y,
        h,
        sag(2.0 * r),
        "righted: the base on the ground",
    );
    // The ground only pushes up and along: no energy from nowhere, it ends at rest.
    assert!(vel(&app, tilted).angular.length() < 0.05);
}

/// The three shapes' masses follow their volumes at the default density.
#[test]
fn new_shapes_weigh_their_volume() {
    let (r, h) = (0.3f32, 0.5f32);
    let cases = [
        (
            Collider::capsule(r, h),
            PI * r * r * 2.0 * h + 4.0 / 3.0 * PI * r.powi(3),
        ),
        (Collider::cylinder(r, h), PI * r * r * 2.0 * h),
        (Collider::cone(r, h), PI * r * r * 2.0 * h / 3.0),
    ];
    for (c, volume) in cases {
        assert_near(
            c.shape.volume(),
            volume,
            1e-5 * volume,
            &format!("{:?}", c.shape),
        );
    }
}
