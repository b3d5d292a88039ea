//! Scene files through the asset system: all of `assets/scenes/*.scene.ron` on number
//! keys, hot reload of the current one, and a readable error (file, line, column) when a
//! file is malformed — the running scene stays.

use bevy::asset::AssetLoadFailedEvent;
use bevy::prelude::*;
use bevy_panorbit_camera::PanOrbitCamera;

use crate::interaction::switch_scene;
use crate::scene::{SceneDesc, SceneEntity};

pub fn plugin(app: &mut App) {
    app.add_message::<SwitchScene>()
        .add_systems(Startup, load_scenes)
        .add_systems(Update, (watch_scene_assets, run_switch).chain());
}

/// The scene files, sorted by name, and which one runs.
#[derive(Resource, Default)]
pub struct DemoScenes {
    /// One handle per scene file, in name order.
    pub handles: Vec<Handle<SceneDesc>>,
    /// The files' names, in the same order.
    pub names: Vec<String>,
    /// Index of the scene that runs.
    pub current: usize,
    /// The last load error, shown in the panel.
    pub error: Option<String>,
    /// Whether the current scene has been spawned since it (re)loaded.
    spawned: bool,
}

/// Ask to run scene `index` (again, for a reset).
#[derive(Message, Clone, Copy, Debug)]
pub struct SwitchScene(pub usize);

/// The scene files in `assets/scenes`, sorted by their number (`10_…` after `9_…`):
/// their order is the number keys' (1–9, then 0 for the tenth).
pub fn scene_file_names() -> Vec<String> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok()?.file_name().into_string().ok())
                .filter(|n| n.ends_with(".scene.ron"))
                .collect()
        })
        .unwrap_or_default();
    // By the leading number, then by name.
    let number = |n: &String| n.split('_').next().and_then(|d| d.parse::<u32>().ok());
    names.sort_by(|a, b| (number(a), a).cmp(&(number(b), b)));
    names
}

fn load_scenes(mut commands: Commands, assets: Res<AssetServer>) {
    let names = scene_file_names();
    let handles = names
        .iter()
        .map(|n| assets.load(format!("scenes/{n}")))
        .collect();
    commands.insert_resource(DemoScenes {
        handles,
        names,
        ..default()
    });
}

fn watch_scene_assets(
    mut events: MessageReader<AssetEvent<SceneDesc>>,
    mut failures: MessageReader<AssetLoadFailedEvent<SceneDesc>>,
    mut scenes: ResMut<DemoScenes>,
    mut switch: MessageWriter<SwitchScene>,
) {
    for failure in failures.read() {
        let message = format!("{}: {}", failure.path, failure.error);
        error!("tumble demo: {message}");
        scenes.error = Some(message);
    }
    let current = scenes.handles.get(scenes.current).map(|h| h.id());
    for ev in events.read() {
        match ev {
            AssetEvent::Modified { id } if Some(*id) == current => {
                scenes.error = None;
                switch.write(SwitchScene(scenes.current));
            }
            AssetEvent::LoadedWithDependencies { id }
                if Some(*id) == current && !scenes.spawned =>
            {
                switch.write(SwitchScene(scenes.current));
            }
            _ => {}
        }
    }
}

fn run_switch(
    mut commands: Commands,
    mut requests: MessageReader<SwitchScene>,
    mut scenes: ResMut<DemoScenes>,
    assets: Res<Assets<SceneDesc>>,
    old: Query<Entity, With<SceneEntity>>,
    mut camera: Query<&mut PanOrbitCamera>,
    mut history: ResMut<super::EnergyHistory>,
) {
    let Some(&SwitchScene(index)) = requests.read().last() else {
        return;
    };
    let Some(scene) = scenes.handles.get(index).and_then(|h| assets.get(h)) else {
        // Not loaded yet: remember the choice, spawn when it arrives.
        scenes.current = index.min(scenes.handles.len().saturating_sub(1));
        scenes.spawned = false;
        return;
    };
    switch_scene(&mut commands, scene, old);
    history.samples.clear();
    for mut cam in &mut camera {
        cam.target_focus = scene.camera.focus;
        cam.target_radius = scene.camera.distance;
        cam.target_yaw = scene.camera.yaw.to_radians();
        cam.target_pitch = scene.camera.pitch.to_radians();
    }
    scenes.current = index;
    scenes.spawned = true;
}
