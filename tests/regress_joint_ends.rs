//! A joint's ends were taken on trust. A joint whose two ends were the same entity threw
//! its ball at tens of thousands of m/s (the joint pulled one anchor towards the other
//! on the same body); a joint to an entity that is not a body (only a `Name`) read it as
//! a still side at the world origin and dragged its body there; a joint to a compound
//! body's part held that part still in the world. Now each end must be a body, a static
//! collider or a body's part (which acts on its body, at the part's pose), the two ends
//! must be two bodies, and a joint that breaks this is refused by field, logged once,
//! leaves its bodies alone, and comes back when its ends are made right.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn floating_ball(app: &mut App, p: Vec3, v: Vec3) -> Entity {
    let e = ball(app, 0.2, 1.0, p, v);
    app.world_mut().entity_mut(e).insert(GravityScale(0.0));
    e
}

#[test]
fn a_joint_whose_ends_are_one_body_is_refused_and_the_body_moves_freely() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        let v = Vec3::new(1.0, 0.0, 0.0);
        let a = floating_ball(&mut app, Vec3::ZERO, v);
        let joint = Joint::spherical(a, a).with_local_anchors(Vec3::X * 0.5, -Vec3::X * 0.5);
        let joint = app.world_mut().spawn(joint).id();
        step(&mut app, 30);
        assert_eq!(
            rejected_field(&app, joint),
            Some("Joint.body2"),
            "{pacing:?}"
        );
        assert_near_vec(
            vel(&app, a).linear,
            v,
            1e-6,
            &format!("{pacing:?}: velocity"),
        );
        assert_near_vec(
            pos(&app, a),
            v * 30.0 * H,
            1e-4,
            &format!("{pacing:?}: place"),
        );
    }
}

#[test]
fn a_joint_to_an_entity_that_is_not_a_body_is_refused_until_it_becomes_one() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        let start = Vec3::new(3.0, 2.0, 0.0);
        let a = floating_ball(&mut app, start, Vec3::ZERO);
        let named = app.world_mut().spawn(Name::new("not a body")).id();
        let hold = Joint::fixed(named, a).with_local_anchors(Vec3::new(0.0, -1.0, 0.0), Vec3::ZERO);
        let joint = app.world_mut().spawn(hold).id();
        step(&mut app, 30);
        assert_eq!(
            rejected_field(&app, joint),
            Some("Joint.body1"),
            "{pacing:?}"
        );
        assert_eq!(pos(&app, a), start, "{pacing:?}: the ball was not dragged");
        // Made a static body at (3, 3, 0), 1 m above the ball: the joint takes hold and
        // pins the ball where it is, under gravity.
        app.world_mut()
            .entity_mut(named)
            .insert((RigidBody::Static, Transform::from_xyz(3.0, 3.0, 0.0)));
        app.world_mut().entity_mut(a).insert(GravityScale(1.0));
        step(&mut app, 60);
        assert_eq!(rejected_field(&app, joint), None, "{pacing:?}");
        assert_near_vec(pos(&app, a), start, 2e-3, &format!("{pacing:?}: held"));
    }
}

/// A cart (a body with a box part on a child entity) on a frictionless floor, moving at
/// 1 m/s, carries a 1 kg ball on a 1 m rod jointed to its part. Momentum is conserved:
/// the part moves with its cart, and the rod pulls the ball along.
#[test]
fn a_joint_to_a_compound_part_acts_on_its_body() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        app.insert_resource(Gravity(Vec3::ZERO));
        let v = 2.0;
        let cart = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Mass(1.0),
                Transform::default(),
                Velocity::linear(Vec3::X * v),
            ))
            .id();
        let part = app
            .world_mut()
            .spawn((
                Collider::cuboid(0.25, 0.25, 0.25),
                Transform::from_xyz(0.5, 0.0, 0.0),
                ChildOf(cart),
            ))
            .id();
        let bob = floating_ball(&mut app, Vec3::new(0.5, -1.0, 0.0), Vec3::ZERO);
        let joint = Joint::distance(part, bob, 1.0);
        let joint = app.world_mut().spawn(joint).id();
        step(&mut app, 60);
        let what = format!("{pacing:?}");
        assert_eq!(rejected_field(&app, joint), None, "{what}");
        let p = vel(&app, cart).linear + vel(&app, bob).linear;
        assert_near_vec(p, Vec3::X * v, 0.01 * v, &format!("{what}: momentum"));
        assert!(
            vel(&app, bob).linear.x > 0.1,
            "{what}: the ball was pulled along"
        );
        let part_at = pos(&app, cart) + rot(&app, cart) * Vec3::X * 0.5;
        let rod = part_at.distance(pos(&app, bob));
        assert_near(rod, 1.0, 0.01, &format!("{what}: rod length"));
    }
}
