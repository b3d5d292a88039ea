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

/// A plugin that tours all scenes (or those whose file name contains `only`) and saves
/// `<dir>/<scene name>.png` for each.
pub fn tour_plugin(dir: PathBuf, only: Option<String>) -> impl Plugin {
    move |app: &mut App| {
        let visits: Vec<(usize, String)> = scene_file_names()
            .into_iter()
            .enumerate()
            .filter(|(_, n)| only.as_ref().is_none_or(|o| n.contains(o.as_str())))
            .collect();
        let shots = visits
            .iter()
            .enumerate()
            .map(|(k, (_, name))| CaptureRequest {
                frame: WARMUP + (k as u32 + 1) * PER_SCENE - 1,
                path: dir.join(format!("{}.png", name.trim_end_matches(".scene.ron"))),
            })
            .collect();
        let order: Vec<usize> = visits.iter().map(|(i, _)| *i).collect();
        app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            1.0 / 30.0,
        )))
        .insert_resource(TourOrder(order))
        .add_plugins(CapturePlugin { shots })
        .add_systems(Update, advance_tour);
    }
}

/// The scene indices the tour visits, in order.
#[derive(Resource)]
struct TourOrder(Vec<usize>);

fn advance_tour(
    mut frame: Local<u32>,
    order: Res<TourOrder>,
    mut switch: MessageWriter<SwitchScene>,
) {
    *frame += 1;
    if *frame >= WARMUP && (*frame - WARMUP).is_multiple_of(PER_SCENE) {
        let k = ((*frame - WARMUP) / PER_SCENE) as usize;
        if let Some(&index) = order.0.get(k) {
            switch.write(SwitchScene(index));
        }
    }
}
