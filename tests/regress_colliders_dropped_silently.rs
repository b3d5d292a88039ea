//! Colliders were dropped or mis-sized without a word. A convex hull under a flattening
//! scale (1, 0, 1) could not be rebuilt and simulated at its unscaled size, while the
//! same cube as a box was refused; a collider more than 32 levels below its body was
//! ignored, and its body rested on its other parts. Now the hull is refused like the
//! box, and the walk below a body goes as deep as the hierarchy does.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn cube_points() -> Vec<Vec3> {
    let mut points = Vec::new();
    for x in [-0.5, 0.5] {
        for y in [-0.5, 0.5] {
            for z in [-0.5, 0.5] {
                points.push(Vec3::new(x, y, z));
            }
        }
    }
    points
}

#[test]
fn a_hull_that_scaling_flattens_is_refused_like_the_box() {
    let mut app = app_with_sleeping();
    let flat = Vec3::new(1.0, 0.0, 1.0);
    let hull = Collider::convex_hull(&cube_points()).expect("a cube hull");
    let at = Transform::from_xyz(0.0, 2.0, 0.0).with_scale(flat);
    let as_hull = app
        .world_mut()
        .spawn((RigidBody::Dynamic, hull.clone(), at))
        .id();
    let as_box = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.5, 0.5),
            at.with_translation(Vec3::X * 3.0),
        ))
        .id();
    let static_hull = app
        .world_mut()
        .spawn((hull, at.with_translation(Vec3::X * 6.0)))
        .id();
    step(&mut app, 2);
    assert_eq!(rejected_field(&app, as_box), Some("Collider"));
    assert_eq!(rejected_field(&app, as_hull), Some("Collider"));
    assert_eq!(rejected_field(&app, static_hull), Some("Collider"));
}

#[test]
fn a_part_forty_levels_below_its_body_carries_it() {
    let mut app = app_with_sleeping();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Mass(1.0),
            Transform::from_xyz(0.0, 1.0, 0.0),
        ))
        .id();
    let mut parent = body;
    for _ in 0..40 {
        parent = app
            .world_mut()
            .spawn((Transform::default(), ChildOf(parent)))
            .id();
    }
    // The only collider: a 0.5 m cube 40 levels down, 0.5 m below the body's origin.
    app.world_mut().spawn((
        Collider::cuboid(0.25, 0.25, 0.25),
        Transform::from_xyz(0.0, -0.5, 0.0),
        ChildOf(parent),
    ));
    step(&mut app, 90);
    // Resting on its part: the part's centre 0.25 m up, the body's origin 0.5 m above it.
    assert_near(
        pos(&app, body).y,
        0.75,
        2e-3,
        "body's height on its deep part",
    );
}
