//! The screenshot tour: visit every scene for a fixed number of frames (with a fixed
//! simulated time per frame, so runs are repeatable however slow the renderer), save a
//! screenshot of each once its bodies have moved, then exit.

use std::path::PathBuf;
use std::time::Duration;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;

use super::scenes::{SwitchScene, scene_file_names};
use crate::viz::{CapturePlugin, CaptureRequest};

/// Frames before the first scene (assets, shaders) and per scene.
const WARMUP: u32 = 40;
const PER_SCENE: u32 = 50;

/// A plugin that tours all scenes and saves `<dir>/<scene name>.png` for each.
pub fn tour_plugin(dir: PathBuf) -> impl Plugin {
    move |app: &mut App| {
        let names = scene_file_names();
        let shots = names
            .iter()
            .enumerate()
            .map(|(i, name)| CaptureRequest {
                frame: WARMUP + (i as u32 + 1) * PER_SCENE - 1,
                path: dir.join(format!("{}.png", name.trim_end_matches(".scene.ron"))),
            })
            .collect();
        app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            1.0 / 30.0,
        )))
        .add_plugins(CapturePlugin { shots })
        .add_systems(Update, advance_tour);
    }
}

fn advance_tour(mut frame: Local<u32>, mut switch: MessageWriter<SwitchScene>) {
    *frame += 1;
    if *frame >= WARMUP && (*frame - WARMUP).is_multiple_of(PER_SCENE) {
        switch.write(SwitchScene(((*frame - WARMUP) / PER_SCENE) as usize));
    }
}
