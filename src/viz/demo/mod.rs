//! The demo application as a plugin: the scene files on number keys, pause/step/reset,
//! the seed engine's six-direction push, adding and deleting bodies, the egui panel, and a
//! screenshot tour for headless runs. `examples/demo.rs` only adds it.

mod keys;
mod panel;
mod scenes;
mod stats;
mod tour;

use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;
use bevy_egui::{EguiPlugin, EguiPrimaryContextPass};
use bevy_panorbit_camera::PanOrbitCameraPlugin;

use super::{BodyMeshPlugin, DebugRenderPlugin, DragBodiesPlugin};
use crate::body::RigidBody;
use crate::interpolation::{TransformInterpolation, TransformInterpolationPlugin};

pub use scenes::{DemoScenes, SwitchScene};
pub use stats::{EnergyHistory, SceneStats};
pub use tour::tour_plugin;

/// Everything the demo needs on top of `DefaultPlugins` and `TumblePlugin`.
pub struct DemoPlugin;

pub use crate::diagnostics::stage_path;

impl Plugin for DemoPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((
            crate::picking::PhysicsPickingPlugin,
            EguiPlugin::default(),
            PanOrbitCameraPlugin,
            BodyMeshPlugin,
            crate::diagnostics::PhysicsDiagnosticsPlugin,
            // Smooth motion at any frame rate: the core's interpolation, on every body.
            TransformInterpolationPlugin::default(),
            DragBodiesPlugin,
            DebugRenderPlugin,
        ))
        .register_required_components::<RigidBody, TransformInterpolation>()
        .init_asset::<crate::scene::SceneDesc>()
        .init_asset_loader::<crate::scene::SceneLoader>()
        .add_plugins((scenes::plugin, keys::plugin, stats::plugin))
        // The physics stages are a chain anyway; run FixedUpdate on the main thread so the
        // panel's stage timings measure the stages, not hand-offs between worker threads
        // (under a software renderer those waits were most of the "step" time).
        .edit_schedule(FixedUpdate, |s| {
            s.set_executor(SingleThreadedExecutor::new());
        })
        .add_systems(Startup, setup_view)
        .add_systems(EguiPrimaryContextPass, panel::draw_panel);
    }
}

fn setup_view(mut commands: Commands) {
    commands.spawn((
        bevy_panorbit_camera::PanOrbitCamera {
            button_orbit: MouseButton::Left,
            ..default()
        },
        Transform::from_xyz(0.0, 6.0, 16.0).looking_at(Vec3::Y, Vec3::Y),
    ));
    commands.spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            illuminance: 9000.0,
            ..default()
        },
        Transform::from_xyz(8.0, 16.0, 6.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.insert_resource(GlobalAmbientLight {
        brightness: 400.0,
        ..default()
    });
    commands.insert_resource(ClearColor(Color::srgb(0.12, 0.13, 0.16)));
}
