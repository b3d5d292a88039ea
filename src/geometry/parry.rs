//! Pairs with a capsule, cylinder or cone: their manifold comes from parry3d's convex
//! contact-manifold query (GJK/EPA and feature clipping, or its special cases), converted
//! to ours: one normal from A to B, points midway between the surfaces, and ids built from
//! parry's feature ids so warm starting carries impulses over while the same features
//! touch. Also the mass properties of these shapes, from parry at unit density.

use std::cell::RefCell;

use bevy::prelude::*;
use parry3d::math::Pose;
use parry3d::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d::shape::{
    Ball, Capsule, Cone, Cuboid, Cylinder, FeatureId, HalfSpace, PackedFeatureId,
    Shape as ParryShape,
};

use super::Posed;
use super::polygon::reduce;
use super::{MAX_POINTS, Manifold};
use crate::collider::Shape;

/// One of our shapes as parry's: the simple ones built on the stack (no allocation),
/// the ones made of points borrowed.
pub(crate) enum Local<'a> {
    Ball(Ball),
    Cuboid(Cuboid),
    Capsule(Capsule),
    Cylinder(Cylinder),
    Cone(Cone),
    HalfSpace(HalfSpace),
    Shared(&'a dyn ParryShape),
}

impl<'a> Local<'a> {
    /// Parry's shape for `shape`, in the same local frame (all along Y; a plane is the
    /// half-space below local +Y).
    pub(crate) fn of(shape: &'a Shape) -> Self {
        match *shape {
            Shape::ConvexHull(ref h) => Local::Shared(h.polyhedron()),
            Shape::TriMesh(ref m) => Local::Shared(m.mesh()),
            Shape::HeightField(ref f) => Local::Shared(f.field()),
            Shape::Sphere { radius } => Local::Ball(Ball::new(radius)),
            Shape::Cuboid { half_extents } => Local::Cuboid(Cuboid::new(half_extents)),
            Shape::Capsule {
                radius,
                half_height,
            } => Local::Capsule(Capsule::new_y(half_height, radius)),
            Shape::Cylinder {
                radius,
                half_height,
            } => Local::Cylinder(Cylinder {
                half_height,
                radius,
            }),
            Shape::Cone {
                radius,
                half_height,
            } => Local::Cone(Cone {
                half_height,
                radius,
            }),
            Shape::Plane { .. } => Local::HalfSpace(HalfSpace::new(Vec3::Y)),
        }
    }

    /// The shape as parry's trait object.
    pub(crate) fn shape(&self) -> &dyn ParryShape {
        match self {
            Local::Ball(s) => s,
            Local::Cuboid(s) => s,
            Local::Capsule(s) => s,
            Local::Cylinder(s) => s,
            Local::Cone(s) => s,
            Local::HalfSpace(s) => s,
            Local::Shared(s) => *s,
        }
    }
}

/// A shape's world bounding box at a pose, from parry (for the shapes made of points).
pub(crate) fn posed_aabb(shape: &Shape, pos: Vec3, rot: Quat) -> (Vec3, Vec3) {
    let aabb = Local::of(shape).shape().compute_aabb(&pose(pos, rot));
    (aabb.mins, aabb.maxs)
}

/// A pose for parry (rotations normalised: parry's inverse assumes unit quaternions).
#[inline]
pub(crate) fn pose(pos: Vec3, rot: Quat) -> Pose {
    Pose::from_parts(pos, rot.normalize())
}

/// Volume (m³) and principal moments at unit density (kg·m² per kg/m³) of a capsule,
/// cylinder or cone, about its centre of mass in its local axes (the three are symmetric
/// about Y, so the local axes are principal).
pub(crate) fn unit_mass(shape: &Shape) -> (f32, Vec3) {
    let props = Local::of(shape).shape().mass_properties(1.0);
    let m = props.reconstruct_inertia_matrix();
    (props.mass(), Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z))
}

thread_local! {
    /// The manifold parry fills, reused so a pair costs no allocation.
    static SCRATCH: RefCell<(ContactManifold<(), ()>, Vec<(Vec3, f32, u32)>)> =
        RefCell::new((ContactManifold::new(), Vec::new()));
}

/// Collides A with B through parry (B is the plane, if either is), within `margin`.
pub(crate) fn collide(a: Posed, b: Posed, margin: f32, out: &mut Manifold) {
    let (sa, sb) = (Local::of(a.shape), Local::of(b.shape));
    let (pa, pb) = (pose(a.pos, a.rot), pose(b.pos, b.rot));
    let rect = match *b.shape {
        Shape::Plane { half_extents } => half_extents,
        _ => None,
    };
    SCRATCH.with_borrow_mut(|(m, points)| {
        m.points.clear();
        let found = DefaultQueryDispatcher.contact_manifold_convex_convex(
            &pa.inv_mul(&pb),
            sa.shape(),
            sb.shape(),
            None,
            None,
            margin,
            m,
        );
        if found.is_err() || m.points.is_empty() {
            return;
        }
        let normal = (pa.rotation * m.local_n1).normalize_or_zero();
        if normal == Vec3::ZERO {
            return;
        }
        points.clear();
        for (k, c) in m.points.iter().enumerate() {
            // Clipped points are not filtered by the prediction distance: we do. A
            // bounded plane keeps only what lies over its rectangle.
            let outside =
                rect.is_some_and(|h| c.local_p2.x.abs() > h.x || c.local_p2.z.abs() > h.y);
            if c.dist > margin || outside {
                continue;
            }
            let point = 0.5 * (pa * c.local_p1 + pb * c.local_p2);
            points.push((point, c.dist, point_id(c.fid1, c.fid2, k)));
        }
        let (keep, len) = reduce(points, normal);
        out.normal = normal;
        for &i in &keep[..len.min(MAX_POINTS)] {
            let (p, s, id) = points[i];
            out.push(p, s, id);
        }
    });
}

