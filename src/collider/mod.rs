//! Collision shapes and the mass properties they imply.

mod mass;
mod mesh;

use bevy::prelude::*;

pub use mesh::{ConvexHull, HeightFieldShape, TriMeshShape};

/// The geometry of a body. Sizes are in metres, before the entity's `Transform::scale`
/// (see [`Shape::scaled`]).
#[derive(Component, Reflect, Clone, Debug, PartialEq)]
#[reflect(Component)]
#[require(Transform)]
pub struct Collider {
    /// The shape, in the entity's local frame, centred on its origin.
    pub shape: Shape,
}

/// The shapes tumble collides. The narrow phase dispatches over pairs of these.
#[derive(Reflect, Clone, Debug, PartialEq)]
pub enum Shape {
    /// A ball.
    Sphere {
        /// Radius, m.
        radius: f32,
    },
    /// A box given by its half extents.
    Cuboid {
        /// Half the box's size along local x, y, z, m.
        half_extents: Vec3,
    },
    /// A capsule along local Y: a segment from −`half_height` to +`half_height` swept by
    /// a ball of `radius` (total height 2·(half_height + radius)). Collided by parry3d.
    Capsule {
        /// Radius of the swept ball, m.
        radius: f32,
        /// Half the length of the inner segment (the caps excluded), m.
        half_height: f32,
    },
    /// A solid cylinder along local Y, from −`half_height` to +`half_height`. Collided by
    /// parry3d.
    Cylinder {
        /// Radius, m.
        radius: f32,
        /// Half the height, m.
        half_height: f32,
    },
    /// A solid cone along local Y: its base (of `radius`) at −`half_height`, its tip at
    /// +`half_height`; the origin is midway, and the centre of mass a quarter of the
    /// height above the base (see [`Shape::center_of_mass`]). Collided by parry3d.
    Cone {
        /// Radius of the base, m.
        radius: f32,
        /// Half the height, m.
        half_height: f32,
    },
    /// The convex hull of a set of points. Collided by parry3d.
    ConvexHull(ConvexHull),
    /// A triangle mesh, for static and kinematic bodies only. Collided by parry3d.
    TriMesh(TriMeshShape),
    /// A heightfield, for static and kinematic bodies only. Collided by parry3d.
    HeightField(HeightFieldShape),
    /// A static plane through the origin of its entity with normal local +Y. `half_extents`
    /// bounds it to a rectangle in local X/Z; `None` makes it infinite.
    Plane {
        /// Half the rectangle's size along local x and z, m; `None`: infinite.
        half_extents: Option<Vec2>,
    },
}

/// Index of a shape kind in the narrow phase's dispatch table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ShapeKind {
    /// [`Shape::Sphere`].
    Sphere = 0,
    /// [`Shape::Cuboid`].
    Cuboid = 1,
    /// [`Shape::Capsule`].
    Capsule = 2,
    /// [`Shape::Cylinder`].
    Cylinder = 3,
    /// [`Shape::Cone`].
    Cone = 4,
    /// [`Shape::ConvexHull`].
    ConvexHull = 5,
    /// [`Shape::TriMesh`] (from here on: shapes that never move by contact).
    TriMesh = 6,
    /// [`Shape::HeightField`].
    HeightField = 7,
    /// [`Shape::Plane`] (last: planes are static only).
    Plane = 8,
}

impl ShapeKind {
    /// How many kinds there are (the size of the dispatch table).
    pub const COUNT: usize = 9;
}

