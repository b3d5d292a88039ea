//! Degenerate values leaked out. A shape cast with a NaN rotation returned a hit whose
//! distance and point were NaN; a zero-length distance joint held its ball within a
//! millimetre of the pin but left it circling at 1 m/s (a distance row has no direction
//! to push along when the anchors coincide). Now a query given a NaN or zero-length
//! rotation, or a NaN origin, finds nothing, and a zero-length distance joint holds its
//! anchors together as a point and the ball comes to rest.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_query_given_a_nan_or_zero_rotation_or_origin_finds_nothing() {
    let mut app = app_with_sleeping();
    app.world_mut().spawn((
        Collider::cuboid(1.0, 1.0, 1.0),
        Transform::from_xyz(3.0, 0.0, 0.0),
    ));
    step(&mut app, 1);
    let f = SpatialQueryFilter::default();
    let ball = Collider::sphere(0.2);
    let nan = Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0);
    query(&mut app, |q| {
        // A usable rotation that is not unit length still works (it is normalized).
        let hit = q.cast_shape(&ball, Vec3::ZERO, Quat::IDENTITY * 2.0, Dir3::X, 10.0, &f);
        let hit = hit.expect("the wall is hit");
        assert_near(hit.distance, 1.8, 1e-4, "distance to the wall");
        for rotation in [nan, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0)] {
            assert!(
                q.cast_shape(&ball, Vec3::ZERO, rotation, Dir3::X, 10.0, &f)
                    .is_none()
            );
            assert!(
                q.shape_intersections(&ball, Vec3::X * 3.0, rotation, &f)
                    .is_empty()
            );
        }
        let nowhere = Vec3::new(f32::NAN, 0.0, 0.0);
        assert!(q.cast_ray(nowhere, Dir3::X, 10.0, true, &f).is_none());
        assert!(q.ray_hits(nowhere, Dir3::X, 10.0, 4, true, &f).is_empty());
        assert!(
            q.cast_ray(Vec3::ZERO, Dir3::X, f32::NAN, true, &f)
                .is_none()
        );
        assert!(q.project_point(nowhere, true, &f).is_none());
        assert!(q.point_intersections(nowhere, &f).is_empty());
        assert!(q.aabb_intersections(nowhere, Vec3::ONE, &f).is_empty());
    });
}

#[test]
fn a_zero_length_distance_joint_brings_its_ball_to_rest_at_the_pin() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        let pin = Vec3::new(0.0, 3.0, 0.0);
        let b = ball(&mut app, 0.2, 1.0, pin, Vec3::new(1.0, 0.0, 0.5));
        app.world_mut()
            .spawn(Joint::distance(None, b, 0.0).with_local_anchors(pin, Vec3::ZERO));
        step(&mut app, 120);
        let what = format!("{pacing:?}");
        assert!(pos(&app, b).distance(pin) < 1e-3, "{what}: at the pin");
        let speed = vel(&app, b).linear.length();
        assert!(
            speed < 1e-3,
            "{what}: still moving at {speed} m/s after 2 s"
        );
    }
}
