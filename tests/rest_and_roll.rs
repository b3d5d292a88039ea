//! Resting and rolling on planes: a ball at rest stays put, and a ball on a 30° slope
//! rolls without slipping with a = 5/7·g·sin θ.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn ball_rests_on_plane_for_ten_seconds() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.5, 1.0, Vec3::Y * 0.5, Vec3::ZERO);
    step(&mut app, 600);
    let y = pos(&app, b).y;
    assert!(y > 0.499 && y < 0.5001, "sank to {y}");
    let v = vel(&app, b);
    let ke = 0.5 * v.linear.length_squared() + 0.5 * 0.1 * v.angular.length_squared();
    assert!(ke < 1e-6, "kinetic energy {ke} J");
}

#[test]
fn ball_rolls_down_slope_at_five_sevenths_g_sin_theta() {
    let mut app = app();
    let theta = 30f32.to_radians();
    let tilt = Quat::from_rotation_z(theta);
    let g = ground(&mut app, Vec3::ZERO, tilt);
    app.world_mut().entity_mut(g).insert(Friction(0.5));
    let n = tilt * Vec3::Y;
    let b = ball(&mut app, 0.5, 1.0, n * 0.5, Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Friction(0.5));
    step(&mut app, 30);
    let v0 = vel(&app, b).linear.length();
    step(&mut app, 60);
    let v1 = vel(&app, b).linear.length();
    let a = (v1 - v0) / 1.0;
    let expected = 5.0 / 7.0 * 9.81 * theta.sin();
    assert!(
        (a - expected).abs() < 0.02 * expected,
        "a = {a}, expected {expected}"
    );
    // Rolling: the contact point does not slip.
    let v = vel(&app, b);
    let slip = v.linear + v.angular.cross(-n * 0.5);
    assert!(slip.length() < 0.01, "slip {slip}");
}