impl Collider {
    /// A ball of `radius` m.
    pub fn sphere(radius: f32) -> Self {
        Self {
            shape: Shape::Sphere { radius },
        }
    }
    /// A box from its half extents.
    pub fn cuboid(half_x: f32, half_y: f32, half_z: f32) -> Self {
        Self {
            shape: Shape::Cuboid {
                half_extents: Vec3::new(half_x, half_y, half_z),
            },
        }
    }
    /// A capsule along local Y: the segment between y = ±`half_height` swept by a ball
    /// of `radius` (avian's `Capsule::new(radius, length)` takes the whole segment length).
    pub fn capsule(radius: f32, half_height: f32) -> Self {
        Self {
            shape: Shape::Capsule {
                radius,
                half_height,
            },
        }
    }
    /// A solid cylinder along local Y of `radius` and height 2·`half_height`.
    pub fn cylinder(radius: f32, half_height: f32) -> Self {
        Self {
            shape: Shape::Cylinder {
                radius,
                half_height,
            },
        }
    }
    /// A solid cone along local Y: base of `radius` at y = −`half_height`, tip at
    /// +`half_height`.
    pub fn cone(radius: f32, half_height: f32) -> Self {
        Self {
            shape: Shape::Cone {
                radius,
                half_height,
            },
        }
    }
    /// The convex hull of `points` (m, local frame); `None` if they span no volume.
    pub fn convex_hull(points: &[Vec3]) -> Option<Self> {
        ConvexHull::from_points(points).map(|h| Self {
            shape: Shape::ConvexHull(h),
        })
    }
    /// A triangle mesh from `vertices` (m, local frame) and triangles of indices into
    /// them, counter-clockwise seen from outside. For static and kinematic bodies.
    pub fn trimesh(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, String> {
        TriMeshShape::new(vertices, triangles).map(|m| Self {
            shape: Shape::TriMesh(m),
        })
    }
    /// A heightfield: `heights[i][j]` (m, along local Y) at evenly spaced points, rows
    /// `i` along local X and columns `j` along local Z, spanning `size` (m, X by Z)
    /// centred on the origin. For static and kinematic bodies.
    pub fn heightfield(heights: &[Vec<f32>], size: Vec2) -> Result<Self, String> {
        HeightFieldShape::new(heights, size).map(|f| Self {
            shape: Shape::HeightField(f),
        })
    }
    /// An infinite static plane through the entity's origin, normal along local +Y.
    pub fn plane() -> Self {
        Self {
            shape: Shape::Plane { half_extents: None },
        }
    }
    /// A static plane bounded to the rectangle |x| ≤ half_x, |z| ≤ half_z (local frame).
    pub fn plane_rect(half_x: f32, half_z: f32) -> Self {
        Self {
            shape: Shape::Plane {
                half_extents: Some(Vec2::new(half_x, half_z)),
            },
        }
    }
}

impl Shape {
    /// Which kind of shape this is (its row in the narrow phase's table).
    pub fn kind(&self) -> ShapeKind {
        match self {
            Shape::Sphere { .. } => ShapeKind::Sphere,
            Shape::Cuboid { .. } => ShapeKind::Cuboid,
            Shape::Capsule { .. } => ShapeKind::Capsule,
            Shape::Cylinder { .. } => ShapeKind::Cylinder,
            Shape::Cone { .. } => ShapeKind::Cone,
            Shape::ConvexHull(_) => ShapeKind::ConvexHull,
            Shape::TriMesh(_) => ShapeKind::TriMesh,
            Shape::HeightField(_) => ShapeKind::HeightField,
            Shape::Plane { .. } => ShapeKind::Plane,
        }
    }

    /// Checks sizes: every size must be finite, > 0 and at most
    /// [`MAX_SIZE`](crate::limits::MAX_SIZE). Returns the reason otherwise.
    pub fn validate(&self) -> Result<(), String> {
        let ok = |v: f32| v.is_finite() && v > 0.0 && v <= crate::limits::MAX_SIZE;
        match *self {
            Shape::Sphere { radius } if !ok(radius) => Err(format!("sphere radius {radius}")),
            Shape::Cuboid { half_extents: h } if !(ok(h.x) && ok(h.y) && ok(h.z)) => {
                Err(format!("cuboid half extents {h}"))
            }
            Shape::Capsule {
                radius,
                half_height,
            }
            | Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Cone {
                radius,
                half_height,
            } if !(ok(radius) && ok(half_height)) => Err(format!(
                "{:?} radius {radius}, half height {half_height}",
                self.kind()
            )),
            Shape::Plane {
                half_extents: Some(h),
            } if !(ok(h.x) && ok(h.y)) => Err(format!("plane half extents {h}")),
            // Built checked; what scaling can break is their size.
            Shape::ConvexHull(_) | Shape::TriMesh(_) | Shape::HeightField(_) => {
                let (lo, hi) = self.aabb(Vec3::ZERO, Quat::IDENTITY);
                let size = (hi - lo).max_element();
                if ok(size) && lo.is_finite() && hi.is_finite() {
                    Ok(())
                } else {
                    Err(format!("{:?} of size {size}", self.kind()))
                }
            }
            _ => Ok(()),
        }
    }

    /// The triangles of a shape made of points (hull, mesh, heightfield), local frame:
    /// vertices (m) and index triples, for drawing; `None` for the others.
    pub fn triangles(&self) -> Option<(Vec<Vec3>, Vec<[u32; 3]>)> {
        match *self {
            Shape::ConvexHull(ref h) => Some(h.polyhedron().to_trimesh()),
            Shape::TriMesh(ref m) => {
                Some((m.mesh().vertices().to_vec(), m.mesh().indices().to_vec()))
            }
            Shape::HeightField(ref f) => Some(f.field().to_trimesh()),
            _ => None,
        }
    }

