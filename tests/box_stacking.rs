//! Boxes at rest: a flat landing, a tall stack, a 385-cube pyramid, and a heavy box on a
//! light one. Stability tests run with the default solver settings.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn box_dropped_flat_lands_flat_without_drifting() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 4.0, 0.0));
    app.world_mut().entity_mut(b).insert(Friction(0.3));
    step(&mut app, 90);
    let p = pos(&app, b);
    assert!((p.y - 0.5).abs() < 0.01, "height {}", p.y);
    assert!(tilt(&app, b) < 0.01, "tilt {}", tilt(&app, b));
    assert!(p.x.abs() < 0.02 && p.z.abs() < 0.02, "drifted to {p}");
}

#[test]
fn ten_box_stack_stands_for_ten_seconds() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let boxes: Vec<_> = (0..10)
        .map(|i| {
            let dx = if i % 2 == 0 { 0.01 } else { -0.01 };
            cuboid(
                &mut app,
                Vec3::splat(0.5),
                1.0,
                Vec3::new(dx, 0.5 + i as f32, 0.0),
            )
        })
        .collect();
    let top0 = pos(&app, boxes[9]);
    step(&mut app, 600);
    let top = pos(&app, boxes[9]);
    assert!(
        (top - top0).xz().length() < 0.02,
        "top moved {}",
        (top - top0).xz().length()
    );
    for (i, &b) in boxes.iter().enumerate() {
        let p = pos(&app, b);
        assert!(
            (p.y - (0.5 + i as f32)).abs() < 0.05 && tilt(&app, b) < 0.05,
            "box {i} fell: {p}"
        );
    }
}

#[test]
fn pyramid_of_385_cubes_holds_for_ten_seconds() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let mut cubes = Vec::new();
    for level in 0..10 {
        let n = 10 - level;
        for i in 0..n {
            for k in 0..n {
                let x = i as f32 - (n - 1) as f32 * 0.5;
                let z = k as f32 - (n - 1) as f32 * 0.5;
                let p = Vec3::new(x, 0.5 + level as f32, z);
                cubes.push((cuboid(&mut app, Vec3::splat(0.5), 1.0, p), p));
            }
        }
    }
    assert_eq!(cubes.len(), 385);
    step(&mut app, 600);
    let worst = cubes
        .iter()
        .map(|&(e, p0)| (pos(&app, e) - p0).length())
        .fold(0.0, f32::max);
    assert!(worst < 0.05, "a cube moved {worst} m");
}

#[test]
fn heavy_box_on_light_box_holds_without_sinking_or_walking() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let small = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.5, 0.0));
    let big = cuboid(&mut app, Vec3::splat(0.5), 100.0, Vec3::new(0.0, 1.5, 0.0));
    step(&mut app, 600);
    let (ps, pb) = (pos(&app, small), pos(&app, big));
    assert!(ps.y >= 0.49, "small box sank into the ground: {}", ps.y);
    assert!(
        pb.y - ps.y >= 0.99,
        "big box sank into the small one: {}",
        pb.y - ps.y
    );
    assert!(
        pb.xz().length() < 0.01,
        "top box walked {}",
        pb.xz().length()
    );
}
