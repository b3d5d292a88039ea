//! Shapes made of many points, held behind an `Arc` so a collider clones cheaply:
//! convex hulls (for any body) and triangle meshes and heightfields (for static and
//! kinematic bodies: they have no inside to weigh). Built and collided by parry3d.

use std::fmt;
use std::sync::Arc;

use bevy::prelude::*;
use parry3d::shape::{ConvexPolyhedron, HeightField, HeightFieldFlags, TriMesh, TriMeshFlags};
use parry3d::utils::Array2;

/// A convex hull of points, in the collider's local frame. Its mass properties (at unit
/// density) are computed once, when it is built.
#[derive(Clone, Reflect)]
#[reflect(opaque)]
pub struct ConvexHull(Arc<HullData>);

struct HullData {
    poly: ConvexPolyhedron,
    /// Volume, m³.
    volume: f32,
    /// Centre of mass in the local frame, m.
    com: Vec3,
    /// Principal moments about the centre of mass at unit density, kg·m² per kg/m³.
    moments: Vec3,
    /// The principal axes' rotation in the local frame.
    frame: Quat,
}

impl ConvexHull {
    /// The hull of `points` (m, local frame); `None` if they span no volume (fewer than
    /// four points off one plane) or are not finite.
    pub fn from_points(points: &[Vec3]) -> Option<Self> {
        if points.len() < 4 || points.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let poly = ConvexPolyhedron::from_convex_hull(points)?;
        let props = parry3d::shape::Shape::mass_properties(&poly, 1.0);
        let volume = props.mass();
        if !(volume.is_finite() && volume > 0.0) {
            return None;
        }
        Some(Self(Arc::new(HullData {
            poly,
            volume,
            com: props.local_com,
            moments: props.principal_inertia(),
            frame: props.principal_inertia_local_frame.normalize(),
        })))
    }

    /// The hull's vertices, m.
    pub fn points(&self) -> &[Vec3] {
        self.0.poly.points()
    }

    /// Volume, m³.
    pub fn volume(&self) -> f32 {
        self.0.volume
    }

    /// Centre of mass in the local frame, m.
    pub fn center_of_mass(&self) -> Vec3 {
        self.0.com
    }

    /// Principal moments for `mass` kg and the principal axes' rotation in the local
    /// frame.
    pub fn principal_inertia(&self, mass: f32) -> (Vec3, Quat) {
        (self.0.moments * (mass / self.0.volume), self.0.frame)
    }

    /// The hull scaled per axis (its points scaled, the hull rebuilt).
    pub fn scaled(&self, scale: Vec3) -> Option<Self> {
        let points: Vec<Vec3> = self.points().iter().map(|p| *p * scale).collect();
        Self::from_points(&points)
    }

    pub(crate) fn polyhedron(&self) -> &ConvexPolyhedron {
        &self.0.poly
    }
}

/// A triangle mesh for static and kinematic bodies: a level, a ramp, a bowl. Triangles
/// face outward by counter-clockwise winding; contacts ignore the mesh's internal edges
/// (no bumps where a ball rolls from one triangle to the next).
#[derive(Clone, Reflect)]
#[reflect(opaque)]
pub struct TriMeshShape(Arc<TriMesh>);

