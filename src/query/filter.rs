//! Which colliders a spatial query may report.

use bevy::ecs::entity::EntityHashSet;
use bevy::prelude::*;

use crate::layers::LayerMask;
use crate::world::ColliderEntry;

/// Which colliders a spatial query may report: members of a layer in `mask`, not
/// excluded, and sensors only if `sensors`. The default reports everything, sensors
/// included (as avian3d and bevy_rapier3d do); a shot or a line of sight usually wants
/// [`without_sensors`](Self::without_sensors).
#[derive(Clone, Debug, PartialEq)]
pub struct SpatialQueryFilter {
    /// Layers whose members may be reported (a collider's
    /// [`CollisionLayers::memberships`](crate::layers::CollisionLayers) must meet it).
    pub mask: LayerMask,
    /// Colliders never reported. A body's entity here excludes all its parts too.
    pub excluded_entities: EntityHashSet,
    /// Whether [`Sensor`](crate::layers::Sensor) colliders may be reported.
    pub sensors: bool,
}

impl Default for SpatialQueryFilter {
    fn default() -> Self {
        Self {
            mask: LayerMask::ALL,
            excluded_entities: EntityHashSet::default(),
            sensors: true,
        }
    }
}

impl SpatialQueryFilter {
    /// Reports only members of the layers in `mask`.
    pub fn from_mask(mask: impl Into<LayerMask>) -> Self {
        Self::default().with_mask(mask)
    }

    /// The same, reporting only members of the layers in `mask`.
    pub fn with_mask(mut self, mask: impl Into<LayerMask>) -> Self {
        self.mask = mask.into();
        self
    }

    /// The same, never reporting these colliders or bodies (a body's parts included).
    pub fn with_excluded_entities(mut self, entities: impl IntoIterator<Item = Entity>) -> Self {
        self.excluded_entities.extend(entities);
        self
    }

    /// The same, never reporting sensors.
    pub fn without_sensors(mut self) -> Self {
        self.sensors = false;
        self
    }

    /// Whether a collider may be reported.
    #[inline]
    pub(crate) fn admits(&self, c: &ColliderEntry) -> bool {
        c.filter.layers.memberships.intersects(self.mask)
            && (self.sensors || !c.filter.sensor)
            && (self.excluded_entities.is_empty()
                || !(self.excluded_entities.contains(&c.entity)
                    || self.excluded_entities.contains(&c.owner)))
    }
}
