//! Every shape collides with every other: each cell of the shape-by-shape table runs here.
//!
//! Moving shapes (sphere, box, capsule, cylinder, cone, convex hull) meet each other head
//! on in zero gravity: they must touch, never pass through or sink in more than 5 mm, and
//! conserve the pair's momentum. Each moving shape also falls onto each shape that only
//! stands still (infinite and bounded plane, triangle mesh, heightfield) and comes to
//! rest on it.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn hull() -> Collider {
    // An irregular hull: a box with one corner cut off, so its centre of mass is off
    // its origin and its axes are not the box's.
    let mut points: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) * 0.5 - 0.25
        })
        .collect();
    points[7] = Vec3::splat(0.05);
    Collider::convex_hull(&points).unwrap()
}

fn movers() -> Vec<(&'static str, Collider)> {
    vec![
        ("sphere", Collider::sphere(0.3)),
        ("box", Collider::cuboid(0.3, 0.25, 0.2)),
        ("capsule", Collider::capsule(0.2, 0.3)),
        ("cylinder", Collider::cylinder(0.3, 0.25)),
        ("cone", Collider::cone(0.3, 0.3)),
        ("hull", hull()),
    ]
}

fn grounds() -> Vec<(&'static str, Collider)> {
    let quad = vec![
        Vec3::new(-5.0, 0.0, -5.0),
        Vec3::new(5.0, 0.0, -5.0),
        Vec3::new(5.0, 0.0, 5.0),
        Vec3::new(-5.0, 0.0, 5.0),
    ];
    vec![
        ("plane", Collider::plane()),
        ("plane_rect", Collider::plane_rect(5.0, 5.0)),
        (
            "trimesh",
            Collider::trimesh(quad, vec![[0, 2, 1], [0, 3, 2]]).unwrap(),
        ),
        (
            "heightfield",
            Collider::heightfield(&vec![vec![0.0; 6]; 6], Vec2::splat(10.0)).unwrap(),
        ),
    ]
}

fn touches(app: &App, a: Entity, b: Entity) -> bool {
    app.world()
        .resource::<PhysicsWorld>()
        .contacts_of(a)
        .any(|c| c.other == b)
}

#[test]
fn every_moving_shape_meets_every_other_head_on() {
    let (mass_a, mass_b) = (2.0, 3.0);
    for (na, a) in movers() {
        for (nb, b) in movers() {
            let what = format!("{na} into {nb}");
            let mut app = app_without_gravity();
            // Slightly off the line of centres and turned, so no pair meets only on a
            // symmetry axis.
            let ea = app
                .world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    a.clone(),
                    Mass(mass_a),
                    Transform::from_xyz(-1.2, 0.03, 0.02).with_rotation(Quat::from_rotation_z(0.1)),
                    Velocity::linear(Vec3::X * 2.0),
                ))
                .id();
            let eb = app
                .world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    b.clone(),
                    Mass(mass_b),
                    Transform::from_xyz(0.0, 0.0, 0.0).with_rotation(Quat::from_rotation_y(0.2)),
                ))
                .id();
            let p0 = mass_a * Vec3::X * 2.0;
            let (mut touched, mut deepest) = (false, 0.0f32);
            for _ in 0..60 {
                step(&mut app, 1);
                touched |= touches(&app, ea, eb);
                deepest = deepest.max(app.world().resource::<PhysicsWorld>().deepest_overlap());
            }
            assert!(touched, "{what}: never touched");
            assert!(deepest < 5e-3, "{what}: sank {deepest} m in");
            assert!(pos(&app, ea).x < pos(&app, eb).x, "{what}: passed through");
            let p1 = mass_a * vel(&app, ea).linear + mass_b * vel(&app, eb).linear;
            assert_near_vec(p1, p0, 1e-3 * p0.length(), &format!("{what}: momentum"));
        }
    }
}

#[test]
fn every_moving_shape_comes_to_rest_on_every_ground() {
    for (ng, g) in grounds() {
        for (na, a) in movers() {
            let what = format!("{na} on {ng}");
            let mut app = app();
            let ground = app
                .world_mut()
                .spawn((g.clone(), Transform::default()))
                .id();
            let body = app
                .world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    a.clone(),
                    Transform::from_xyz(0.5, 0.8, -0.3),
                ))
                .id();
            step(&mut app, 150);
            // Resting: touching, or asleep (a sleeper keeps no contact; where it lies is
            // checked below).
            let resting = touches(&app, body, ground) || asleep(&app, body);
            assert!(resting, "{what}: neither touching nor asleep");
            let overlap = app.world().resource::<PhysicsWorld>().deepest_overlap();
            assert!(overlap < 5e-3, "{what}: sank {overlap} m in");
            assert!(
                vel(&app, body).linear.length() < 0.02,
                "{what}: still moving {:?}",
                vel(&app, body)
            );
            // Its lowest point on the ground, within the contacts' sag.
            let (lo, _) = a.shape.aabb(pos(&app, body), rot(&app, body));
            assert!(lo.y.abs() < 5e-3, "{what}: lowest point at {}", lo.y);
        }
    }
}
