//! Entities with parents: a static collider nested under transformed parents collides
//! where the chain puts it; what is not supported yet (a collider on a body's child, a
//! body under a moved parent) is refused with the reason, never simulated in the wrong
//! place.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_nested_static_floor_is_where_its_parents_put_it() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        // A level root moved 5 m down and 10 m along x, a group under it turned a quarter
        // turn about y, and the floor slab under that: its top ends up at y = −5.
        let root = app
            .world_mut()
            .spawn(Transform::from_xyz(10.0, -5.0, 0.0))
            .id();
        let group = app
            .world_mut()
            .spawn((
                Transform::from_rotation(Quat::from_rotation_y(1.0)),
                ChildOf(root),
            ))
            .id();
        app.world_mut().spawn((
            Collider::cuboid(3.0, 0.5, 3.0),
            Transform::from_xyz(0.0, -0.5, 0.0),
            ChildOf(group),
        ));
        let b = ball(app, 0.5, 1.0, Vec3::new(10.0, 0.0, 0.0), Vec3::ZERO);
        step(app, 90);
        assert_near(
            pos(app, b).y,
            -4.5,
            1e-3,
            &format!("{what}: rests on the nested floor"),
        );
    });
}

#[test]
fn what_is_not_supported_yet_is_refused_not_misplaced() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let body = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y * 2.0);
    // A collider on the body's child: a compound body. Before, it became a static
    // collider at its local coordinates.
    let part = app
        .world_mut()
        .spawn((
            Collider::sphere(0.3),
            Transform::from_xyz(0.0, 1.0, 0.0),
            ChildOf(body),
        ))
        .id();
    // A body under a parent away from the origin.
    let holder = app
        .world_mut()
        .spawn(Transform::from_xyz(0.0, 10.0, 0.0))
        .id();
    let child_body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.3),
            Transform::default(),
            ChildOf(holder),
        ))
        .id();
    step(&mut app, 60);
    assert_eq!(rejected_field(&app, part), Some("ChildOf"));
    assert_eq!(rejected_field(&app, child_body), Some("ChildOf"));
    // The body itself rests on the ground, not on a ghost of its part.
    assert_near(pos(&app, body).y, 0.5, 1e-3, "the body lands on the ground");
    let contacts = app
        .world()
        .resource::<PhysicsWorld>()
        .contacts_of(body)
        .count();
    assert_eq!(contacts, 1, "only the ground");
}
