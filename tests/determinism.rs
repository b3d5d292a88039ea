//! The same scene stepped twice from scratch gives bit-identical poses and velocities:
//! nothing in the step depends on hash seeds, allocation addresses or timing. Scenes are
//! the demo's own files; the runs cover contacts, friction, restitution, sleeping and
//! waking (a ball dropped onto a sleeping tower half-way through).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;
use tumble::scene::SceneDesc;

/// Every body's pose and velocity as raw bits.
fn snapshot(app: &mut App) -> Vec<[u32; 13]> {
    let mut q = app
        .world_mut()
        .query_filtered::<(&Transform, &Velocity), With<RigidBody>>();
    q.iter(app.world())
        .map(|(t, v)| {
            let f = [
                t.translation.x,
                t.translation.y,
                t.translation.z,
                t.rotation.x,
                t.rotation.y,
                t.rotation.z,
                t.rotation.w,
                v.linear.x,
                v.linear.y,
                v.linear.z,
                v.angular.x,
                v.angular.y,
                v.angular.z,
            ];
            f.map(f32::to_bits)
        })
        .collect()
}

/// The final snapshot, and how far the ball dropped half-way fell.
fn run(file: &str, steps: usize) -> (Vec<[u32; 13]>, f32) {
    let mut app = app_with_sleeping();
    let scene = SceneDesc::load(format!("assets/scenes/{file}")).expect("scene");
    scene.spawn_into(app.world_mut());
    step(&mut app, steps / 2);
    let b = ball(&mut app, 0.4, 3.0, Vec3::new(0.1, 12.0, 0.05), Vec3::ZERO);
    step(&mut app, steps - steps / 2);
    (snapshot(&mut app), 12.0 - pos(&app, b).y)
}

#[test]
fn two_runs_of_the_same_scene_are_bit_identical() {
    for (file, steps) in [
        ("1_spheres_in_a_box.scene.ron", 240),
        ("2_box_tower.scene.ron", 240),
        ("4_mixed_masses.scene.ron", 240),
    ] {
        let ((a, fell), (b, _)) = (run(file, steps), run(file, steps));
        assert!(!a.is_empty());
        let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(differing, 0, "{file}: {differing} bodies differ");
        // The runs did something: the dropped ball fell onto the scene.
        assert!(fell > 1.0, "{file}: the ball fell only {fell} m");
    }
}
