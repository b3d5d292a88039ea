//! Exact queries against one posed shape, for the spatial queries: ray casts, shape casts,
//! point projection and overlap tests, all through parry3d. Plain functions without the
//! ECS; the search over many colliders lives in `crate::query`.
//!
//! An infinite plane is the half-space below its surface (as in contacts: a ray from
//! below starts inside it). A bounded plane is its rectangle, a surface with no inside.

use bevy::prelude::*;
use parry3d::query::{Ray, ShapeCastOptions, ShapeCastStatus};
use parry3d::shape::{Cuboid, Shape as ParryShape};

use super::parry::{Local, pose};
use super::ray_interval;
use crate::collider::Shape;

/// Parry's shape for a query on `shape` (a bounded plane as its flat rectangle).
fn query_shape(shape: &Shape) -> Local<'_> {
    match *shape {
        Shape::Plane {
            half_extents: Some(h),
        } => Local::Cuboid(Cuboid::new(Vec3::new(h.x, 0.0, h.y))),
        _ => Local::of(shape),
    }
}

/// A ray's first hit on a posed shape within `max_distance` (m, along the unit `dir`):
/// the distance and the world normal at the hit (facing the ray's origin side). With
/// `solid`, a ray that starts inside hits at distance 0; without, it hits the boundary
/// on its way out.
pub(crate) fn cast_ray(
    shape: &Shape,
    (pos, rot): (Vec3, Quat),
    origin: Vec3,
    dir: Vec3,
    max_distance: f32,
    solid: bool,
) -> Option<(f32, Vec3)> {
    if let Shape::Plane {
        half_extents: Some(h),
    } = *shape
    {
        return cast_ray_rect(h, (pos, rot), origin, dir, max_distance);
    }
    if matches!(
        shape,
        Shape::Capsule { .. } | Shape::Cylinder { .. } | Shape::Cone { .. }
    ) {
        return cast_ray_round(shape, (pos, rot), origin, dir, max_distance, solid);
    }
    let local = query_shape(shape);
    let ray = Ray::new(origin, dir);
    let hit = local
        .shape()
        .cast_ray_and_get_normal(&pose(pos, rot), &ray, max_distance, solid)?;
    // From inside a solid: distance 0, facing back along the ray.
    let normal = if hit.time_of_impact == 0.0 && solid {
        -dir
    } else {
        hit.normal
    };
    Some((hit.time_of_impact, normal))
}

/// A ray against a capsule, cylinder or cone, in closed form (see [`ray_interval`]).
fn cast_ray_round(
    shape: &Shape,
    (pos, rot): (Vec3, Quat),
    origin: Vec3,
    dir: Vec3,
    max_distance: f32,
    solid: bool,
) -> Option<(f32, Vec3)> {
    let rot = rot.normalize();
    let inv = rot.inverse();
    let ((t0, n0), (t1, n1)) = ray_interval::interval(shape, inv * (origin - pos), inv * dir)?;
    if t1 < 0.0 {
        return None;
    }
    let (t, normal) = if t0 >= 0.0 {
        (t0, rot * n0)
    } else if solid {
        (0.0, -dir)
    } else {
        // From inside, out through the boundary: its normal turned to face the origin.
        (t1, -(rot * n1))
    };
    (t <= max_distance).then_some((t, normal))
}

/// A ray against a bounded plane's rectangle, hit from either side (it has no inside).
fn cast_ray_rect(
    h: Vec2,
    (pos, rot): (Vec3, Quat),
    origin: Vec3,
    dir: Vec3,
    max_distance: f32,
) -> Option<(f32, Vec3)> {
    let inv = rot.normalize().inverse();
    let (o, d) = (inv * (origin - pos), inv * dir);
    if d.y == 0.0 {
        return None;
    }
    let t = -o.y / d.y;
    let at = o + d * t;
    let inside = at.x.abs() <= h.x && at.z.abs() <= h.y;
    (t >= 0.0 && t <= max_distance && inside).then(|| {
        let up = rot.normalize() * Vec3::Y;
        (t, if o.y >= 0.0 { up } else { -up })
    })
}

