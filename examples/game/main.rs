//! A small playable scene using the game API: a kinematic platform moved by its
//! Transform carries a crate, a sensor pickup, projectiles that ignore their shooter
//! (collision layers), a jump by impulse, per-entity hit observers, interpolated motion.
//!
//! `cargo run --release --features viz --example game`: A/D walk, Space jumps, F fires.
//! The rules live in `logic.rs`; `tests/game_example.rs` plays them headless.

mod logic;

use bevy::prelude::*;
use tumble::prelude::*;
use tumble::viz::BodyMeshPlugin;

fn main() {
    App::new()
        .add_plugins((DefaultPlugins, TumblePlugin::default()))
        .add_plugins((TransformInterpolationPlugin::default(), BodyMeshPlugin))
        .add_plugins(logic::plugin)
        .add_systems(Startup, setup_view)
        .add_systems(Update, (read_keys, show_score))
        .run();
}

fn setup_view(mut commands: Commands) {
    commands.spawn((
        Camera3d::default(),
        Transform::from_xyz(0.0, 6.0, 18.0).looking_at(Vec3::new(0.0, 1.0, 0.0), Vec3::Y),
    ));
    commands.spawn((
        PointLight {
            intensity: 4.0e6,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(4.0, 10.0, 6.0),
    ));
}

fn read_keys(keys: Res<ButtonInput<KeyCode>>, mut controls: ResMut<logic::Controls>) {
    controls.walk =
        keys.pressed(KeyCode::KeyD) as i32 as f32 - keys.pressed(KeyCode::KeyA) as i32 as f32;
    controls.jump |= keys.just_pressed(KeyCode::Space);
    controls.fire |= keys.just_pressed(KeyCode::KeyF);
}

fn show_score(score: Res<logic::Score>) {
    if score.is_changed() {
        info!(
            "pickups {} hits {} (hardest {:.1} m/s)",
            score.pickups, score.hits, score.hardest_hit
        );
    }
}
