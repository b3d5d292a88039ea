//! The interaction logic of the demo that needs no window, so it is tested headless: the
//! drag spring, the six-direction push keys, adding bodies and switching scenes.

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
    /// The grabbed point in the body's frame, m.
    pub local_anchor: Vec3,
    /// The point to pull it to, m (world).
    pub target: Vec3,
    /// Unit normal of the plane the target moves in, towards the camera (world).
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

/// What the pull needs to know of a held body's mass distribution.
type HeldBody = (Option<&'static Mass>, Option<&'static Collider>);

/// The pull, a critically damped spring at the grabbed point acting through the point's
/// effective mass M (the 3×3 mass the point shows when pushed, rotation included):
/// F = M·(ω²·(target − anchor) − 2ω·v_anchor), so the grabbed point moves like a unit
/// oscillator of frequency ω wherever the body is held, plus a damping torque −(ω/2)·I·Ω
/// so a held body hangs still instead of swinging about the grabbed point for ever.
/// Written into `ExternalForce`; the body keeps colliding meanwhile.
///
/// With the body's plain mass instead of M, a light box held by a corner was unstable at
/// 60 Hz (its rotation answers the off-centre force several times faster than ω) and
/// flung the tower apart in the demo; see `tests/drag_corner_grab.rs`.
pub fn pull_dragged(
    mut commands: Commands,
    q: Query<(Entity, &Transform, &Velocity, HeldBody, &Dragged)>,
) {
    let omega = std::f32::consts::TAU * PULL_HERTZ;
    for (e, tf, v, (mass, collider), d) in &q {
        let m = mass.map_or(1.0, |m| m.0);
        let shape = collider.map_or(Collider::sphere(0.5).shape, |c| c.shape.clone());
        let rot = Mat3::from_quat(tf.rotation);
        let inertia = shape.principal_inertia(m);
        let inv_i = rot * Mat3::from_diagonal(inertia.recip()) * rot.transpose();
        let i_world = rot * Mat3::from_diagonal(inertia) * rot.transpose();
        let anchor = tf.transform_point(d.local_anchor);
        let r = anchor - tf.translation;
        // K·x = x/m + (I⁻¹(r × x)) × r: the anchor's acceleration per unit force.
        let k = |x: Vec3| x / m + (inv_i * r.cross(x)).cross(r);
        let point_mass = Mat3::from_cols(k(Vec3::X), k(Vec3::Y), k(Vec3::Z)).inverse();
        let v_anchor = v.linear + v.angular.cross(r);
        let force = point_mass * (omega * omega * (d.target - anchor) - 2.0 * omega * v_anchor);
        let torque = r.cross(force) - 0.5 * omega * (i_world * v.angular);
        // A held body is being moved by hand: it must not fall asleep in the air.
        commands
            .entity(e)
            .insert((ExternalForce { force, torque }, SleepTimer(0.0)));
    }
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
