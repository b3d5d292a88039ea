//! The interaction logic of the demo that needs no window, so it is tested headless: the
//! drag spring, the six-direction push keys, adding bodies and switching scenes.

use bevy::input::ButtonInput;
use bevy::input::keyboard::KeyCode;
use bevy::prelude::*;

use crate::PhysicsSystems;
use crate::body::{ExternalForce, Mass, RigidBody, SleepTimer, Velocity};
use crate::collider::Collider;
use crate::scene::{SceneDesc, SceneEntity};

/// The selected body (at most one).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct Selected;

/// A body being pulled: the grabbed point in the body's frame, the point to pull it to,
/// and the drag plane's normal (towards the camera).
#[derive(Component, Clone, Copy, Debug)]
pub struct Dragged {
    pub local_anchor: Vec3,
    pub target: Vec3,
    pub plane_normal: Vec3,
}

/// Spring frequency of the pull, Hz.
pub const PULL_HERTZ: f32 = 3.0;

/// Force of one push key, N.
pub const PUSH_FORCE: f32 = 15.0;

/// Pulls every [`Dragged`] body towards its target before each step.
pub struct DragPullPlugin;

impl Plugin for DragPullPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(FixedUpdate, pull_dragged.before(PhysicsSystems::Prepare));
    }
}

/// The pull, a critically damped spring at the grabbed point:
/// F = m·(ω²·(target − anchor) − 2ω·v_anchor), plus a damping torque
/// −m·(|r|² + 0.1 m²)·(ω/2)·Ω on the body's spin Ω, so a held body hangs still instead of
/// swinging about the grabbed point for ever. Written into `ExternalForce`; the body keeps colliding meanwhile.
pub fn pull_dragged(
    mut commands: Commands,
    q: Query<(Entity, &Transform, &Velocity, Option<&Mass>, &Dragged)>,
) {
    let omega = std::f32::consts::TAU * PULL_HERTZ;
    for (e, tf, v, mass, d) in &q {
        let m = mass.map_or(1.0, |m| m.0);
        let anchor = tf.transform_point(d.local_anchor);
        let r = anchor - tf.translation;
        let v_anchor = v.linear + v.angular.cross(r);
        let force = m * (omega * omega * (d.target - anchor) - 2.0 * omega * v_anchor);
        let torque = r.cross(force) - m * (r.length_squared() + 0.1) * 0.5 * omega * v.angular;
        // A held body is being moved by hand: it must not fall asleep in the air.
        commands
            .entity(e)
            .insert((ExternalForce { force, torque }, SleepTimer(0.0)));
    }
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

/// A body added by hand: 2 kg, part of the scene (so a reset removes it).
pub fn added_body(collider: Collider, at: Vec3) -> impl Bundle {
    (
        SceneEntity,
        RigidBody::Dynamic,
        collider,
        Mass(2.0),
        Transform::from_translation(at),
        Velocity::ZERO,
    )
}

/// Replaces the running scene: despawns every [`SceneEntity`] in `old`, spawns `scene`.
pub fn switch_scene(
    commands: &mut Commands,
    scene: &SceneDesc,
    old: impl IntoIterator<Item = Entity>,
) -> Vec<Entity> {
    for e in old {
        commands.entity(e).despawn();
    }
    scene.spawn(commands)
}
