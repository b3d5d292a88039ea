//! `Transform::scale` scales colliders: a box per axis, a sphere uniformly (unevenly: its
//! largest axis, with a warning), and the mass that follows from the volume.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_scaled_box_rests_at_its_scaled_height() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let scale = Vec3::new(2.0, 3.0, 0.5);
        let b = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Collider::cuboid(0.5, 0.5, 0.5),
                Mass(1.0),
                Transform::from_xyz(0.0, 3.0, 0.0).with_scale(scale),
            ))
            .id();
        step(app, 120);
        // Half height 0.5 · 3 = 1.5 m, less the resting sag (< 1 mm).
        assert_near(pos(app, b).y, 1.5, 1e-3, &format!("{what}: rests at 1.5 m"));
        assert_eq!(
            app.world().get::<Transform>(b).unwrap().scale,
            scale,
            "{what}: scale kept"
        );
    });
}

#[test]
fn a_scaled_static_floor_and_sphere() {
    let mut app = app();
    // A 1 m slab scaled to 10 m wide and 0.2 m thick, its top at y = 0.
    app.world_mut().spawn((
        Collider::cuboid(0.5, 0.5, 0.5),
        Transform::from_xyz(0.0, -0.1, 0.0).with_scale(Vec3::new(10.0, 0.2, 10.0)),
    ));
    let b = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.25),
            Mass(1.0),
            Transform::from_xyz(3.0, 2.0, 0.0).with_scale(Vec3::splat(2.0)),
        ))
        .id();
    step(&mut app, 120);
    assert_near(
        pos(&app, b).y,
        0.5,
        1e-3,
        "a 0.25 m ball scaled ×2 rests at 0.5 m",
    );
}

#[test]
fn the_mass_of_a_scaled_body_follows_its_volume() {
    let mut app = app_without_gravity();
    let b = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.5, 0.5),
            Transform::from_scale(Vec3::new(2.0, 1.0, 1.0)),
            ExternalImpulse::new(Vec3::X * 200.0),
        ))
        .id();
    step(&mut app, 1);
    // 2 m³ of water: 2000 kg.
    assert_near(vel(&app, b).linear.x, 0.1, 1e-6, "Δv = J/(ρ·V·sx)");
}
