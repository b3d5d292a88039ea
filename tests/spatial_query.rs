//! Spatial queries through the plugin: rays and casts against each shape at known
//! angles give closed-form distances and normals; queries see the poses of the last
//! completed step under every frame pacing; filters (layers, excluded bodies, sensors)
//! and compound parts report what they should.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, FRAC_PI_6};
use tumble::prelude::*;

/// A static collider at `p` turned by `rot`.
fn fixed(app: &mut App, collider: Collider, p: Vec3, rot: Quat) -> Entity {
    app.world_mut()
        .spawn((collider, Transform::from_translation(p).with_rotation(rot)))
        .id()
}

fn any() -> SpatialQueryFilter {
    SpatialQueryFilter::default()
}

/// Each shape, static at a known pose, hit by rays at known angles: distances exact to
/// 1e-5 m and normals to 1e-5.
#[test]
fn rays_hit_each_shape_where_geometry_says() {
    let mut app = app();
    let at = |x: f32| Vec3::new(x, 1.0, 0.0);
    let sphere = fixed(&mut app, Collider::sphere(0.5), at(0.0), Quat::IDENTITY);
    // A box turned 45° about z: its top is an edge at √2·h above its centre.
    let cube = fixed(
        &mut app,
        Collider::cuboid(0.5, 0.5, 0.5),
        at(3.0),
        Quat::from_rotation_z(FRAC_PI_4),
    );
    // A capsule lying along x: its top is its radius above the axis.
    let capsule = fixed(
        &mut app,
        Collider::capsule(0.3, 0.6),
        at(6.0),
        Quat::from_rotation_z(FRAC_PI_2),
    );
    let cylinder = fixed(
        &mut app,
        Collider::cylinder(0.4, 0.7),
        at(9.0),
        Quat::IDENTITY,
    );
    let cone = fixed(&mut app, Collider::cone(0.4, 0.5), at(12.0), Quat::IDENTITY);
    step(&mut app, 1);
    let down = |x: f32| (Vec3::new(x, 10.0, 0.0), Dir3::NEG_Y);
    let cases = [
        (sphere, 0.0, 10.0 - 1.5),
        (cube, 3.0, 10.0 - 1.0 - 0.5 * 2f32.sqrt()),
        (capsule, 6.0, 10.0 - 1.3),
        (cylinder, 9.0, 10.0 - 1.7),
        (cone, 12.0, 10.0 - 1.5),
    ];
    for (e, x, d) in cases {
        let (o, dir) = down(x);
        let hit = query(&mut app, |q| q.cast_ray(o, dir, 100.0, true, &any())).expect("a hit");
        assert_eq!(hit.entity, e);
        assert_eq!(hit.body, None, "static: no body");
        assert_near(hit.distance, d, 1e-5, "distance from above");
        assert_near_vec(hit.normal, Vec3::Y, 1e-5, "normal from above");
        assert_near_vec(hit.point, o + Vec3::NEG_Y * d, 1e-5, "point");
    }
    // The sphere from 30° below the horizontal, aimed at its centre: distance |o − c| − r,
    // normal back along the ray.
    let dir = Dir3::new(Vec3::new(FRAC_PI_6.cos(), -FRAC_PI_6.sin(), 0.0)).unwrap();
    let o = at(0.0) - *dir * 4.0;
    let hit = query(&mut app, |q| q.cast_ray(o, dir, 100.0, true, &any())).unwrap();
    assert_eq!(hit.entity, sphere);
    assert_near(hit.distance, 3.5, 1e-5, "slanted at the sphere");
    assert_near_vec(hit.normal, -*dir, 1e-5, "normal back along the ray");
    // The cylinder's side from between it and the capsule: distance to its radius.
    let o = at(9.0) + Vec3::new(-2.0, 0.2, 0.0);
    let hit = query(&mut app, |q| q.cast_ray(o, Dir3::X, 100.0, true, &any())).unwrap();
    assert_eq!(hit.entity, cylinder);
    assert_near(hit.distance, 2.0 - 0.4, 1e-5, "the cylinder's side");
    assert_near_vec(hit.normal, Vec3::NEG_X, 1e-5, "the side's normal");
    // The cone's slanted side, level with its centre (radius r/2 there), and from
    // inside it without `solid`: out through the side, the normal facing inward.
    let o = at(12.0) + Vec3::new(-1.0, 0.0, 0.0);
    let hit = query(&mut app, |q| q.cast_ray(o, Dir3::X, 100.0, true, &any())).unwrap();
    assert_near(hit.distance, 1.0 - 0.2, 1e-5, "the cone's side");
    // Its side leans in by atan(r / 2h): normal (−2h, r, 0)/√(4h² + r²).
    let lean = Vec3::new(-1.0, 0.4, 0.0).normalize();
    assert_near_vec(hit.normal, lean, 1e-5, "the cone's side normal");
    let hit = query(&mut app, |q| {
        q.cast_ray(at(12.0), Dir3::X, 100.0, false, &any())
    })
    .unwrap();
    assert_near(hit.distance, 0.2, 1e-5, "out of the cone");
    assert_near_vec(
        hit.normal,
        Vec3::new(-1.0, -0.4, 0.0).normalize(),
        1e-5,
        "inward",
    );
    // All hits along a row through every shape, nearest first; nothing past the last.
    let o = Vec3::new(-5.0, 1.0, 0.0);
    let hits = query(&mut app, |q| {
        q.ray_hits(o, Dir3::X, 100.0, 10, true, &any())
    });
    let order: Vec<_> = hits.iter().map(|h| h.entity).collect();
    assert_eq!(order, vec![sphere, cube, capsule, cylinder, cone]);
    assert!(hits.windows(2).all(|w| w[0].distance <= w[1].distance));
    assert_near(hits[0].distance, 4.5, 1e-5, "first along the row");
    let short = query(&mut app, |q| q.ray_hits(o, Dir3::X, 100.0, 2, true, &any()));
    assert_eq!(short.len(), 2);
}