impl TriMeshShape {
    /// A mesh of `vertices` (m, local frame) and triangles (indices into them). Fails on
    /// no triangles, an index out of range or a vertex that is not finite.
    pub fn new(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, String> {
        if vertices.iter().any(|v| !v.is_finite()) {
            return Err("a vertex is not finite".into());
        }
        let n = vertices.len() as u32;
        if let Some(t) = triangles.iter().find(|t| t.iter().any(|&i| i >= n)) {
            return Err(format!("triangle {t:?} indexes past the {n} vertices"));
        }
        let mut mesh = TriMesh::new(vertices, triangles).map_err(|e| format!("{e:?}"))?;
        // Merging duplicate vertices gives the topology internal-edge fixing needs; a
        // mesh without it (a soup of loose triangles) still collides, with its bumps.
        let _ = mesh.set_flags(TriMeshFlags::FIX_INTERNAL_EDGES);
        Ok(Self(Arc::new(mesh)))
    }

    /// The mesh, scaled per axis.
    pub fn scaled(&self, scale: Vec3) -> Self {
        Self(Arc::new((*self.0).clone().scaled(scale)))
    }

    pub(crate) fn mesh(&self) -> &TriMesh {
        &self.0
    }
}

/// A heightfield for static and kinematic bodies: terrain over a grid in local X/Z.
#[derive(Clone, Reflect)]
#[reflect(opaque)]
pub struct HeightFieldShape(Arc<HeightField>);

impl HeightFieldShape {
    /// Heights (m, along local Y) on a grid of `heights.len()` rows along local X by
    /// `heights[0].len()` columns along local Z, spread evenly over `size.x` × `size.y`
    /// metres centred on the origin. Needs at least 2 × 2 heights, all rows as long,
    /// every height finite.
    pub fn new(heights: &[Vec<f32>], size: Vec2) -> Result<Self, String> {
        let rows = heights.len();
        let cols = heights.first().map_or(0, Vec::len);
        if rows < 2 || cols < 2 || heights.iter().any(|r| r.len() != cols) {
            return Err(format!(
                "needs at least 2 × 2 heights in equal rows ({rows} rows)"
            ));
        }
        if heights.iter().flatten().any(|h| !h.is_finite()) {
            return Err("a height is not finite".into());
        }
        if !(size.is_finite() && size.min_element() > 0.0) {
            return Err(format!("size {size}"));
        }
        // Parry's rows run along z and its columns along x, stored column-major: its
        // (i, j) at index i + j·nrows is our heights[j][i].
        let mut data = Vec::with_capacity(rows * cols);
        for row in heights {
            data.extend_from_slice(row);
        }
        let grid = Array2::new(cols, rows, data);
        let scale = Vec3::new(size.x, 1.0, size.y);
        let field = HeightField::with_flags(grid, scale, HeightFieldFlags::FIX_INTERNAL_EDGES);
        Ok(Self(Arc::new(field)))
    }

    /// The field, scaled per axis.
    pub fn scaled(&self, scale: Vec3) -> Self {
        Self(Arc::new((*self.0).clone().scaled(scale)))
    }

    pub(crate) fn field(&self) -> &HeightField {
        &self.0
    }
}

macro_rules! by_identity {
    ($($t:ident: $what:literal),*) => {$(
        impl PartialEq for $t {
            /// The same shape data (clones of one collider are equal).
            fn eq(&self, other: &Self) -> bool {
                Arc::ptr_eq(&self.0, &other.0)
            }
        }
    )*};
}
by_identity!(ConvexHull: "hull", TriMeshShape: "mesh", HeightFieldShape: "field");

impl fmt::Debug for ConvexHull {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "ConvexHull({} points, {:.4} m³)",
            self.points().len(),
            self.volume()
        )
    }
}

impl fmt::Debug for TriMeshShape {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "TriMesh({} triangles)", self.0.indices().len())
    }
}

impl fmt::Debug for HeightFieldShape {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "HeightField({} × {})", self.0.ncols(), self.0.nrows())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cube_hull_weighs_and_turns_like_the_box() {
        let corners: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) - 0.5)
            .collect();
        let hull = ConvexHull::from_points(&corners).unwrap();
        assert!((hull.volume() - 1.0).abs() < 1e-5);
        assert!(hull.center_of_mass().length() < 1e-6);
        // A unit cube of 6 kg: I = m(1 + 1)/12 = 1 about every axis.
        let (moments, _) = hull.principal_inertia(6.0);
        assert!(moments.abs_diff_eq(Vec3::ONE, 1e-4), "{moments}");
        // Flat points span no volume.
        let flat: Vec<Vec3> = corners.iter().map(|p| p.with_y(0.0)).collect();
        assert!(ConvexHull::from_points(&flat).is_none());
    }

    #[test]
    fn a_heightfield_rejects_ragged_rows() {
        assert!(HeightFieldShape::new(&[vec![0.0, 1.0], vec![0.0]], Vec2::ONE).is_err());
        assert!(HeightFieldShape::new(&[vec![0.0, 1.0]], Vec2::ONE).is_err());
        assert!(HeightFieldShape::new(&[vec![0.0; 3], vec![f32::NAN; 3]], Vec2::ONE).is_err());
        assert!(HeightFieldShape::new(&vec![vec![0.0; 3]; 4], Vec2::new(4.0, 3.0)).is_ok());
        assert!(TriMeshShape::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]).is_err());
    }
}
