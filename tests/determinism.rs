//! Determinism that holds in a game. The same scene gives bit-identical poses and
//! velocities:
//! - run twice from scratch, compared with each other and with a pinned hash (a hash
//!   that changes means the physics changed: update the pin only on purpose, and say so);
//! - under three frame pacings (one step per update, a 240 Hz and a 30 Hz render);
//! - while unrelated bodies are spawned and despawned 50 times far away, which recycles
//!   entity ids, reorders the ECS tables (a despawn moves the last row into the hole)
//!   and reorders the fixed set — none of which may change the order the solver visits
//!   the scene's contacts in.
//!
//! The scenes are the demo's own files and cover contacts, friction, restitution,
//! joints, sleeping and waking (a ball dropped onto the scene half-way through).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;
use tumble::scene::{SceneDesc, SceneEntity};

const SCENES: [(&str, usize); 4] = [
    ("1_spheres_in_a_box.scene.ron", 240),
    ("2_box_tower.scene.ron", 240),
    ("4_mixed_masses.scene.ron", 240),
    // Joints among contacts.
    ("15_ragdolls.scene.ron", 240),
];

/// The scene's bodies' poses and velocities as raw bits, in spawn order.
fn bits(app: &App, bodies: &[Entity]) -> Vec<[u32; 13]> {
    bodies
        .iter()
        .map(|&e| {
            let world = app.world();
            let (t, v) = (
                world.get::<Transform>(e).unwrap(),
                world.get::<Velocity>(e).unwrap(),
            );
            tumble::state_hash::body_bits(t, v)
        })
        .collect()
}

/// Runs a scene file for `steps` under `pacing`, dropping a ball on it half-way; with
/// `churn`, spawns and despawns an unrelated ball (and a static block) far away at 50
/// points of the run. Returns the final bits and how far the dropped ball fell.
fn run(file: &str, steps: usize, pacing: Pacing, churn: bool) -> (Vec<[u32; 13]>, f32) {
    let mut app = paced_app(pacing, true);
    let scene = SceneDesc::load(format!("assets/scenes/{file}")).expect("scene");
    let mut bodies = scene.spawn_into(app.world_mut());
    let mut extra = Vec::new();
    for k in 0..steps {
        if churn && k % (steps / 50) == 0 {
            // The same components as the scene's bodies and planes, so they share their
            // ECS tables (and, asleep or static, the fixed set).
            let far = Vec3::new(500.0 + k as f32, 1.0, 0.0);
            let a = app
                .world_mut()
                .spawn((
                    SceneEntity,
                    RigidBody::Dynamic,
                    Collider::sphere(0.3),
                    Mass(1.0),
                    Transform::from_translation(far),
                    Velocity::ZERO,
                    Friction(0.5),
                    Restitution(0.0),
                ))
                .id();
            let b = app
                .world_mut()
                .spawn((
                    SceneEntity,
                    Name::new("plane"),
                    Collider::plane_rect(1.0, 1.0),
                    Transform::from_translation(far - Vec3::Y * 0.3),
                    Friction(0.5),
                    Restitution(0.0),
                ))
                .id();
            extra.push([a, b]);
            if extra.len() > 2 {
                for e in extra.remove(0) {
                    app.world_mut().despawn(e);
                }
            }
        }
        if k == steps / 2 {
            bodies.push(ball(
                &mut app,
                0.4,
                3.0,
                Vec3::new(0.1, 12.0, 0.05),
                Vec3::ZERO,
            ));
        }
        step(&mut app, 1);
    }
    let dropped = *bodies.last().unwrap();
    (bits(&app, &bodies), 12.0 - pos(&app, dropped).y)
}

#[test]
fn two_runs_of_the_same_scene_are_bit_identical() {
    for (file, steps) in SCENES {
        let ((a, fell), (b, _)) = (
            run(file, steps, Pacing::OneStep, false),
            run(file, steps, Pacing::OneStep, false),
        );
        assert!(!a.is_empty());
        let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(differing, 0, "{file}: {differing} bodies differ");
        // The runs did something: the dropped ball fell onto the scene.
        assert!(fell > 1.0, "{file}: the ball fell only {fell} m");
    }
}

#[test]
fn every_pacing_gives_the_same_bits() {
    for (file, steps) in SCENES {
        let (reference, _) = run(file, steps, Pacing::OneStep, false);
        for pacing in [Pacing::Render(240.0), Pacing::Render(30.0)] {
            let (got, _) = run(file, steps, pacing, false);
            let differing = reference.iter().zip(&got).filter(|(x, y)| x != y).count();
            assert_eq!(
                differing, 0,
                "{file} under {pacing:?}: {differing} bodies differ"
            );
        }
    }
}

#[test]
fn spawning_and_despawning_unrelated_bodies_changes_nothing() {
    for (file, steps) in SCENES {
        let (reference, _) = run(file, steps, Pacing::OneStep, false);
        let (got, _) = run(file, steps, Pacing::Render(240.0), true);
        let differing = reference.iter().zip(&got).filter(|(x, y)| x != y).count();
        assert_eq!(differing, 0, "{file} with churn: {differing} bodies differ");
    }
}

/// The hash `cargo run --release --example state_hash -- assets/scenes/4_mixed_masses.scene.ron 600`
/// printed in another process, a release build, when this was pinned. This test runs in
/// a debug build on whatever machine CI has: agreeing means the physics is the same bit
/// for bit across processes, builds and machines. If a change to the physics moves it,
/// re-run the command and update the pin in the same commit, saying why.
const PINNED_MIXED_MASSES_600: u64 = 0x2232_5908_a972_1998;

#[test]
fn the_state_hash_matches_the_pinned_one_under_every_pacing() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        let scene = SceneDesc::load("assets/scenes/4_mixed_masses.scene.ron").unwrap();
        scene.spawn_into(app.world_mut());
        step(&mut app, 600);
        let hash = tumble::state_hash::state_hash(app.world_mut());
        assert_eq!(
            hash, PINNED_MIXED_MASSES_600,
            "{pacing:?}: state hash {hash:016x}, pinned {PINNED_MIXED_MASSES_600:016x}"
        );
    }
}
