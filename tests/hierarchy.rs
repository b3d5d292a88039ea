//! Entities with parents: a static collider nested under transformed parents collides
//! where the chain puts it; a body under a moved parent is simulated in the world and
//! keeps a local Transform; what is not supported (a body under another body, a body
//! under an unevenly scaled parent) is refused with the reason, never simulated in the
//! wrong place.

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

/// A body under a parent moved, turned and scaled 2× is simulated in the world and
/// written back in its parent's frame: it falls onto the ground, rests at its scaled
/// radius, and its local Transform is the world pose seen from the parent.
#[test]
fn a_body_under_a_moved_parent_falls_in_the_world_and_stays_local() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let parent = Transform::from_xyz(3.0, 10.0, 0.0)
            .with_rotation(Quat::from_rotation_y(0.5))
            .with_scale(Vec3::splat(2.0));
        let holder = app.world_mut().spawn(parent).id();
        let b = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Collider::sphere(0.3),
                Mass(1.0),
                Transform::from_xyz(0.0, -2.0, 0.0),
                ChildOf(holder),
            ))
            .id();
        step(app, 150);
        // World: straight down from (3, 6, 0) to rest at the scaled radius 0.6.
        let local = pos(app, b);
        let world = parent.transform_point(local);
        assert_near_vec(
            world,
            Vec3::new(3.0, 0.6, 0.0),
            1e-3,
            &format!("{what}: rests in the world"),
        );
        assert_near(local.y, (0.6 - 10.0) / 2.0, 1e-3, &format!("{what}: local"));
        assert!(
            rot(app, b).angle_between(Quat::IDENTITY) < 1e-4,
            "{what}: the local rotation undoes the parent's"
        );
        assert_eq!(rejected_field(app, b), None, "{what}");
    });
}

#[test]
fn what_is_not_supported_yet_is_refused_not_misplaced() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let body = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y * 2.0);
    // A body under another body: they would move as one without a joint.
    let child_body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.3),
            Transform::from_xyz(2.0, 0.0, 0.0),
            ChildOf(body),
        ))
        .id();
    // A body under a parent scaled unevenly: its frame would shear.
    let stretched = app
        .world_mut()
        .spawn(Transform::from_xyz(5.0, 3.0, 0.0).with_scale(Vec3::new(1.0, 2.0, 1.0)))
        .id();
    let sheared = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.3),
            Transform::default(),
            ChildOf(stretched),
        ))
        .id();
    step(&mut app, 60);
    assert_eq!(rejected_field(&app, child_body), Some("ChildOf"));
    assert_eq!(rejected_field(&app, sheared), Some("ChildOf"));
    // The body itself rests on the ground, not on a ghost of its child.
    assert_near(pos(&app, body).y, 0.5, 1e-3, "the body lands on the ground");
    let contacts = app
        .world()
        .resource::<PhysicsWorld>()
        .contacts_of(body)
        .count();
    assert_eq!(contacts, 1, "only the ground");
}
