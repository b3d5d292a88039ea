//! Overlap at spawn: a flat pyramid of ten 1 m cubes (rows of 4, 3, 2, 1) spawned with
//! 25% overlap between neighbours and sunk 12.5 cm into the ground separates gently —
//! push-out is capped per contact, so no body ever exceeds 5 m/s — and after 5 s stands at
//! rest with every overlap under 1 cm.

mod common;
use bevy::prelude::*;
use common::*;

#[test]
fn overlapping_pyramid_separates_gently_and_stands() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let pitch = 0.75; // 25% overlap between neighbours, sideways and vertically
    let mut cubes = Vec::new();
    for row in 0..4 {
        for i in 0..(4 - row) {
            let x = (i as f32 - (3 - row) as f32 * 0.5) * pitch;
            let y = 0.5 - 0.125 + row as f32 * pitch;
            cubes.push(cuboid(
                &mut app,
                Vec3::splat(0.5),
                1.0,
                Vec3::new(x, y, 0.0),
            ));
        }
    }
    let mut peak = 0.0f32;
    for _ in 0..300 {
        step(&mut app, 1);
        for &c in &cubes {
            peak = peak.max(vel(&app, c).linear.length());
        }
    }
    eprintln!("peak speed {peak} m/s");
    assert!(peak < 5.0, "peak speed {peak} m/s");
    for &c in &cubes {
        let v = vel(&app, c);
        assert!(
            v.linear.length() < 0.05 && v.angular.length() < 0.05,
            "cube {c} still moving: {v:?}"
        );
        assert!(
            pos(&app, c).y > 0.5 - 0.01,
            "cube {c} still in the ground: {}",
            pos(&app, c)
        );
        assert!(
            tilt(&app, c) < 0.05,
            "cube {c} toppled: tilt {}",
            tilt(&app, c)
        );
    }
    // Every pair of cubes: overlap of their boxes (they stay nearly axis-aligned).
    for (i, &a) in cubes.iter().enumerate() {
        for &b in &cubes[i + 1..] {
            let d = (pos(&app, a) - pos(&app, b)).abs();
            let overlap = (Vec3::ONE - d).min_element();
            assert!(overlap < 0.01, "cubes {a} and {b} overlap by {overlap}");
        }
    }
}
