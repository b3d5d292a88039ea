//! Two spheres meeting head-on (masses 1 and 3): the 1D collision formulas for e = 1 and
//! e = 0.5, and conservation of momentum.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn collide(e: f32) {
    let mut app = app_without_gravity();
    let (m1, m2, v1, v2) = (1.0, 3.0, 3.0, -1.0);
    let a = ball(&mut app, 0.5, m1, Vec3::new(-2.0, 0.0, 0.0), Vec3::X * v1);
    let b = ball(&mut app, 0.5, m2, Vec3::new(2.0, 0.0, 0.0), Vec3::X * v2);
    for ent in [a, b] {
        app.world_mut()
            .entity_mut(ent)
            .insert((Restitution(e), Friction(0.0)));
    }
    step(&mut app, 90);
    let (u1, u2) = (vel(&app, a).linear, vel(&app, b).linear);
    let expect1 = ((m1 - e * m2) * v1 + (1.0 + e) * m2 * v2) / (m1 + m2);
    let expect2 = ((m2 - e * m1) * v2 + (1.0 + e) * m1 * v1) / (m1 + m2);
    assert!(
        (u1.x - expect1).abs() < 1e-4,
        "e={e}: v1' = {u1}, expected {expect1}"
    );
    assert!(
        (u2.x - expect2).abs() < 1e-4,
        "e={e}: v2' = {u2}, expected {expect2}"
    );
    let p0 = m1 * v1 + m2 * v2;
    let p1 = m1 * u1 + m2 * u2;
    assert!(
        (p1.x - p0).abs() < 1e-5 && p1.yz().length() < 1e-5,
        "momentum {p0} → {p1}"
    );
    assert!(pos(&app, a).x < pos(&app, b).x - 1.0, "they separated");
}

#[test]
fn elastic_head_on() {
    collide(1.0);
}

#[test]
fn half_elastic_head_on() {
    collide(0.5);
}

#[test]
fn glancing_elastic_equal_masses_leave_at_right_angles() {
    let mut app = app_without_gravity();
    let a = ball(&mut app, 0.5, 1.0, Vec3::new(-3.0, 0.4, 0.1), Vec3::X * 4.0);
    let b = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    for ent in [a, b] {
        app.world_mut()
            .entity_mut(ent)
            .insert((Restitution(1.0), Friction(0.0)));
    }
    step(&mut app, 60);
    let (u1, u2) = (vel(&app, a).linear, vel(&app, b).linear);
    assert!(
        u2.length() > 1.0 && u1.length() > 1.0,
        "both move: {u1} {u2}"
    );
    let angle = u1.angle_between(u2).to_degrees();
    assert!((angle - 90.0).abs() < 1.0, "angle {angle}°");
    assert!(
        (u1.length_squared() + u2.length_squared() - 16.0).abs() < 1e-3,
        "energy kept"
    );
}
