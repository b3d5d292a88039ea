//! Debug gizmos, each switchable: joints (their anchors and what joins them), contact
//! points with their normals, the broad phase's swept bounding boxes, and body
//! velocities.

use bevy::prelude::*;

use crate::joint::{Joint, JointKind};
use crate::world::{PhysicsWorld, STATIC};

/// Draws the gizmos [`DebugRenderSettings`] switches on.
pub struct DebugRenderPlugin;

/// Which debug gizmos are drawn (joints on, the rest off by default).
#[derive(Resource, Clone, Copy, Debug)]
pub struct DebugRenderSettings {
    /// Joints: a line between their anchors (a string, a rod) and a dot at each.
    pub joints: bool,
    /// Contact points and their normals.
    pub contacts: bool,
    /// The broad phase's swept, fattened bounding boxes.
    pub aabbs: bool,
    /// Each body's linear velocity as an arrow (0.25 m per m/s).
    pub velocities: bool,
}

impl Default for DebugRenderSettings {
    fn default() -> Self {
        Self {
            joints: true,
            contacts: false,
            aabbs: false,
            velocities: false,
        }
    }
}

impl Plugin for DebugRenderPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<DebugRenderSettings>()
            .add_systems(Update, (draw_debug, draw_joints));
    }
}

/// Each joint's anchors, joined by a line: at the bodies' rendered poses.
fn draw_joints(
    settings: Res<DebugRenderSettings>,
    joints: Query<&Joint>,
    bodies: Query<&GlobalTransform>,
    mut gizmos: Gizmos,
) {
    if !settings.joints {
        return;
    }
    for j in &joints {
        let anchor = |body: Option<Entity>, local: Vec3| match body {
            None => Some(local),
            Some(e) => bodies.get(e).ok().map(|g| {
                let (_, rot, at) = g.to_scale_rotation_translation();
                at + rot * local
            }),
        };
        let (Some(a), Some(b)) = (
            anchor(j.body1, j.local_anchor1),
            anchor(Some(j.body2), j.local_anchor2),
        ) else {
            continue;
        };
        let color = match j.kind {
            JointKind::Distance { .. } => Color::srgb(0.85, 0.85, 0.8),
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => Color::srgb(1.0, 0.6, 0.2),
            JointKind::Fixed | JointKind::Spherical { .. } => Color::srgb(0.3, 0.8, 1.0),
        };
        gizmos.line(a, b, color);
        for p in [a, b] {
            gizmos.sphere(Isometry3d::from_translation(p), 0.03, color);
        }
    }
}

fn draw_debug(world: Res<PhysicsWorld>, settings: Res<DebugRenderSettings>, mut gizmos: Gizmos) {
    if settings.contacts {
        for m in &world.manifolds {
            for p in m.points() {
                let color = if p.normal_impulse > 0.0 {
                    Color::srgb(1.0, 0.9, 0.1)
                } else {
                    Color::srgb(0.4, 0.4, 0.4)
                };
                gizmos.sphere(Isometry3d::from_translation(p.point), 0.03, color);
                gizmos.arrow(p.point, p.point - m.normal * 0.3, color);
            }
        }
    }
    if settings.aabbs {
        // Awake colliders (swept bounds of this step), then the whole fixed set.
        let awake = world.colliders.iter().filter(|c| c.body != STATIC);
        for c in awake.chain(world.fixed.entries()) {
            if !(c.aabb_max.is_finite() && c.aabb_min.is_finite()) {
                continue;
            }
            let color = match (c.body == STATIC, c.asleep) {
                (false, _) => Color::srgb(0.2, 0.9, 0.4),
                (true, true) => Color::srgb(0.5, 0.5, 0.5),
                (true, false) => Color::srgb(0.3, 0.3, 0.8),
            };
            let centre = 0.5 * (c.aabb_min + c.aabb_max);
            let transform = Transform::from_translation(centre).with_scale(c.aabb_max - c.aabb_min);
            gizmos.cube(transform, color);
        }
    }
    if settings.velocities {
        for (i, s) in world.solver_bodies.iter().enumerate() {
            let (p, _) = world.body_pose(i);
            gizmos.arrow(p, p + s.v * 0.25, Color::srgb(1.0, 0.3, 0.3));
        }
    }
}
