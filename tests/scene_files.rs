//! Every scene in assets/scenes parses, spawns headless (no asset server) and runs 600
//! steps with every body finite; the box tower scene stands; a malformed file names its
//! line and column.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;
use tumble::scene::{SceneDesc, SceneError};

fn scene_files() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".scene.ron"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_scene_runs_600_steps_finite() {
    let files = scene_files();
    assert!(files.len() >= 9, "{files:?}");
    for file in files {
        let scene = SceneDesc::load(&file).unwrap_or_else(|e| panic!("{e}"));
        let mut app = app_with_sleeping();
        let bodies = scene.spawn_into(app.world_mut());
        assert!(!bodies.is_empty(), "{}", file.display());
        step(&mut app, 600);
        for &b in &bodies {
            let (p, v) = (pos(&app, b), vel(&app, b));
            assert!(
                p.is_finite() && v.linear.is_finite() && v.angular.is_finite(),
                "{}: body {b} at {p}",
                file.display()
            );
            assert!(
                app.world().get::<PhysicsRejected>(b).is_none(),
                "{}: body {b} rejected",
                file.display()
            );
            assert!(
                p.y > -1.0,
                "{}: body {b} fell through the floor: {p}",
                file.display()
            );
        }
    }
}

#[test]
fn box_tower_scene_stands() {
    let scene = SceneDesc::load("assets/scenes/2_box_tower.scene.ron").unwrap();
    let mut app = app();
    let bodies = scene.spawn_into(app.world_mut());
    let top0 = pos(&app, bodies[9]);
    step(&mut app, 600);
    let moved = pos(&app, bodies[9]) - top0;
    assert!(
        moved.xz().length() < 0.02 && moved.y.abs() < 0.05,
        "top moved {moved}"
    );
}

#[test]
fn malformed_scene_names_line_and_column() {
    let text =
        "(\n    name: \"broken\",\n    bodies: [Single((shape: Sphere(0.5), mass: Some(1.0)),\n";
    match SceneDesc::from_ron(text, "broken.scene.ron") {
        Err(SceneError::Parse { path, line, .. }) => {
            assert_eq!(path, "broken.scene.ron");
            assert!(line >= 3, "line {line}");
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
    let unknown = "(name: \"x\", gravity_typo: 1.0)";
    let err = SceneDesc::from_ron(unknown, "typo.scene.ron")
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("typo.scene.ron:1:"), "{err}");
}
