//! The scene file format. Every field but the scene's name has a default, so a scene file
//! says only what it needs.

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
    /// The scene's name, used in log messages.
    pub name: String,
    /// What the scene shows, free text. Default empty.
    #[serde(default)]
    pub description: String,
    /// Simulation settings; left out: [`SceneSettings::default`].
    #[serde(default)]
    pub settings: SceneSettings,
    /// Where the demo's camera looks from.
    #[serde(default)]
    pub camera: CameraDesc,
    /// Static planes (ground, walls, ramps). Default none.
    #[serde(default)]
    pub planes: Vec<PlaneDesc>,
    /// Static triangle meshes and heightfields (terrain, ramps). Default none.
    #[serde(default)]
    pub meshes: Vec<MeshDesc>,
    /// The bodies, single or in generated groups. Default none.
    #[serde(default)]
    pub bodies: Vec<BodyGroup>,
    /// Joints between the bodies (by index, groups expanded) or to the world. Default
    /// none.
    #[serde(default)]
    pub joints: Vec<super::joints::JointGroup>,
}

/// Simulation settings a scene asks for.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SceneSettings {
    /// Gravitational acceleration, m/s², each component within ±1e4
    /// ([`MAX_ACCELERATION`](crate::limits::MAX_ACCELERATION)). Default (0, −9.81, 0).
    #[serde(deserialize_with = "check::gravity")]
    pub gravity: Vec3,
    /// The time integrator. Default semi-implicit Euler.
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

/// Where the demo's camera starts: orbiting `focus` at `distance`, turned by `yaw` and
/// `pitch`.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDesc {
    /// The point the camera looks at and orbits, m (world). Default (0, 1, 0).
    pub focus: Vec3,
    /// Distance from `focus`, m. Default 16.
    pub distance: f32,
    /// Degrees.
    pub yaw: f32,
    /// Angle of the camera above `focus`, from the horizontal, degrees. Default 25.
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
    /// A point on the plane, the centre of a rectangle, m (world). Default the origin.
    #[serde(deserialize_with = "check::position")]
    pub position: Vec3,
    /// The direction the plane faces; any finite non-zero length. Default +Y.
    #[serde(deserialize_with = "check::normal")]
    pub normal: Vec3,
    /// Turn about the normal, degrees (orients a rectangle).
    pub spin_deg: f32,
    /// Half extents of the rectangle along the plane's local x and z; `None`: infinite.
    #[serde(deserialize_with = "check::opt_rect")]
    pub half_extents: Option<Vec2>,
    /// Friction coefficient, 0..=1e4. Default 0.5.
    #[serde(deserialize_with = "check::friction")]
    pub friction: f32,
    /// Coefficient of restitution, 0 (no bounce) to 1. Default 0.
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

