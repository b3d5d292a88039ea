//! Regression: a joint to a static body spawned in the same frame as its first step read
//! the static body's `GlobalTransform`, which Bevy computes only after the fixed steps of
//! that frame: still the identity. The door scene's post stood at (0, 1.1, 0), the joint
//! took it at the origin and yanked the 20 kg door 1.1 m down in one step (its energy
//! went from 682 J to 3135 J). A root static body is now read by its `Transform`.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_hinge_to_a_static_post_spawned_this_frame_holds_where_the_post_is() {
    let mut app = app_without_gravity();
    let post = app
        .world_mut()
        .spawn((
            RigidBody::Static,
            Collider::cuboid(0.05, 1.0, 0.05),
            Transform::from_xyz(0.0, 1.1, 0.0),
        ))
        .id();
    let door = cuboid(
        &mut app,
        Vec3::new(0.5, 1.0, 0.03),
        20.0,
        Vec3::new(0.56, 1.1, 0.0),
    );
    app.world_mut().spawn(
        Joint::revolute(post, door, Vec3::Y)
            .with_local_anchors(Vec3::new(0.06, 0.0, 0.0), Vec3::new(-0.5, 0.0, 0.0)),
    );
    step(&mut app, 10);
    // Nothing pulls on it: it stays where it was spawned.
    assert_near_vec(pos(&app, door), Vec3::new(0.56, 1.1, 0.0), 1e-4, "door, m");
    assert!(vel(&app, door).linear.length() < 1e-4);
}
