//! The demo's keys: 1–9 scenes, Space pause, N single step, R reset, Delete removes the
//! selected body, B / V add a box / ball under the cursor, and the seed engine's six
//! pushes: A/D along x, Q/E along y, W/S along z (a force on every body while held).

use bevy::prelude::*;
use bevy_egui::input::egui_wants_any_keyboard_input;

use super::scenes::{DemoScenes, SwitchScene};
use crate::collider::Collider;
use crate::interaction::{PUSH_FORCE, Selected, added_body};
use crate::settings::GlobalForce;

pub fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        (handle_keys, push_bodies).run_if(not(egui_wants_any_keyboard_input)),
    );
}

fn push_bodies(keys: Res<ButtonInput<KeyCode>>, mut force: ResMut<GlobalForce>) {
    let f = push_direction(&keys) * PUSH_FORCE;
    if force.0 != f {
        force.0 = f;
    }
}

#[allow(clippy::too_many_arguments)]
fn handle_keys(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    scenes: Res<DemoScenes>,
    mut switch: MessageWriter<SwitchScene>,
    mut time: ResMut<Time<Virtual>>,
    selected: Query<Entity, With<Selected>>,
    windows: Query<&Window>,
    cameras: Query<(&Camera, &GlobalTransform)>,
) {
    let digits = [
        KeyCode::Digit1,
        KeyCode::Digit2,
        KeyCode::Digit3,
        KeyCode::Digit4,
        KeyCode::Digit5,
        KeyCode::Digit6,
        KeyCode::Digit7,
        KeyCode::Digit8,
        KeyCode::Digit9,
        KeyCode::Digit0,
    ];
    for (i, key) in digits.iter().enumerate() {
        if keys.just_pressed(*key) && i < scenes.handles.len() {
            switch.write(SwitchScene(i));
        }
    }
    // Every scene, past the ten the digits reach: previous and next, wrapping around.
    let n = scenes.handles.len();
    if n > 0 {
        if keys.just_pressed(KeyCode::PageDown) || keys.just_pressed(KeyCode::BracketRight) {
            switch.write(SwitchScene((scenes.current + 1) % n));
        }
        if keys.just_pressed(KeyCode::PageUp) || keys.just_pressed(KeyCode::BracketLeft) {
            switch.write(SwitchScene((scenes.current + n - 1) % n));
        }
    }
    if keys.just_pressed(KeyCode::KeyR) {
        switch.write(SwitchScene(scenes.current));
    }
    if keys.just_pressed(KeyCode::Space) {
        if time.is_paused() {
            time.unpause()
        } else {
            time.pause()
        }
    }
    if keys.just_pressed(KeyCode::KeyN) && time.is_paused() {
        commands.run_schedule(bevy::app::FixedMain);
    }
    if keys.just_pressed(KeyCode::Delete) || keys.just_pressed(KeyCode::Backspace) {
        for e in &selected {
            commands.entity(e).despawn();
        }
    }
    let add_box = keys.just_pressed(KeyCode::KeyB);
    if add_box || keys.just_pressed(KeyCode::KeyV) {
        let at = cursor_on_ground(&windows, &cameras).unwrap_or(Vec3::ZERO) + Vec3::Y * 3.0;
        let collider = if add_box {
            Collider::cuboid(0.4, 0.4, 0.4)
        } else {
            Collider::sphere(0.4)
        };
        commands.spawn(added_body(collider, at));
    }
}

/// Where the cursor's ray meets the ground plane y = 0.
fn cursor_on_ground(
    windows: &Query<&Window>,
    cameras: &Query<(&Camera, &GlobalTransform)>,
) -> Option<Vec3> {
    let cursor = windows.iter().next()?.cursor_position()?;
    let (camera, tf) = cameras.iter().next()?;
    let ray = camera.viewport_to_world(tf, cursor).ok()?;
    let t = ray.intersect_plane(Vec3::ZERO, InfinitePlane3d::new(Vec3::Y))?;
    Some(ray.get_point(t))
}

/// The push direction the held keys ask for (A/D: ∓x, Q/E: ∓y, W/S: ∓z).
pub fn push_direction(keys: &ButtonInput<KeyCode>) -> Vec3 {
    let axis =
        |neg: KeyCode, pos: KeyCode| f32::from(keys.pressed(pos)) - f32::from(keys.pressed(neg));
    Vec3::new(
        axis(KeyCode::KeyA, KeyCode::KeyD),
        axis(KeyCode::KeyQ, KeyCode::KeyE),
        axis(KeyCode::KeyW, KeyCode::KeyS),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_keys_give_six_directions() {
        let cases = [
            (KeyCode::KeyD, Vec3::X),
            (KeyCode::KeyA, Vec3::NEG_X),
            (KeyCode::KeyE, Vec3::Y),
            (KeyCode::KeyQ, Vec3::NEG_Y),
            (KeyCode::KeyS, Vec3::Z),
            (KeyCode::KeyW, Vec3::NEG_Z),
        ];
        for (key, dir) in cases {
            let mut keys = ButtonInput::<KeyCode>::default();
            keys.press(key);
            assert_eq!(push_direction(&keys), dir, "{key:?}");
        }
    }
}
