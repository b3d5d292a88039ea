//! Bad input is rejected per body with the offending field named, never panics, and never
//! reaches other bodies.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn each_bad_field_rejects_only_its_body() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let good = ball(&mut app, 0.5, 1.0, Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO);
    let cases: Vec<(Entity, &str)> = vec![
        (
            ball(
                &mut app,
                0.5,
                1.0,
                Vec3::new(f32::NAN, 2.0, 0.0),
                Vec3::ZERO,
            ),
            "Transform.translation",
        ),
        (
            ball(
                &mut app,
                0.5,
                1.0,
                Vec3::new(0.5, f32::INFINITY, 0.0),
                Vec3::ZERO,
            ),
            "Transform.translation",
        ),
        (
            ball(
                &mut app,
                0.5,
                1.0,
                Vec3::new(0.4, 2.0, 0.0),
                Vec3::new(f32::NAN, 0.0, 0.0),
            ),
            "Velocity.linear",
        ),
        (
            ball(&mut app, 0.5, 0.0, Vec3::new(0.3, 2.0, 0.0), Vec3::ZERO),
            "Mass",
        ),
        (
            ball(&mut app, 0.5, -1.0, Vec3::new(0.2, 2.0, 0.0), Vec3::ZERO),
            "Mass",
        ),
        (
            ball(
                &mut app,
                0.5,
                f32::INFINITY,
                Vec3::new(0.1, 2.0, 0.0),
                Vec3::ZERO,
            ),
            "Mass",
        ),
        (
            ball(&mut app, 0.0, 1.0, Vec3::new(0.0, 2.5, 0.0), Vec3::ZERO),
            "Collider",
        ),
        (
            ball(&mut app, -0.5, 1.0, Vec3::new(0.0, 2.4, 0.0), Vec3::ZERO),
            "Collider",
        ),
        (
            app.world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    Collider::cuboid(0.5, f32::NAN, 0.5),
                    Transform::from_xyz(0.0, 2.3, 0.0),
                ))
                .id(),
            "Collider",
        ),
        (
            app.world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    Collider::sphere(0.5),
                    Transform::from_xyz(0.0, 2.2, 0.0),
                    Velocity {
                        linear: Vec3::ZERO,
                        angular: Vec3::splat(f32::NEG_INFINITY),
                    },
                ))
                .id(),
            "Velocity.angular",
        ),
    ];
    let before: Vec<Transform> = cases
        .iter()
        .map(|(e, _)| *app.world().get::<Transform>(*e).unwrap())
        .collect();
    step(&mut app, 120);
    for ((e, field), tf) in cases.iter().zip(before) {
        assert_eq!(rejected_field(&app, *e), Some(*field), "entity {e}");
        let now = app.world().get::<Transform>(*e).unwrap();
        assert!(
            now.translation.x.to_bits() == tf.translation.x.to_bits()
                && now.translation.y.to_bits() == tf.translation.y.to_bits(),
            "rejected body did not move"
        );
    }
    // The good ball overlaps several of the rejected ones and still lands normally.
    let p = pos(&app, good);
    assert!(
        p.is_finite() && (p.y - 0.5).abs() < 0.01,
        "good ball at {p}"
    );
    assert!(rejected_field(&app, good).is_none());
}

#[test]
fn body_that_blows_up_is_frozen_and_its_neighbour_stays_finite() {
    // Explicit Euler gains energy on a tumbling box every step (the seed engine's story):
    // at 60 Hz with one substep its spin grows without bound. The bystander is a ball
    // resting against the box, so whatever the box's state becomes crosses their contact.
    let mut app = app_without_gravity();
    app.insert_resource(Integrator::ExplicitEuler);
    app.world_mut().resource_mut::<SolverSettings>().substeps = 1;
    let wild = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.05, 0.2),
            Mass(1.0),
            Transform::default(),
            Velocity {
                linear: Vec3::ZERO,
                angular: Vec3::new(1.0, 0.0, 10.0),
            },
        ))
        .id();
    let bystander = ball(&mut app, 0.25, 1.0, Vec3::new(0.0, 0.8, 0.0), Vec3::ZERO);
    let mut steps = 0;
    while rejected_field(&app, wild).is_none() {
        step(&mut app, 1);
        steps += 1;
        assert!(steps < 3600, "explicit Euler's box never blew up");
        let v = vel(&app, bystander);
        assert!(
            v.linear.is_finite() && v.angular.is_finite() && pos(&app, bystander).is_finite(),
            "step {steps}: the bystander went non-finite"
        );
        assert!(rejected_field(&app, bystander).is_none(), "step {steps}");
    }
    // Frozen where it was, at its last finite pose, and named.
    let field = rejected_field(&app, wild).unwrap();
    assert!(
        ["Transform", "Velocity.angular", "Velocity.linear"].contains(&field),
        "rejected for {field}"
    );
    let tf = *app.world().get::<Transform>(wild).unwrap();
    assert!(tf.translation.is_finite() && tf.rotation.is_finite());
    step(&mut app, 10);
    assert_eq!(*app.world().get::<Transform>(wild).unwrap(), tf, "frozen");
}