/// A point's id from the features that touch (shared with the mesh pairs). Parry adds one point whose features are
/// unknown (GJK's closest pair): it gets an id of its own, apart from every feature pair.
#[inline]
pub(super) fn point_id(f1: PackedFeatureId, f2: PackedFeatureId, k: usize) -> u32 {
    if f1 == PackedFeatureId::UNKNOWN && f2 == PackedFeatureId::UNKNOWN {
        return u32::MAX - k as u32;
    }
    let code = |f: PackedFeatureId| match f.unpack() {
        FeatureId::Vertex(i) => i << 2,
        FeatureId::Edge(i) => (i << 2) | 1,
        FeatureId::Face(i) => (i << 2) | 2,
        FeatureId::Unknown => 3,
    };
    code(f1).wrapping_mul(0x9E37_79B1) ^ code(f2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    fn near(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol * b.abs().max(1e-6)
    }

    #[test]
    fn mass_properties_match_the_formulas() {
        let (r, h) = (0.3f32, 0.5f32);
        // Cylinder: V = πr²·2h; I_y = V r²/2, I_x = V (3r² + (2h)²)/12.
        let (v, i) = unit_mass(&Shape::Cylinder {
            radius: r,
            half_height: h,
        });
        let vc = PI * r * r * 2.0 * h;
        assert!(near(v, vc, 1e-5), "{v} vs {vc}");
        assert!(near(i.y, vc * r * r / 2.0, 1e-4));
        assert!(near(i.x, vc * (3.0 * r * r + 4.0 * h * h) / 12.0, 1e-4));
        assert!(near(i.z, i.x, 1e-6));
        // Capsule: the cylinder plus two hemispheres of total mass ms at the ends:
        // I_y adds ms·2r²/5; I_x adds ms (2r²/5 + h² + 3hr/4).
        let (v, i) = unit_mass(&Shape::Capsule {
            radius: r,
            half_height: h,
        });
        let ms = 4.0 / 3.0 * PI * r.powi(3);
        assert!(near(v, vc + ms, 1e-5), "{v}");
        assert!(
            near(i.y, vc * r * r / 2.0 + ms * 0.4 * r * r, 1e-4),
            "{}",
            i.y
        );
        let ix =
            vc * (3.0 * r * r + 4.0 * h * h) / 12.0 + ms * (0.4 * r * r + h * h + 0.75 * h * r);
        assert!(near(i.x, ix, 1e-4), "{} vs {ix}", i.x);
        // Cone (height H = 2h): V = πr²H/3; about its centre of mass
        // I_y = 3/10 V r², I_x = V (3r²/20 + 3H²/80).
        let (v, i) = unit_mass(&Shape::Cone {
            radius: r,
            half_height: h,
        });
        let vk = PI * r * r * 2.0 * h / 3.0;
        assert!(near(v, vk, 1e-5));
        assert!(near(i.y, 0.3 * vk * r * r, 1e-4));
        assert!(near(
            i.x,
            vk * (3.0 * r * r / 20.0 + 3.0 * 4.0 * h * h / 80.0),
            1e-4
        ));
    }

    #[test]
    fn capsule_on_a_plane_touches_along_its_side() {
        // A capsule lying along X, 1 mm into the ground: two points, normal up.
        let capsule = Shape::Capsule {
            radius: 0.25,
            half_height: 0.5,
        };
        let plane = Shape::Plane { half_extents: None };
        let a = Posed {
            shape: &capsule,
            pos: Vec3::new(0.0, 0.249, 0.0),
            rot: Quat::from_rotation_z(PI / 2.0),
        };
        let b = Posed {
            shape: &plane,
            pos: Vec3::ZERO,
            rot: Quat::IDENTITY,
        };
        let mut m = Manifold::default();
        collide(a, b, 0.02, &mut m);
        assert!(m.len >= 2, "{m:?}");
        assert!(m.normal.abs_diff_eq(Vec3::NEG_Y, 1e-5), "{}", m.normal);
        for p in m.points() {
            assert!((p.separation + 0.001).abs() < 1e-5, "{p:?}");
        }
        let xs: Vec<f32> = m.points().iter().map(|p| p.point.x).collect();
        let span = xs.iter().cloned().fold(f32::MIN, f32::max)
            - xs.iter().cloned().fold(f32::MAX, f32::min);
        assert!((span - 1.0).abs() < 1e-4, "points span the segment: {xs:?}");
    }
}
