//! Frame-counted screenshots for runs under Xvfb: software rendering is slow, so shots are
//! taken after a number of frames, not seconds. The app exits once every shot is saved.

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};

/// Take a screenshot of the primary window at `frame` and save it to `path`.
#[derive(Clone, Debug)]
pub struct CaptureRequest {
    /// The frame (counted from the app's start) to capture.
    pub frame: u32,
    /// Where the PNG goes.
    pub path: std::path::PathBuf,
}

/// Takes the requested shots, then exits the app a few frames after the last.
#[derive(Resource, Clone, Debug, Default)]
pub struct CapturePlugin {
    /// The shots to take, in any order.
    pub shots: Vec<CaptureRequest>,
}

impl Plugin for CapturePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.clone())
            .add_systems(Last, take_shots);
    }
}

fn take_shots(
    mut commands: Commands,
    plan: Res<CapturePlugin>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    *frame += 1;
    for shot in plan.shots.iter().filter(|s| s.frame == *frame) {
        if let Some(dir) = shot.path.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(shot.path.clone()));
    }
    let last = plan.shots.iter().map(|s| s.frame).max().unwrap_or(0);
    if last > 0 && *frame == last + 10 {
        exit.write(AppExit::Success);
    }
}
