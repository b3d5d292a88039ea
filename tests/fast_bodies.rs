//! Fast bodies don't tunnel: contacts are created speculatively as far ahead as the pair
//! can close in one step, so a 200 m/s ball stops at a 10 cm wall.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn ball_at_200_mps_never_passes_a_thin_wall() {
    let mut app = app_without_gravity();
    // A static wall 0.1 m thick, its near face at x = 10.
    app.world_mut().spawn((
        Collider::cuboid(0.05, 2.0, 2.0),
        Transform::from_xyz(10.05, 0.0, 0.0),
    ));
    let b = ball(&mut app, 0.1, 1.0, Vec3::ZERO, Vec3::X * 200.0);
    for k in 0..60 {
        step(&mut app, 1);
        let x = pos(&app, b).x;
        assert!(
            x < 10.0 - 0.1 + 0.01,
            "step {k}: ball at x = {x}, inside or past the wall"
        );
    }
    assert!(
        vel(&app, b).linear.x <= 1e-3,
        "stopped or bounced back: {}",
        vel(&app, b).linear
    );
}

#[test]
fn fast_box_lands_on_the_ground_instead_of_falling_through() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::new(0.0, 3.0, 0.0));
    app.world_mut()
        .entity_mut(b)
        .insert(Velocity::linear(Vec3::NEG_Y * 150.0));
    step(&mut app, 60);
    let y = pos(&app, b).y;
    assert!((y - 0.25).abs() < 0.02, "box at y = {y}");
}