/// Queries answer for the poses the last completed step left: a falling ball is found
/// where its Transform says, whatever the frame pacing (frames that run no step see the
/// same answer as the frame before).
#[test]
fn queries_see_the_last_completed_step_under_every_pacing() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        let r = 0.25;
        let ball = ball(&mut app, r, 1.0, Vec3::new(0.0, 20.0, 0.0), Vec3::ZERO);
        for _ in 0..40 {
            frames(&mut app, 1);
            let y = pos(&app, ball).y;
            let o = Vec3::new(0.0, 30.0, 0.0);
            let hit = query(&mut app, |q| {
                q.cast_ray(o, Dir3::NEG_Y, f32::MAX, true, &any())
            });
            if steps_taken(&app) == 0 {
                // Not simulated yet (a 240 Hz frame can run no step): not found either.
                assert!(hit.is_none(), "{pacing:?}: found before its first step");
                continue;
            }
            let hit = hit.expect("the ball is below");
            assert_eq!(hit.entity, ball);
            assert_eq!(hit.body, Some(ball));
            let what = format!("{pacing:?} at y {y}");
            assert_near(hit.distance, 30.0 - (y + r), 2e-5, &what);
        }
        assert!(pos(&app, ball).y < 19.9, "{pacing:?}: it fell");
    }
}

#[test]
fn filters_skip_layers_excluded_bodies_and_sensors() {
    tumble::physics_layers! { enum Layer { World, Player, Pickup } }
    let mut app = app();
    let floor = fixed(&mut app, Collider::plane(), Vec3::ZERO, Quat::IDENTITY);
    let player = app
        .world_mut()
        .spawn((
            RigidBody::Kinematic,
            Collider::capsule(0.3, 0.5),
            CollisionLayers::new(Layer::Player, LayerMask::ALL),
            Transform::from_xyz(0.0, 1.0, 0.0),
        ))
        .id();
    let pickup = app
        .world_mut()
        .spawn((
            Collider::sphere(0.2),
            Sensor,
            CollisionLayers::new(Layer::Pickup, Layer::Player),
            Transform::from_xyz(0.0, 3.0, 0.0),
        ))
        .id();
    step(&mut app, 2);
    let o = Vec3::new(0.0, 5.0, 0.0);
    let first = |app: &mut App, f: SpatialQueryFilter| {
        query(app, |q| q.cast_ray(o, Dir3::NEG_Y, 10.0, true, &f)).map(|h| h.entity)
    };
    assert_eq!(
        first(&mut app, any()),
        Some(pickup),
        "everything: the sensor first"
    );
    assert_eq!(first(&mut app, any().without_sensors()), Some(player));
    let not_me = any().without_sensors().with_excluded_entities([player]);
    assert_eq!(first(&mut app, not_me), Some(floor));
    assert_eq!(
        first(&mut app, SpatialQueryFilter::from_mask(Layer::World)),
        Some(floor)
    );
    assert_eq!(
        first(&mut app, SpatialQueryFilter::from_mask(Layer::Pickup)),
        Some(pickup)
    );
    assert_eq!(
        first(&mut app, SpatialQueryFilter::from_mask(LayerMask::NONE)),
        None
    );
    // A predicate sees each candidate's entity.
    let hit = query(&mut app, |q| {
        q.cast_ray_predicate(o, Dir3::NEG_Y, 10.0, true, &any(), &|e| {
            e != pickup && e != player
        })
    });
    assert_eq!(hit.map(|h| h.entity), Some(floor));
    // Overlap queries under the same filters.
    let inside = query(&mut app, |q| {
        q.point_intersections(Vec3::new(0.0, 1.0, 0.0), &any())
    });
    assert_eq!(inside, vec![player]);
    let under = query(&mut app, |q| {
        q.point_intersections(Vec3::new(0.0, -1.0, 0.0), &any())
    });
    assert_eq!(under, vec![floor], "below an infinite plane is inside it");
}

