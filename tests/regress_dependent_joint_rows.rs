//! Joints whose rows depend on each other. The joints' equality rows are solved together
//! (`joint_direct.rs`), and a first version solved them undamped: rows that depend on
//! each other exactly (one body welded to the world twice) or nearly (a chain pulled
//! dead straight between two fixed points, where the rows along it sum to nothing) met a
//! pivot of f32 round-off, and took impulses of round-off over round-off. The plank
//! bridge scene, 40 planks hinged exactly across its 20 m span, reported 52 kN in its
//! first step (1.2 kN of planks hang from it) and flew apart when a crate stepped on it.
//!
//! Now such rows get what the others leave (a damped step: `DAMPING`): the doubly welded
//! box carries its weight between the two welds and does not move, and the bridge holds
//! the crate.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;
use tumble::scene::SceneDesc;

#[test]
fn a_box_welded_twice_carries_its_weight_and_stays() {
    let mut app = app();
    let (m, start) = (2.0, Vec3::new(0.0, 3.0, 0.0));
    let bar = cuboid(&mut app, Vec3::new(0.5, 0.1, 0.1), m, start);
    let welds: Vec<Entity> = [-0.5f32, 0.5]
        .iter()
        .map(|&x| {
            let at = Vec3::X * x;
            let joint = Joint::fixed(None, bar).with_local_anchors(start + at, at);
            app.world_mut().spawn(joint).id()
        })
        .collect();
    step(&mut app, 120);
    let moved = pos(&app, bar).distance(start);
    assert!(moved < 1e-3, "the welded bar moved {moved} m");
    let forces: Vec<Vec3> = welds
        .iter()
        .map(|&w| app.world().get::<JointForces>(w).unwrap().force)
        .collect();
    let weight = m * G;
    // Together they hold the weight (the split between them is the solver's choice).
    assert_near_vec(
        forces[0] + forces[1],
        Vec3::Y * weight,
        0.01 * weight,
        "the welds' force together, N",
    );
    for f in &forces {
        assert!(f.length() < 2.0 * weight, "one weld pulls {f} N");
    }
}

#[test]
fn the_taut_bridge_holds_a_crate_crossing_it() {
    // The bridge scene: 40 planks (2 kg) hinged edge to edge across exactly their span,
    // a 40 kg crate pushed onto them by a steady 300 N. The crate reaches the planks
    // after about 40 steps; the bridge then sags and rocks at under 2 m/s (undamped it
    // flew apart within ten steps of the crate's arrival, at 1,000 m/s).
    let scene = SceneDesc::load("assets/scenes/12_chain_bridge.scene.ron").unwrap();
    let (mut app, bodies) = scene.headless_app();
    let planks = &bodies[..40];
    let mut fastest = 0.0f32;
    for _ in 0..240 {
        app.update();
        for &p in planks {
            fastest = fastest.max(vel(&app, p).linear.length());
        }
    }
    assert!(fastest < 5.0, "a plank reached {fastest} m/s");
    // The crate made it past the first planks.
    let crate_x = pos(&app, bodies[42]).x;
    assert!(crate_x > -9.0, "the crate stopped at x = {crate_x} m");
}
