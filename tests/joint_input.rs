//! Joints under the robustness rules: bad input (NaN anchors, a zero axis, limits the
//! wrong way round) is refused by field and nothing else breaks; a joint to a despawned
//! body is removed; a joint between two statics is ignored; jointed bodies do not
//! collide unless asked; and a jointed scene steps alike under every frame pacing.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn ball_at(app: &mut App, p: Vec3) -> Entity {
    ball(app, 0.2, 1.0, p, Vec3::ZERO)
}

#[test]
fn bad_joint_input_is_refused_by_field_and_the_rest_steps_on() {
    let mut app = app();
    let a = ball_at(&mut app, Vec3::new(0.0, 5.0, 0.0));
    let b = ball_at(&mut app, Vec3::new(1.0, 5.0, 0.0));
    let nan = Vec3::new(f32::NAN, 0.0, 0.0);
    let cases = [
        (
            Joint::spherical(a, b).with_local_anchors(nan, Vec3::ZERO),
            "Joint.local_anchor1",
        ),
        (Joint::revolute(a, b, Vec3::ZERO), "Joint.local_axis1"),
        (
            Joint::revolute(a, b, Vec3::Z).with_limits(1.0, -1.0),
            "Joint.kind.limits",
        ),
        (Joint::distance(a, b, -1.0), "Joint.kind"),
        (
            Joint::prismatic(a, b, Vec3::X).with_motor(1.0, f32::INFINITY),
            "Joint.kind.motor.max_force",
        ),
        (
            Joint::spherical(a, b).with_break_force(0.0),
            "Joint.break_force",
        ),
    ];
    let joints: Vec<(Entity, &str)> = cases
        .into_iter()
        .map(|(j, field)| (app.world_mut().spawn(j).id(), field))
        .collect();
    step(&mut app, 30);
    for (joint, field) in &joints {
        assert_eq!(rejected_field(&app, *joint), Some(*field));
    }
    // None of them acted: both balls fell freely, side by side.
    let t = 30.0 * H;
    for e in [a, b] {
        assert_free_fall(5.0 - pos(&app, e).y, t, "ball under a refused joint");
    }
    // Fixed, the joint is taken back: the NaN anchor made good holds the balls 1 m apart.
    let (first, _) = joints[0];
    app.world_mut()
        .entity_mut(first)
        .insert(Joint::distance(a, b, 1.0));
    step(&mut app, 60);
    assert_eq!(rejected_field(&app, first), None);
    assert_near(
        pos(&app, a).distance(pos(&app, b)),
        1.0,
        1e-3,
        "rod length, m",
    );
}

#[test]
fn a_joint_to_a_despawned_body_is_removed() {
    let mut app = app();
    let a = ball_at(&mut app, Vec3::new(0.0, 5.0, 0.0));
    let b = ball_at(&mut app, Vec3::new(1.0, 5.0, 0.0));
    let joint = app.world_mut().spawn(Joint::distance(a, b, 1.0)).id();
    step(&mut app, 10);
    app.world_mut().despawn(b);
    step(&mut app, 10);
    assert!(app.world().get::<Joint>(joint).is_none(), "joint kept");
    // The other ball falls on freely.
    let v = vel(&app, a).linear;
    assert!(v.is_finite() && v.y < 0.0, "{v}");
}

#[test]
fn a_joint_between_two_statics_is_ignored() {
    let mut app = app();
    let ground = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let wall = app
        .world_mut()
        .spawn((
            RigidBody::Static,
            Collider::cuboid(1.0, 1.0, 1.0),
            Transform::from_xyz(3.0, 1.0, 0.0),
        ))
        .id();
    app.world_mut().spawn(Joint::fixed(ground, wall));
    let falling = ball_at(&mut app, Vec3::new(-3.0, 4.0, 0.0));
    step(&mut app, 20);
    assert_free_fall(
        4.0 - pos(&app, falling).y,
        20.0 * H,
        "ball beside the ignored joint",
    );
}

#[test]
fn jointed_bodies_do_not_collide_unless_asked() {
    // Two overlapping balls held 0.1 m apart by a rod: without collisions between them
    // they stay so; with them, their contact pushes against the rod.
    for collide in [false, true] {
        let mut app = app_without_gravity();
        let a = ball_at(&mut app, Vec3::ZERO);
        let b = ball_at(&mut app, Vec3::new(0.1, 0.0, 0.0));
        let mut joint = Joint::distance(a, b, 0.1);
        if collide {
            joint = joint.with_collisions();
        }
        let joint = app.world_mut().spawn(joint).id();
        step(&mut app, 30);
        let push = app
            .world()
            .get::<JointForces>(joint)
            .unwrap()
            .force
            .length();
        if collide {
            assert!(push > 1.0, "the contact pushes on the rod: {push} N");
        } else {
            assert!(push < 1e-3, "nothing pushes on the rod: {push} N");
            assert!(vel(&app, a).linear.length() < 1e-4);
        }
    }
}

#[test]
fn a_jointed_scene_steps_alike_under_every_frame_pacing() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, _, _| {
        let pivot = Vec3::new(0.0, 4.0, 0.0);
        let bob = ball(app, 0.2, 1.0, Vec3::new(1.0, 4.0, 0.0), Vec3::ZERO);
        app.world_mut()
            .spawn(Joint::distance(None, bob, 1.0).with_local_anchors(pivot, Vec3::ZERO));
        let second = ball(app, 0.2, 1.0, Vec3::new(2.0, 4.0, 0.0), Vec3::ZERO);
        app.world_mut().spawn(
            Joint::revolute(bob, second, Vec3::Z)
                .with_local_anchors(Vec3::new(0.5, 0.0, 0.0), Vec3::new(-0.5, 0.0, 0.0))
                .with_limits(-1.0, 1.0),
        );
        step(app, 90);
    });
}