/// A ball cast at a wall stops one radius short of it; a box cast down onto the floor
/// stops its half height above it; a shape already overlapping hits at 0.
#[test]
fn shape_casts_stop_at_first_touch() {
    let mut app = app();
    let floor = fixed(&mut app, Collider::plane(), Vec3::ZERO, Quat::IDENTITY);
    let wall = fixed(
        &mut app,
        Collider::cuboid(0.5, 2.0, 2.0),
        Vec3::new(5.0, 2.0, 0.0),
        Quat::IDENTITY,
    );
    step(&mut app, 1);
    let r = 0.3;
    let ball = Collider::sphere(r);
    let hit = query(&mut app, |q| {
        q.cast_shape(
            &ball,
            Vec3::new(0.0, 1.0, 0.0),
            Quat::IDENTITY,
            Dir3::X,
            20.0,
            &any(),
        )
    })
    .unwrap();
    assert_eq!(hit.entity, wall);
    assert_near(hit.distance, 4.5 - r, 1e-4, "ball to wall");
    assert_near_vec(hit.normal, Vec3::NEG_X, 1e-4, "the wall's face");
    // The point is on the wall's face and on the ball's surface where it stopped (GJK
    // places it along the face only to its tolerance, ~1 mm).
    assert_near(hit.point.x, 4.5, 1e-4, "on the wall's face");
    let centre = Vec3::new(hit.distance, 1.0, 0.0);
    assert_near(hit.point.distance(centre), r, 1e-4, "on the ball");
    // A box turned 45° about y falls onto the floor on its bottom face.
    let crate_ = Collider::cuboid(0.4, 0.25, 0.4);
    let hit = query(&mut app, |q| {
        q.cast_shape(
            &crate_,
            Vec3::new(0.0, 3.0, 0.0),
            Quat::from_rotation_y(FRAC_PI_4),
            Dir3::NEG_Y,
            f32::MAX,
            &any(),
        )
    })
    .unwrap();
    assert_eq!(hit.entity, floor);
    assert_near(hit.distance, 3.0 - 0.25, 1e-4, "box to floor");
    assert_near_vec(hit.normal, Vec3::Y, 1e-4, "the floor's normal");
    // Starting inside the wall: distance 0.
    let hit = query(&mut app, |q| {
        q.cast_shape(
            &ball,
            Vec3::new(5.0, 1.0, 0.0),
            Quat::IDENTITY,
            Dir3::X,
            20.0,
            &any().with_excluded_entities([floor]),
        )
    })
    .unwrap();
    assert_eq!((hit.entity, hit.distance), (wall, 0.0));
    // Shape overlaps: a ball touching the wall's face, and one a hair off it.
    let touching = query(&mut app, |q| {
        q.shape_intersections(
            &ball,
            Vec3::new(4.5 - r + 1e-3, 1.0, 0.0),
            Quat::IDENTITY,
            &any(),
        )
    });
    assert_eq!(touching, vec![wall]);
    let apart = query(&mut app, |q| {
        q.shape_intersections(
            &ball,
            Vec3::new(4.5 - r - 1e-3, 1.0, 0.0),
            Quat::IDENTITY,
            &any(),
        )
    });
    assert!(apart.is_empty());
    // The nearest point: on the wall's face for a point beside it, on the floor below.
    let p = query(&mut app, |q| {
        q.project_point(Vec3::new(3.0, 2.0, 0.0), true, &any())
    })
    .unwrap();
    assert_eq!(p.entity, wall);
    assert_near_vec(
        p.point,
        Vec3::new(4.5, 2.0, 0.0),
        1e-5,
        "projected on the wall",
    );
    assert_near(p.distance, 1.5, 1e-5, "distance to the wall");
    let p = query(&mut app, |q| {
        q.project_point(Vec3::new(-30.0, 0.5, 0.0), true, &any())
    })
    .unwrap();
    assert_eq!((p.entity, p.is_inside), (floor, false));
    assert_near(p.distance, 0.5, 1e-5, "far away, the floor is nearest");
    let boxes = query(&mut app, |q| {
        q.aabb_intersections(Vec3::new(4.0, 3.9, -0.1), Vec3::new(4.6, 4.5, 0.1), &any())
    });
    assert_eq!(boxes, vec![wall]);
}

/// A compound body's part is hit as itself, and reports the body it belongs to; the
/// body's entity excludes all its parts.
#[test]
fn compound_parts_report_their_body() {
    let mut app = app_without_gravity();
    let body = app
        .world_mut()
        .spawn((RigidBody::Dynamic, Transform::from_xyz(0.0, 2.0, 0.0)))
        .id();
    let part = app
        .world_mut()
        .spawn((
            Collider::cuboid(0.5, 0.1, 0.5),
            Transform::from_xyz(1.0, 0.0, 0.0),
            ChildOf(body),
        ))
        .id();
    step(&mut app, 2);
    let o = Vec3::new(1.0, 10.0, 0.0);
    let hit = query(&mut app, |q| {
        q.cast_ray(o, Dir3::NEG_Y, 100.0, true, &any())
    })
    .unwrap();
    assert_eq!((hit.entity, hit.body), (part, Some(body)));
    assert_near(hit.distance, 10.0 - 2.1, 1e-5, "the part's top");
    let f = any().with_excluded_entities([body]);
    assert!(query(&mut app, |q| q.cast_ray(o, Dir3::NEG_Y, 100.0, true, &f)).is_none());
}