    /// The shape under a `Transform::scale`: a box's half extents and a bounded plane's
    /// rectangle scale per axis (by the magnitude), a sphere by its largest axis (a
    /// sphere cannot scale non-uniformly: see [`scales_exactly`](Self::scales_exactly)),
    /// a capsule, cylinder or cone along Y by y and across by the larger of x and z, an
    /// infinite plane not at all.
    pub fn scaled(&self, scale: Vec3) -> Self {
        let s = scale.abs();
        if s == Vec3::ONE {
            return self.clone();
        }
        match *self {
            Shape::Sphere { radius } => Shape::Sphere {
                radius: radius * s.max_element(),
            },
            Shape::Cuboid { half_extents } => Shape::Cuboid {
                half_extents: half_extents * s,
            },
            // Round across the axis (the larger of x and z), scaled along it by y.
            Shape::Capsule {
                radius,
                half_height,
            }
            | Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Cone {
                radius,
                half_height,
            } => {
                let (radius, half_height) = (radius * s.x.max(s.z), half_height * s.y);
                match *self {
                    Shape::Capsule { .. } => Shape::Capsule {
                        radius,
                        half_height,
                    },
                    Shape::Cylinder { .. } => Shape::Cylinder {
                        radius,
                        half_height,
                    },
                    _ => Shape::Cone {
                        radius,
                        half_height,
                    },
                }
            }
            // Rebuilt from scaled points (a hull on a moving body with a scale other
            // than one is rebuilt every step: scale its points instead).
            // A hull that cannot be rebuilt (a scale that flattens it to a plane or a
            // line) becomes its bounding box under the same scale, which validation
            // refuses as it refuses a flattened box: never the unscaled hull, silently.
            Shape::ConvexHull(ref h) => h.scaled(s).map_or_else(
                || {
                    let (lo, hi) = self.aabb(Vec3::ZERO, Quat::IDENTITY);
                    Shape::Cuboid {
                        half_extents: (hi - lo) * 0.5 * s,
                    }
                },
                Shape::ConvexHull,
            ),
            Shape::TriMesh(ref m) => Shape::TriMesh(m.scaled(scale)),
            Shape::HeightField(ref f) => Shape::HeightField(f.scaled(s)),
            Shape::Plane { half_extents } => Shape::Plane {
                half_extents: half_extents.map(|h| h * Vec2::new(s.x, s.z)),
            },
        }
    }

    /// Whether [`scaled`](Self::scaled) is exact for this scale (not for a sphere
    /// stretched more along one axis than another, nor a capsule, cylinder or cone
    /// stretched unevenly across its axis, nor a capsule along it: its caps stay round).
    pub fn scales_exactly(&self, scale: Vec3) -> bool {
        let s = scale.abs();
        match self {
            Shape::Sphere { .. } => s.x == s.y && s.y == s.z,
            Shape::Capsule { .. } => s.x == s.y && s.y == s.z,
            Shape::Cylinder { .. } | Shape::Cone { .. } => s.x == s.z,
            Shape::Cuboid { .. }
            | Shape::Plane { .. }
            | Shape::ConvexHull(_)
            | Shape::TriMesh(_)
            | Shape::HeightField(_) => true,
        }
    }

    /// The shape's smallest dimension, m: a sphere's diameter, a box's thinnest side; a
    /// plane has none (∞).
    #[inline]
    pub fn thickness(&self) -> f32 {
        match *self {
            Shape::Sphere { radius } => 2.0 * radius,
            Shape::Cuboid { half_extents } => 2.0 * half_extents.min_element(),
            Shape::Capsule { radius, .. } => 2.0 * radius,
            Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Cone {
                radius,
                half_height,
            } => 2.0 * radius.min(half_height),
            Shape::ConvexHull(_) => {
                let (lo, hi) = crate::geometry::posed_aabb(self, Vec3::ZERO, Quat::IDENTITY);
                (hi - lo).min_element()
            }
            // Surfaces: as thick as what touches them.
            Shape::TriMesh(_) | Shape::HeightField(_) | Shape::Plane { .. } => f32::INFINITY,
        }
    }

    /// The thinner of two shapes' thicknesses, m: what sets a pair's allowed sag and
    /// its speculative margin.
    #[inline]
    pub fn pair_thickness(&self, other: &Shape) -> f32 {
        self.thickness().min(other.thickness())
    }