/// A body's shape.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum ShapeDesc {
    /// A sphere of this radius, m.
    Sphere(#[serde(deserialize_with = "check::size")] f32),
    /// Half extents.
    Cuboid(#[serde(deserialize_with = "check::sizes")] Vec3),
    /// A capsule along Y: (radius, half the inner segment's length), m.
    Capsule(
        #[serde(deserialize_with = "check::size")] f32,
        #[serde(deserialize_with = "check::size")] f32,
    ),
    /// A cylinder along Y: (radius, half height), m.
    Cylinder(
        #[serde(deserialize_with = "check::size")] f32,
        #[serde(deserialize_with = "check::size")] f32,
    ),
    /// A cone along Y, tip up: (base radius, half height), m.
    Cone(
        #[serde(deserialize_with = "check::size")] f32,
        #[serde(deserialize_with = "check::size")] f32,
    ),
    /// A rock: the convex hull of 14 points about `radius` (m) from its centre, each
    /// pushed in or out by up to a third, seeded by the second value.
    Rock(#[serde(deserialize_with = "check::size")] f32, u64),
}

/// A static triangle mesh or heightfield.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
pub enum MeshDesc {
    /// Terrain: heights h(x, z) = `amplitude`·sin(2πx/`wavelength`)·cos(2πz/`wavelength`)
    /// on a grid of `samples` points across `size` (m, X by Z), centred on `position`.
    Heightfield {
        /// The field's centre, m (world).
        #[serde(deserialize_with = "check::position")]
        position: Vec3,
        /// Extent along X and Z, m.
        size: Vec2,
        /// Grid points along X and Z, at least 2 each.
        samples: UVec2,
        /// Peak height, m.
        amplitude: f32,
        /// Length of one wave along X and Z, m.
        wavelength: f32,
    },
    /// A triangle mesh at `position`, turned by `rotation_deg` (Euler XYZ), its
    /// triangles counter-clockwise seen from outside.
    TriMesh {
        /// The mesh's origin, m (world).
        #[serde(deserialize_with = "check::position")]
        position: Vec3,
        /// Euler angles XYZ, degrees.
        #[serde(default)]
        rotation_deg: Vec3,
        /// Vertices, m (the mesh's frame).
        vertices: Vec<Vec3>,
        /// Triangles: three indices into `vertices` each.
        triangles: Vec<[u32; 3]>,
    },
}

impl MeshDesc {
    /// The collider and its pose.
    pub fn collider(&self) -> Result<(Collider, Transform), String> {
        match self {
            MeshDesc::Heightfield {
                position,
                size,
                samples,
                amplitude,
                wavelength,
            } => {
                let (nx, nz) = (samples.x.max(2) as usize, samples.y.max(2) as usize);
                let k = std::f32::consts::TAU / wavelength;
                let heights: Vec<Vec<f32>> = (0..nx)
                    .map(|i| {
                        let x = (i as f32 / (nx - 1) as f32 - 0.5) * size.x;
                        (0..nz)
                            .map(|j| {
                                let z = (j as f32 / (nz - 1) as f32 - 0.5) * size.y;
                                amplitude * (k * x).sin() * (k * z).cos()
                            })
                            .collect()
                    })
                    .collect();
                let c = Collider::heightfield(&heights, *size)?;
                Ok((c, Transform::from_translation(*position)))
            }
            MeshDesc::TriMesh {
                position,
                rotation_deg,
                vertices,
                triangles,
            } => {
                let c = Collider::trimesh(vertices.clone(), triangles.clone())?;
                let r = *rotation_deg * (std::f32::consts::PI / 180.0);
                let rot = Quat::from_euler(EulerRot::XYZ, r.x, r.y, r.z);
                Ok((c, Transform::from_translation(*position).with_rotation(rot)))
            }
        }
    }
}

/// One body.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct BodyDesc {
    /// The collider's shape. Default a 1 m cube (half extents 0.5 m).
    pub shape: ShapeDesc,
    /// Dynamic, static or kinematic. Default dynamic.
    pub kind: RigidBody,
    /// Position of the body's centre, m (world). Default the origin.
    #[serde(deserialize_with = "check::position")]
    pub position: Vec3,
    /// Euler angles XYZ, degrees.
    #[serde(deserialize_with = "check::angles")]
    pub rotation_deg: Vec3,
    /// Initial linear velocity, m/s (world). Default zero.
    #[serde(deserialize_with = "check::velocity")]
    pub velocity: Vec3,
    /// Initial angular velocity, rad/s (world). Default zero.
    #[serde(deserialize_with = "check::spin")]
    pub angular_velocity: Vec3,
    /// kg; when absent, `density` (or water's) times the volume.
    #[serde(deserialize_with = "check::opt_positive")]
    pub mass: Option<f32>,
    /// kg/m³, used when `mass` is absent; default water's ([`DEFAULT_DENSITY`], 1000).
    #[serde(deserialize_with = "check::opt_positive")]
    pub density: Option<f32>,
    /// Friction coefficient, 0..=1e4; default
    /// [`DEFAULT_FRICTION`](crate::body::DEFAULT_FRICTION) (0.5).
    #[serde(deserialize_with = "check::opt_friction")]
    pub friction: Option<f32>,
    /// Coefficient of restitution, 0 (no bounce) to 1; default 0.
    #[serde(deserialize_with = "check::opt_restitution")]
    pub restitution: Option<f32>,
    /// No rotation at all (a character's capsule). Default false.
    pub lock_rotation: bool,
    /// A constant force on the body, N (world). Default zero.
    #[serde(deserialize_with = "check::velocity")]
    pub force: Vec3,
    /// Linear drag coefficient, 1/s (with a force: a top speed of force / (mass·drag)).
    /// Default 0.
    pub linear_damping: f32,
}

impl BodyDesc {
    /// `mass`, or else `density` (water's by default) times the shape's volume, kg.
    pub fn mass(&self) -> f32 {
        let volume = self.collider().shape.volume();
        self.mass
            .unwrap_or_else(|| volume * self.density.unwrap_or(DEFAULT_DENSITY))
    }

    /// The collider of `shape`.
    pub fn collider(&self) -> Collider {
        match self.shape {
            ShapeDesc::Sphere(r) => Collider::sphere(r),
            ShapeDesc::Cuboid(h) => Collider::cuboid(h.x, h.y, h.z),
            ShapeDesc::Capsule(r, h) => Collider::capsule(r, h),
            ShapeDesc::Cylinder(r, h) => Collider::cylinder(r, h),
            ShapeDesc::Cone(r, h) => Collider::cone(r, h),
            ShapeDesc::Rock(r, seed) => {
                let points = super::generate::rock_points(r, seed);
                Collider::convex_hull(&points).unwrap_or(Collider::sphere(r))
            }
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
            lock_rotation: false,
            force: Vec3::ZERO,
            linear_damping: 0.0,
        }
    }
}

/// A body or a generated group of copies of a template body (`body`), placed relative to
/// the template's position (a pile: anywhere in its box).
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
pub enum BodyGroup {
    /// One body.
    Single(BodyDesc),
    /// count.x × count.y × count.z copies `spacing` apart.
    Grid {
        /// The template; the copy at (0, 0, 0) sits at its position.
        body: BodyDesc,
        /// Copies along x, y and z; at most 100 000 in all.
        #[serde(deserialize_with = "check::grid_count")]
        count: UVec3,
        /// Distance between neighbouring copies along x, y and z, m.
        spacing: Vec3,
    },
    /// `count` copies stacked along +Y `spacing` apart, shifted alternately by +`jitter`
    /// and −`jitter`.
    Stack {
        /// The template; the bottom copy sits at its position (plus `jitter`).
        body: BodyDesc,
        /// Number of copies, at most 100 000.
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        /// Distance between neighbouring copies along +Y, m.
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        /// Offset, m, added to the 1st, 3rd, … copy and taken from the 2nd, 4th, ….
        /// Default zero.
        #[serde(default)]
        jitter: Vec3,
    },
    /// A square pyramid: layers of base², (base−1)², …, 1 copies `spacing` apart; `flat`
    /// makes it a one-deep wall (rows of base, base−1, …).
    Pyramid {
        /// The template; the bottom layer is centred on its position.
        body: BodyDesc,
        /// Copies along a side of the bottom layer, at most 400.
        #[serde(deserialize_with = "check::pyramid_base")]
        base: u32,
        /// Distance between neighbouring copies, across and up, m.
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        /// One copy deep, a wall in the x–y plane. Default false.
        #[serde(default)]
        flat: bool,
    },
    /// `count` copies at seeded random positions in the box `min`..`max`, random turns;
    /// the mass of each is scaled by a random factor in `mass_range` when given.
    Pile {
        /// The template; its position and rotation are not used.
        body: BodyDesc,
        /// Number of copies, at most 100 000.
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        /// Seed of the random positions, turns and masses: the same seed, the same pile.
        seed: u64,
        /// Lowest corner of the box, m (world).
        min: Vec3,
        /// Highest corner of the box, m (world).
        max: Vec3,
        /// The range (x to y) of the factor each copy's mass is multiplied by; when the
        /// template has no `mass`, the drawn value is the mass, kg. Default `None`: every
        /// copy has the template's mass.
        #[serde(default)]
        mass_range: Option<Vec2>,
    },
    /// A row of `count` copies `spacing` apart along `direction`.
    Row {
        /// The template; the first copy sits at its position.
        body: BodyDesc,
        /// Number of copies, at most 100 000.
        #[serde(deserialize_with = "check::group_count")]
        count: u32,
        /// Distance between the centres of neighbouring copies, m.
        #[serde(deserialize_with = "check::spacing")]
        spacing: f32,
        /// The row's direction, any length; zero gives +X.
        direction: Vec3,
    },
}
