//! The tumble demo: the scene files in `assets/scenes/` on number keys, rendered by Bevy,
//! driven by an egui panel, orbit camera and mouse dragging.
//!
//! `cargo run --release --features viz --example demo`
//!
//! With `TUMBLE_TOUR=<dir>` it visits every scene instead, saves a screenshot of each to
//! `<dir>/<scene>.png` and exits (see `scripts/screenshots.sh`); `TUMBLE_TOUR_ONLY=<text>`
//! visits only the scenes whose file name contains it.

use bevy::prelude::*;
use tumble::prelude::*;
use tumble::viz::demo::{DemoPlugin, tour_plugin};

fn main() {
    let mut app = App::new();
    let window = Window {
        title: "tumble".into(),
        resolution: (1280, 720).into(),
        ..default()
    };
    // The scene files live in this repository's assets/, wherever the binary runs from.
    let assets = AssetPlugin {
        file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").into(),
        ..default()
    };
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(window),
                ..default()
            })
            .set(assets),
    )
    .add_plugins((TumblePlugin::default(), DemoPlugin));
    if let Ok(dir) = std::env::var("TUMBLE_TOUR") {
        let only = std::env::var("TUMBLE_TOUR_ONLY").ok();
        app.add_plugins(tour_plugin(dir.into(), only));
    }
    app.run();
}
