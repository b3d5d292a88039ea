//! Debug gizmos, each switchable: contact points with their normals, the broad phase's
//! swept bounding boxes, and body velocities.

use bevy::prelude::*;

use crate::world::{PhysicsWorld, STATIC};

/// Draws the gizmos [`DebugRenderSettings`] switches on.
pub struct DebugRenderPlugin;

/// Which debug gizmos are drawn (all off by default).
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct DebugRenderSettings {
    /// Contact points and their normals.
    pub contacts: bool,
    /// The broad phase's swept, fattened bounding boxes.
    pub aabbs: bool,
    /// Each body's linear velocity as an arrow (0.25 m per m/s).
    pub velocities: bool,
}

impl Plugin for DebugRenderPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<DebugRenderSettings>()
            .add_systems(Update, draw_debug);
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