    /// World-space bounding box at a pose, as (min, max). Infinite planes are unbounded.
    pub fn aabb(&self, pos: Vec3, rot: Quat) -> (Vec3, Vec3) {
        let half = match *self {
            // Not centred on their origin: parry's box at the pose.
            Shape::ConvexHull(_) | Shape::TriMesh(_) | Shape::HeightField(_) => {
                return crate::geometry::posed_aabb(self, pos, rot);
            }
            Shape::Sphere { radius } => Vec3::splat(radius),
            Shape::Cuboid { half_extents } => abs_rotated(rot, half_extents),
            // The segment's reach along its axis plus the ball.
            Shape::Capsule {
                radius,
                half_height,
            } => (rot * Vec3::Y).abs() * half_height + Vec3::splat(radius),
            // A disc of radius r with normal a reaches r·√(1 − a_i²) along axis i; the two
            // end discs sit ±h·a from the centre. The cone's box is its cylinder's.
            Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Cone {
                radius,
                half_height,
            } => {
                let a = rot * Vec3::Y;
                let disc = (Vec3::ONE - a * a).max(Vec3::ZERO);
                a.abs() * half_height
                    + Vec3::new(disc.x.sqrt(), disc.y.sqrt(), disc.z.sqrt()) * radius
            }
            Shape::Plane {
                half_extents: Some(h),
            } => abs_rotated(rot, Vec3::new(h.x, 0.0, h.y)),
            Shape::Plane { half_extents: None } => Vec3::splat(f32::INFINITY),
        };
        (pos - half, pos + half)
    }
}

/// Half extents of the box `half` rotated by `rot`, projected on the world axes.
fn abs_rotated(rot: Quat, half: Vec3) -> Vec3 {
    let m = Mat3::from_quat(rot);
    Vec3::new(
        m.row(0).abs().dot(half),
        m.row(1).abs().dot(half),
        m.row(2).abs().dot(half),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_inertia_matches_formula() {
        // 1.0 × 0.1 × 0.4 m box, 1 kg: Ixx = (0.01 + 0.16)/12.
        let i = Collider::cuboid(0.5, 0.05, 0.2)
            .shape
            .principal_inertia(1.0);
        assert!((i.x - 0.17 / 12.0).abs() < 1e-7);
        assert!((i.y - 1.16 / 12.0).abs() < 1e-7);
        assert!((i.z - 1.01 / 12.0).abs() < 1e-7);
    }

    #[test]
    fn rotated_box_aabb_grows_by_sqrt2() {
        let s = Collider::cuboid(1.0, 1.0, 1.0).shape;
        let (lo, hi) = s.aabb(
            Vec3::ZERO,
            Quat::from_rotation_y(std::f32::consts::FRAC_PI_4),
        );
        assert!((hi.x - 2f32.sqrt()).abs() < 1e-5 && (lo.z + 2f32.sqrt()).abs() < 1e-5);
        assert!((hi.y - 1.0).abs() < 1e-6);
    }

    #[test]
    fn round_shapes_scale_across_and_along_their_axis() {
        let s = Vec3::new(2.0, 3.0, 1.5);
        for shape in [
            Collider::capsule(0.5, 1.0).shape,
            Collider::cylinder(0.5, 1.0).shape,
            Collider::cone(0.5, 1.0).shape,
        ] {
            let scaled = shape.scaled(s);
            assert_eq!(scaled.kind(), shape.kind());
            let (r, h) = match scaled {
                Shape::Capsule {
                    radius,
                    half_height,
                }
                | Shape::Cylinder {
                    radius,
                    half_height,
                }
                | Shape::Cone {
                    radius,
                    half_height,
                } => (radius, half_height),
                _ => unreachable!(),
            };
            assert_eq!((r, h), (1.0, 3.0), "{scaled:?}");
            // Uneven across the axis is never exact; even across it is, but for a
            // capsule stretched along it (its caps stay round).
            assert!(!shape.scales_exactly(s));
            let even_across = Vec3::new(2.0, 3.0, 2.0);
            let capsule = matches!(shape, Shape::Capsule { .. });
            assert_eq!(shape.scales_exactly(even_across), !capsule, "{shape:?}");
        }
    }

    #[test]
    fn bad_sizes_are_rejected() {
        assert!(Collider::sphere(0.0).shape.validate().is_err());
        assert!(Collider::sphere(f32::NAN).shape.validate().is_err());
        assert!(Collider::cuboid(1.0, -1.0, 1.0).shape.validate().is_err());
        assert!(
            Collider::plane_rect(1.0, f32::INFINITY)
                .shape
                .validate()
                .is_err()
        );
        assert!(Collider::plane().shape.validate().is_ok());
    }
}