/// Where a shape moved from `origin` along the unit `dir` first touches a posed target,
/// within `max_distance`: the distance travelled (0 if it starts touching), the point on
/// the target and the target's outward normal there, world frame.
pub(crate) fn cast_shape(
    moving: &Shape,
    (origin, rotation): (Vec3, Quat),
    dir: Vec3,
    max_distance: f32,
    target: &Shape,
    (pos, rot): (Vec3, Quat),
) -> Option<(f32, Vec3, Vec3)> {
    let (a, b) = (query_shape(moving), query_shape(target));
    let (pa, pb) = (pose(origin, rotation), pose(pos, rot));
    let options = ShapeCastOptions::with_max_time_of_impact(max_distance);
    let hit = parry3d::query::cast_shapes(&pa, dir, a.shape(), &pb, Vec3::ZERO, b.shape(), options)
        .ok()
        .flatten()?;
    if hit.status == ShapeCastStatus::Failed && !hit.time_of_impact.is_finite() {
        return None;
    }
    // Witnesses and normals come back in each shape's own frame.
    let point = pb * hit.witness2;
    let mut normal = (pb.rotation * hit.normal2).normalize_or_zero();
    if matches!(
        target,
        Shape::Plane {
            half_extents: Some(_)
        }
    ) {
        // A flat rectangle's normal is either face's: the one toward the moving shape.
        let up = pb.rotation * Vec3::Y;
        let side = (origin + dir * hit.time_of_impact - pos).dot(up);
        normal = if side >= 0.0 { up } else { -up };
    }
    Some((hit.time_of_impact, point, normal))
}

/// The point of a posed shape nearest to `point`, and whether `point` is inside. With
/// `solid`, a point inside projects onto itself; without, onto the boundary.
pub(crate) fn project_point(
    shape: &Shape,
    (pos, rot): (Vec3, Quat),
    point: Vec3,
    solid: bool,
) -> (Vec3, bool) {
    let local = query_shape(shape);
    let p = local.shape().project_point(&pose(pos, rot), point, solid);
    (p.point, p.is_inside)
}

/// Whether `point` lies inside (or on) a posed shape.
pub(crate) fn contains_point(shape: &Shape, (pos, rot): (Vec3, Quat), point: Vec3) -> bool {
    query_shape(shape)
        .shape()
        .contains_point(&pose(pos, rot), point)
}

/// Whether two posed shapes overlap (touching counts).
pub(crate) fn intersects(a: &Shape, pa: (Vec3, Quat), b: &Shape, pb: (Vec3, Quat)) -> bool {
    let (sa, sb) = (query_shape(a), query_shape(b));
    let (ga, gb): (&dyn ParryShape, &dyn ParryShape) = (sa.shape(), sb.shape());
    parry3d::query::intersection_test(&pose(pa.0, pa.1), ga, &pose(pb.0, pb.1), gb).unwrap_or(false)
}

