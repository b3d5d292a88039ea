//! The scene file format. Every field but the bodies has a default, so a scene file says
//! only what it needs.

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::body::{DEFAULT_DENSITY, RigidBody};
use crate::collider::Collider;
use crate::effects::{Effects, Wind};
use crate::settings::Integrator;

use super::check;

/// One scene file.
#[derive(TypePath, Serialize, Deserialize, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "viz", derive(bevy::asset::Asset))]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    pub name: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub settings: SceneSettings,
    /// Where the demo's camera looks from.
    #[serde(default)]
    pub camera: CameraDesc,
    #[serde(default)]
    pub planes: Vec<PlaneDesc>,
    #[serde(default)]
    pub bodies: Vec<BodyGroup>,
}

/// Simulation settings a scene asks for.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SceneSettings {
    #[serde(deserialize_with = "check::gravity")]
    pub gravity: Vec3,
    pub integrator: Integrator,
    /// Fixed steps per second, 1..=10000.
    #[serde(deserialize_with = "check::hz")]
    pub hz: f64,
    /// 1..=64.
    #[serde(deserialize_with = "check::count")]
    pub substeps: u32,
    /// 1..=64.
    #[serde(deserialize_with = "check::count")]
    pub iterations: u32,
    /// Which effects the scene runs; left out: the defaults.
    pub effects: Effects,
    /// The wind, when `effects.wind` is on.
    #[serde(deserialize_with = "check::wind")]
    pub wind: Wind,
}

impl Default for SceneSettings {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            integrator: Integrator::default(),
            hz: 60.0,
            substeps: 4,
            iterations: 1,
            effects: Effects::default(),
            wind: Wind::default(),
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDesc {
    pub focus: Vec3,
    pub distance: f32,
    /// Degrees.
    pub yaw: f32,
    pub pitch: f32,
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self {
            focus: Vec3::new(0.0, 1.0, 0.0),
            distance: 16.0,
            yaw: 20.0,
            pitch: 25.0,
        }
    }
}

/// A static plane: infinite, or a rectangle (walls, slopes, ramps).
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PlaneDesc {
    #[serde(deserialize_with = "check::position")]
    pub position: Vec3,
    #[serde(deserialize_with = "check::normal")]
    pub normal: Vec3,
    /// Turn about the normal, degrees (orients a rectangle).
    pub spin_deg: f32,
    /// Half extents of the rectangle along the plane's local x and z; `None`: infinite.
    #[serde(deserialize_with = "check::opt_rect")]
    pub half_extents: Option<Vec2>,
    #[serde(deserialize_with = "check::friction")]
    pub friction: f32,
    #[serde(deserialize_with = "check::restitution")]
    pub restitution: f32,
}

impl Default for PlaneDesc {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            normal: Vec3::Y,
            spin_deg: 0.0,
            half_extents: None,
            friction: 0.5,
            restitution: 0.0,
        }
    }
}

impl PlaneDesc {
    /// Local +Y turned onto `normal`, then spun by `spin_deg` about it.
    pub fn rotation(&self) -> Quat {
        let n = self.normal.normalize_or(Vec3::Y);
        Quat::from_axis_angle(n, self.spin_deg.to_radians()) * Quat::from_rotation_arc(Vec3::Y, n)
    }
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum ShapeDesc {
    Sphere(#[serde(deserialize_with = "check::size")] f32),
    /// Half extents.
    Cuboid(#[serde(deserialize_with = "check::sizes")] Vec3),
}

/// One body.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct BodyDesc {
    pub shape: ShapeDesc,
    pub kind: RigidBody,
    #[serde(deserialize_with = "check::position")]
    pub position: Vec3,
    /// Euler angles XYZ, degrees.
    #[serde(deserialize_with = "check::angles")]
    pub rotation_deg: Vec3,
    #[serde(deserialize_with = "check::velocity")]
    pub velocity: Vec3,
    #[serde(deserialize_with = "check::spin")]
    pub angular_velocity: Vec3,
    /// kg; when absent, `density` (or water's) times the volume.
    #[serde(deserialize_with = "check::opt_positive")]
    pub mass: Option<f32>,
    #[serde(deserialize_with = "check::opt_positive")]
    pub density: Option<f32>,
    #[serde(deserialize_with = "check::opt_friction")]
    pub friction: Option<f32>,
    #[serde(deserialize_with = "check::opt_restitution")]
    pub restitution: Option<f32>,
}

impl BodyDesc {
    /// `mass`, or else `density` (water's by default) times the shape's volume, kg.
    pub fn mass(&self) -> f32 {
        let volume = self.collider().shape.volume();
        self.mass
            .unwrap_or_else(|| volume * self.density.unwrap_or(DEFAULT_DENSITY))
    }

    pub fn collider(&self) -> Collider {
        match self.shape {
            ShapeDesc::Sphere(r) => Collider::sphere(r),
            ShapeDesc::Cuboid(h) => Collider::cuboid(h.x, h.y, h.z),
        }
    }

    /// The orientation from `rotation_deg` (Euler XYZ).
    pub fn rotation(&self) -> Quat {
        let r = self.rotation_deg * (std::f32::consts::PI / 180.0);
        Quat::from_euler(EulerRot::XYZ, r.x, r.y, r.z)
    }
}

impl Default for BodyDesc {
    fn default() -> Self {
        Self {
            shape: ShapeDesc::Cuboid(Vec3::splat(0.5)),
            kind: RigidBody::Dynamic,
            position: Vec3::ZERO,
            rotation_deg: Vec3::ZERO,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            mass: None,
            density: None,
            friction: None,
            restitution: None,
        }
    }
}

/// A body or a generated group of copies of a template body (`body`), placed relative to
/// the template's position.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
pub enum BodyGroup {
    Single(BodyDesc),
    /// count.x × count.y × count.z copies `spacing` apart.
    Grid {
        body: BodyDesc,
        #[serde(deserialize_with = "check::grid_count")]
        count: UVec3,
        spacing: Vec3,
    },
    /// `count` copies stacked along +Y `spacing` apart, every other one shifted by `jitter`.
    Stack {
        body: BodyDesc,
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        #[serde(default)]
        jitter: Vec3,
    },
    /// A square pyramid: layers of base², (base−1)², …, 1 copies `spacing` apart; `flat`
    /// makes it a one-deep wall (rows of base, base−1, …).
    Pyramid {
        body: BodyDesc,
        #[serde(deserialize_with = "check::pyramid_base")]
        base: u32,
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        #[serde(default)]
        flat: bool,
    },
    /// `count` copies at seeded random positions in the box `min`..`max`, random turns;
    /// the mass of each is scaled by a random factor in `mass_range` when given.
    Pile {
        body: BodyDesc,
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        seed: u64,
        min: Vec3,
        max: Vec3,
        #[serde(default)]
        mass_range: Option<Vec2>,
    },
    /// A row of `count` copies `spacing` apart along `direction`.
    Row {
        body: BodyDesc,
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        direction: Vec3,
    },
}
