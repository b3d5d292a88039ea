//! A `bevy_picking` backend on [`SpatialQuery::ray_hits`] (feature `picking`): colliders
//! are pickable without meshes, by their exact shapes. Add [`PhysicsPickingPlugin`]
//! beside Bevy's picking plugins; `Pickable` works as for meshes (`is_hoverable: false`
//! skips a collider, `should_block_lower` stops the ray at it).

use bevy::camera::Camera;
use bevy::picking::Pickable;
use bevy::picking::PickingSystems;
use bevy::picking::backend::ray::RayMap;
use bevy::picking::backend::{HitData, PointerHits};
use bevy::prelude::*;

use crate::query::{SpatialQuery, SpatialQueryFilter};

/// Picks colliders by ray casts against the last step's poses.
#[derive(Default)]
pub struct PhysicsPickingPlugin;

impl Plugin for PhysicsPickingPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PhysicsPickingSettings>().add_systems(
            PreUpdate,
            update_physics_hits.in_set(PickingSystems::Backend),
        );
    }
}

/// Which colliders the physics picking backend reports.
#[derive(Resource, Clone, Debug)]
pub struct PhysicsPickingSettings {
    /// Layers, excluded entities, sensors (sensors are not picked by default).
    pub filter: SpatialQueryFilter,
    /// How far a pointer's ray reaches, m.
    pub max_distance: f32,
    /// The most colliders one ray reports (nearest first).
    pub max_hits: usize,
}

impl Default for PhysicsPickingSettings {
    fn default() -> Self {
        Self {
            filter: SpatialQueryFilter::default().without_sensors(),
            max_distance: 1.0e4,
            max_hits: 8,
        }
    }
}

/// Casts each pointer's ray and reports the colliders it hits, nearest first.
pub fn update_physics_hits(
    settings: Res<PhysicsPickingSettings>,
    ray_map: Res<RayMap>,
    cameras: Query<&Camera>,
    pickables: Query<&Pickable>,
    query: SpatialQuery,
    mut hits: MessageWriter<PointerHits>,
) {
    for (&ray_id, &ray) in ray_map.iter() {
        let Ok(camera) = cameras.get(ray_id.camera) else {
            continue;
        };
        let found = query.ray_hits(
            ray.origin,
            ray.direction,
            settings.max_distance,
            settings.max_hits,
            true,
            &settings.filter,
        );
        let mut picks = Vec::new();
        for hit in found {
            let pickable = pickables.get(hit.entity).ok();
            if pickable.is_some_and(|p| !p.is_hoverable) {
                continue;
            }
            let data = HitData::new(
                ray_id.camera,
                hit.distance,
                Some(hit.point),
                Some(hit.normal),
            );
            picks.push((hit.entity, data));
            if pickable.is_none_or(|p| p.should_block_lower) {
                break;
            }
        }
        if !picks.is_empty() {
            hits.write(PointerHits::new(ray_id.pointer, picks, camera.order as f32));
        }
    }
}
