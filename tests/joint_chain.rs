//! The joints' mass-ratio hard case: a hanging chain of 30 light links (0.1 kg) with a
//! ball a hundred times heavier (10 kg) at its end. Solved joint by joint (Gauss–Seidel)
//! with soft rows, each joint is a spring across two light links carrying the ball's
//! weight and the passes never carry the load up the chain: it stretches 14.5 % at 4
//! substeps (11 % at 16 passes), and holds under 1 % only once a sag rule raises the
//! substeps to 16. So the joints' equality rows are solved together and exactly
//! (`joint_direct.rs`): the chain must stretch less than 1 % at a true 4 substeps.
//!
//! Let go from the horizontal, the same chain whips the ball down and its taut links
//! ring fast (a 560 N pull on 0.1 kg links): at 4 substeps that ringing outruns the solve
//! and the chain comes apart; so the substeps follow it (`tension_omega`) and every joint
//! must stay closed within 1 cm.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const LINKS: usize = 30;
/// Link length, m (a capsule's ends to ends: ball joints at its two ends).
const LINK: f32 = 0.2;

/// The chain from `top` down: the links, then the ball. Returns (links, ball).
fn chain(app: &mut App, top: Vec3, ball_mass: f32) -> (Vec<Entity>, Entity) {
    let mut links = Vec::new();
    let mut above: Option<Entity> = None;
    for i in 0..LINKS {
        let centre = top - Vec3::Y * LINK * (i as f32 + 0.5);
        let link = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Collider::capsule(0.03, LINK / 2.0 - 0.03),
                Mass(0.1),
                Transform::from_translation(centre),
            ))
            .id();
        let up = Vec3::Y * LINK / 2.0;
        let joint = match above {
            None => Joint::spherical(None, link).with_local_anchors(top, up),
            Some(a) => Joint::spherical(a, link).with_local_anchors(-up, up),
        };
        app.world_mut().spawn(joint);
        links.push(link);
        above = Some(link);
    }
    let radius = 0.25;
    let end = top - Vec3::Y * (LINK * LINKS as f32 + radius);
    let ball = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(radius),
            Mass(ball_mass),
            Transform::from_translation(end),
        ))
        .id();
    let last = *links.last().unwrap();
    let joint =
        Joint::spherical(last, ball).with_local_anchors(-Vec3::Y * LINK / 2.0, Vec3::Y * radius);
    app.world_mut().spawn(joint);
    (links, ball)
}

#[test]
fn a_heavy_ball_on_a_light_chain_stretches_it_less_than_one_percent() {
    let mut app = app();
    let top = Vec3::new(0.0, 10.0, 0.0);
    let (_, ball) = chain(&mut app, top, 10.0);
    let rest = LINK * LINKS as f32;
    let mut longest = 0.0f32;
    for _ in 0..300 {
        step(&mut app, 1);
        // From the pivot to the ball's top (where the last joint holds it).
        let reach = top.y - (pos(&app, ball).y + 0.25);
        longest = longest.max(reach);
        // The default 4 substeps, never raised.
        let substeps = app.world().resource::<PhysicsWorld>().substeps();
        assert_eq!(substeps, 4, "took {substeps} substeps");
    }
    let stretch = longest / rest - 1.0;
    assert!(
        stretch < 0.01,
        "the chain stretched {:.2} %",
        stretch * 100.0
    );
    // And it hangs still, straight down.
    let v = vel(&app, ball).linear.length();
    assert!(v < 0.05, "the ball still moves at {v} m/s");
    let p = pos(&app, ball);
    assert!(
        p.x.abs() < 1e-3 && p.z.abs() < 1e-3,
        "the ball hangs off-centre: {p}"
    );
}

#[test]
fn a_swinging_chain_keeps_its_links_together() {
    // The same chain let go from the horizontal: every joint's anchors stay within 1 cm
    // of each other as it whips down.
    let mut app = app();
    let top = Vec3::new(0.0, 10.0, 0.0);
    let (links, ball) = chain(&mut app, top, 10.0);
    // Lay it out along +x: turn every body a quarter turn about z around the pivot.
    let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    for &e in links.iter().chain([&ball]) {
        let mut tf = app.world_mut().get_mut::<Transform>(e).unwrap();
        tf.translation = top + turn * (tf.translation - top);
        tf.rotation = turn * tf.rotation;
    }
    let mut worst = 0.0f32;
    let mut most_substeps = 0;
    for _ in 0..240 {
        step(&mut app, 1);
        most_substeps = most_substeps.max(app.world().resource::<PhysicsWorld>().substeps());
        let end =
            |e: Entity, sign: f32| pos(&app, e) + rot(&app, e) * (Vec3::Y * sign * LINK / 2.0);
        worst = worst.max(end(links[0], 1.0).distance(top));
        for pair in links.windows(2) {
            worst = worst.max(end(pair[0], -1.0).distance(end(pair[1], 1.0)));
        }
    }
    assert!(worst < 0.01, "a joint opened {worst} m");
    // The ringing of the taut links raised the substeps on the way down.
    assert!(most_substeps > 4, "at most {most_substeps} substeps");
}
