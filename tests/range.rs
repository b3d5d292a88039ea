//! Range: mass ratios to 1000:1 in resting contact, and bodies from a centimetre to a
//! hundred metres. A soft contact sags by r·g/ω² whatever the size of its bodies, so a
//! fixed stiffness either crushes a light box under a heavy crate or lets a stack of
//! centimetre cubes sink by a large part of their size. So each contact asks for the
//! stiffness that holds its sag to half a percent of its smaller body
//! (`SolverSettings::max_sag`, 0.2 %), and the step takes the substeps that needs (up
//! to 16). At a fixed stiffness the crate sags 13.6 cm in 10 s and the 2 cm stack
//! drifts 2.6 mm (13 %); with the rule, 8.6 mm and 0.66 mm (3.3 %, most of it the first
//! steps after spawn).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_1000_kg_crate_on_a_1_kg_box_holds_for_10_s() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let light = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.5, 0.0));
    let heavy = cuboid(&mut app, Vec3::splat(0.5), 1000.0, Vec3::new(0.0, 1.5, 0.0));
    for _ in 0..600 {
        step(&mut app, 1);
        // Sag: two contacts at half a percent of 1 m each, 1 cm in all.
        assert_near(pos(&app, heavy).y, 1.5, 0.01, "crate height");
        assert!(
            pos(&app, light).y > 0.5 - 0.005,
            "the box sank into the floor"
        );
        // No slide-off: the crate stays centred on the box and level.
        let off = (pos(&app, heavy) - pos(&app, light)).xz().length();
        assert!(off < 0.01, "the crate walked {off} m off the box");
        assert!(
            tilt(&app, heavy) < 0.01,
            "the crate tilted {}",
            tilt(&app, heavy)
        );
    }
    let substeps = app.world().resource::<PhysicsWorld>().substeps();
    assert!(substeps > 4, "the load took more substeps: {substeps}");
}

/// A five-high stack of cubes of side `size` (water density) for 5 s: the largest
/// displacement of any cube, as a fraction of `size`.
fn stack_drift(size: f32) -> f32 {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let h = size / 2.0;
    let boxes: Vec<_> = (0..5)
        .map(|i| {
            let p = Vec3::new(0.0, h + i as f32 * size, 0.0);
            cuboid(&mut app, Vec3::splat(h), 1000.0 * size.powi(3), p)
        })
        .collect();
    let start: Vec<_> = boxes.iter().map(|&b| pos(&app, b)).collect();
    let mut drift = 0.0f32;
    for _ in 0..300 {
        step(&mut app, 1);
        for (&b, p) in boxes.iter().zip(&start) {
            drift = drift.max((pos(&app, b) - *p).length());
        }
    }
    drift / size
}

#[test]
fn stacks_of_2_cm_1_m_and_100_m_cubes_drift_under_5_percent() {
    for size in [0.02, 1.0, 100.0] {
        let drift = stack_drift(size);
        assert!(
            drift < 0.05,
            "{size} m cubes drifted {:.1} %",
            drift * 100.0
        );
    }
}

#[test]
fn a_1_cm_ball_rests_on_a_100_m_box() {
    let mut app = app();
    let big = app
        .world_mut()
        .spawn((
            Collider::cuboid(50.0, 50.0, 50.0),
            Transform::from_xyz(0.0, -50.0, 0.0),
        ))
        .id();
    let r = 0.005;
    let b = ball(
        &mut app,
        r,
        1000.0 * 4.19 * r * r * r,
        Vec3::new(3.0, r, -7.0),
        Vec3::ZERO,
    );
    for _ in 0..300 {
        step(&mut app, 1);
        // At rest on the top face within 5 % of its size, and not rolling away.
        assert_near_vec(
            pos(&app, b),
            Vec3::new(3.0, r, -7.0),
            0.05 * 2.0 * r,
            "1 cm ball",
        );
    }
    assert!(rejected_field(&app, big).is_none());
}