/// The entry and exit distances of a ray (unit or not: in multiples of `dir`) through
/// the box [lo, hi], clipped to [0, max]; `None` when it misses. The slab test: every
/// candidate box is tested with it before the exact cast.
#[inline]
pub(crate) fn ray_aabb(
    origin: Vec3,
    dir: Vec3,
    max: f32,
    lo: Vec3,
    hi: Vec3,
) -> Option<(f32, f32)> {
    let inv = dir.recip();
    let (t0, t1) = ((lo - origin) * inv, (hi - origin) * inv);
    // A zero direction component gives ±inf (or NaN on the slab's plane: treated as in).
    let near = t0.min(t1);
    let far = t0.max(t1);
    let enter = [near.x, near.y, near.z, 0.0]
        .into_iter()
        .filter(|t| !t.is_nan())
        .fold(f32::NEG_INFINITY, f32::max);
    let exit = [far.x, far.y, far.z, max]
        .into_iter()
        .filter(|t| !t.is_nan())
        .fold(f32::INFINITY, f32::min);
    (enter <= exit).then_some((enter, exit))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_4, FRAC_PI_6};

    const AT: (Vec3, Quat) = (Vec3::new(1.0, 2.0, 3.0), Quat::IDENTITY);

    fn close(a: Vec3, b: Vec3) -> bool {
        a.abs_diff_eq(b, 1e-5)
    }

    /// Each shape hit head-on along −Y from above, and at 30° off the vertical: the
    /// distance to the surface is known in closed form.
    #[test]
    fn rays_hit_each_shape_at_its_surface() {
        let (r, h) = (0.5f32, 0.75f32);
        let cases = [
            (Shape::Sphere { radius: r }, r),
            (
                Shape::Cuboid {
                    half_extents: Vec3::new(0.4, h, 0.3),
                },
                h,
            ),
            (
                Shape::Capsule {
                    radius: r,
                    half_height: h,
                },
                h + r,
            ),
            (
                Shape::Cylinder {
                    radius: r,
                    half_height: h,
                },
                h,
            ),
            (
                Shape::Cone {
                    radius: r,
                    half_height: h,
                },
                h,
            ),
            (Shape::Plane { half_extents: None }, 0.0),
            (
                Shape::Plane {
                    half_extents: Some(Vec2::splat(2.0)),
                },
                0.0,
            ),
        ];
        for (shape, top) in cases {
            let origin = AT.0 + Vec3::Y * 10.0;
            let (d, n) = cast_ray(&shape, AT, origin, Vec3::NEG_Y, 100.0, true).unwrap();
            assert!((d - (10.0 - top)).abs() < 1e-5, "{shape:?}: {d}");
            assert!(close(n, Vec3::Y), "{shape:?}: {n}");
        }
        // A box's top face from 30° off the vertical: distance (10 − h)/cos 30°.
        let cuboid = Shape::Cuboid {
            half_extents: Vec3::splat(h),
        };
        let dir = Vec3::new(FRAC_PI_6.sin(), -FRAC_PI_6.cos(), 0.0);
        // Aimed at the face's centre: it starts (10 − h)·tan 30° to the side.
        let origin = AT.0 + Vec3::new(-(10.0 - h) * FRAC_PI_6.tan(), 10.0, 0.0);
        let (d, n) = cast_ray(&cuboid, AT, origin, dir, 100.0, true).unwrap();
        assert!((d - (10.0 - h) / FRAC_PI_6.cos()).abs() < 1e-5, "{d}");
        assert!(close(n, Vec3::Y));
        // A sphere grazed off-centre: the chord's near end at distance 10 − √(r² − b²).
        let b = 0.3f32;
        let sphere = Shape::Sphere { radius: r };
        let (d, n) = cast_ray(
            &sphere,
            AT,
            AT.0 + Vec3::new(b, 10.0, 0.0),
            Vec3::NEG_Y,
            100.0,
            true,
        )
        .unwrap();
        let y = (r * r - b * b).sqrt();
        assert!((d - (10.0 - y)).abs() < 1e-5, "{d}");
        assert!(close(n, Vec3::new(b, y, 0.0) / r), "{n}");
    }

    #[test]
    fn a_turned_box_is_hit_on_its_turned_face() {
        // A unit cube turned 45° about z: a ray along −x meets its edge at √2·½.
        let rot = Quat::from_rotation_z(FRAC_PI_4);
        let cube = Shape::Cuboid {
            half_extents: Vec3::splat(0.5),
        };
        let (d, _) = cast_ray(
            &cube,
            (Vec3::ZERO, rot),
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::NEG_X,
            10.0,
            true,
        )
        .unwrap();
        assert!((d - (5.0 - 0.5 * 2f32.sqrt())).abs() < 1e-5, "{d}");
        // Just above the edge the ray meets the upper right face, normal (1, 1, 0)/√2.
        let (_, n) = cast_ray(
            &cube,
            (Vec3::ZERO, rot),
            Vec3::new(5.0, 0.1, 0.0),
            Vec3::NEG_X,
            10.0,
            true,
        )
        .unwrap();
        assert!(close(n, Vec3::new(1.0, 1.0, 0.0).normalize()), "{n}");
    }

    #[test]
    fn solid_rays_start_inside_and_hollow_ones_leave() {
        let sphere = Shape::Sphere { radius: 1.0 };
        let (d, _) = cast_ray(&sphere, AT, AT.0, Vec3::X, 10.0, true).unwrap();
        assert_eq!(d, 0.0);
        let (d, _) = cast_ray(&sphere, AT, AT.0, Vec3::X, 10.0, false).unwrap();
        assert!((d - 1.0).abs() < 1e-5);
        // Out of reach, and pointing away.
        assert!(cast_ray(&sphere, AT, AT.0 + Vec3::X * 5.0, Vec3::X, 10.0, true).is_none());
        assert!(cast_ray(&sphere, AT, AT.0 + Vec3::X * 5.0, Vec3::NEG_X, 3.9, true).is_none());
        // A bounded plane is missed beside its rectangle; an infinite one is not.
        let tile = Shape::Plane {
            half_extents: Some(Vec2::ONE),
        };
        let beside = Vec3::new(1.5, 5.0, 0.0);
        assert!(
            cast_ray(
                &tile,
                (Vec3::ZERO, Quat::IDENTITY),
                beside,
                Vec3::NEG_Y,
                10.0,
                true
            )
            .is_none()
        );
        let floor = Shape::Plane { half_extents: None };
        assert!(
            cast_ray(
                &floor,
                (Vec3::ZERO, Quat::IDENTITY),
                beside,
                Vec3::NEG_Y,
                10.0,
                true
            )
            .is_some()
        );
    }

    #[test]
    fn a_cast_ball_stops_one_radius_short_of_a_wall() {
        let ball = Shape::Sphere { radius: 0.25 };
        let wall = Shape::Cuboid {
            half_extents: Vec3::new(0.5, 2.0, 2.0),
        };
        let (d, point, normal) = cast_shape(
            &ball,
            (Vec3::new(-5.0, 0.3, 0.0), Quat::IDENTITY),
            Vec3::X,
            20.0,
            &wall,
            (Vec3::ZERO, Quat::IDENTITY),
        )
        .unwrap();
        assert!((d - (5.0 - 0.5 - 0.25)).abs() < 1e-4, "{d}");
        assert!(close(normal, Vec3::NEG_X), "{normal}");
        assert!(
            point.abs_diff_eq(Vec3::new(-0.5, 0.3, 0.0), 1e-4),
            "{point}"
        );
        // Too short a cast misses.
        assert!(
            cast_shape(
                &ball,
                (Vec3::new(-5.0, 0.3, 0.0), Quat::IDENTITY),
                Vec3::X,
                4.0,
                &wall,
                (Vec3::ZERO, Quat::IDENTITY)
            )
            .is_none()
        );
    }

    #[test]
    fn points_project_onto_the_nearest_surface() {
        let cube = Shape::Cuboid {
            half_extents: Vec3::splat(1.0),
        };
        let (p, inside) = project_point(&cube, AT, AT.0 + Vec3::new(3.0, 0.5, 0.0), true);
        assert!(!inside && close(p, AT.0 + Vec3::new(1.0, 0.5, 0.0)));
        let (p, inside) = project_point(&cube, AT, AT.0 + Vec3::new(0.8, 0.0, 0.0), false);
        assert!(inside && close(p, AT.0 + Vec3::X));
        assert!(contains_point(&cube, AT, AT.0 + Vec3::splat(0.9)));
        assert!(!contains_point(&cube, AT, AT.0 + Vec3::splat(1.1)));
        let ball = Shape::Sphere { radius: 0.5 };
        assert!(intersects(
            &cube,
            AT,
            &ball,
            (AT.0 + Vec3::X * 1.45, Quat::IDENTITY)
        ));
        assert!(!intersects(
            &cube,
            AT,
            &ball,
            (AT.0 + Vec3::X * 1.55, Quat::IDENTITY)
        ));
    }

    #[test]
    fn the_slab_test_clips_to_the_box() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let (a, b) = ray_aabb(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, 10.0, lo, hi).unwrap();
        assert!((a - 2.0).abs() < 1e-6 && (b - 4.0).abs() < 1e-6);
        assert!(ray_aabb(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, 1.5, lo, hi).is_none());
        assert!(ray_aabb(Vec3::new(-3.0, 2.0, 0.0), Vec3::X, 10.0, lo, hi).is_none());
        // Along a face's plane (0 · inf = NaN) still counts as inside that slab.
        assert!(ray_aabb(Vec3::new(-3.0, 1.0, 0.0), Vec3::X, 10.0, lo, hi).is_some());
    }
}
