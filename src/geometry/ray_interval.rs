//! Where a line crosses a capsule, cylinder or cone, in closed form: the entry and exit
//! parameters with the outward normals there. Parry casts rays on these shapes by GJK,
//! which stops at its tolerance: 0.35 mm short of a capsule 8.7 m away, measured; the
//! quadratic, solved in f64, is exact to f32 rounding (even at a cone's tip, a double
//! root). Local frame (axis along Y), unit direction.

use bevy::math::DVec3;
use bevy::prelude::*;

/// An entry or exit: the line parameter and the outward normal there (f64 inside).
type Cross = (f64, DVec3);

/// An entry or exit: the line parameter and the outward normal there.
pub(crate) type Crossing = (f32, Vec3);

/// The stretch of the line `o + t·d` inside the shape, or `None` if it misses.
pub(crate) fn interval(
    shape: &crate::collider::Shape,
    o: Vec3,
    d: Vec3,
) -> Option<(Crossing, Crossing)> {
    use crate::collider::Shape;
    let (o, d) = (o.as_dvec3(), d.as_dvec3());
    let out = |((t0, n0), (t1, n1)): (Cross, Cross)| {
        ((t0 as f32, n0.as_vec3()), (t1 as f32, n1.as_vec3()))
    };
    let f = |x: f32| x as f64;
    match *shape {
        Shape::Capsule {
            radius,
            half_height,
        } => capsule(f(radius), f(half_height), o, d).map(out),
        Shape::Cylinder {
            radius,
            half_height,
        } => cylinder(f(radius), f(half_height), o, d).map(out),
        Shape::Cone {
            radius,
            half_height,
        } => cone(f(radius), f(half_height), o, d).map(out),
        _ => None,
    }
}

/// The roots of a·t² + b·t + c = 0, smaller first (`None` when there are none).
fn roots(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 || a == 0.0 {
        return None;
    }
    // The form that avoids cancelling b against the root.
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (t0, t1) = (q / a, if q != 0.0 { c / q } else { -b / (2.0 * a) });
    Some((t0.min(t1), t0.max(t1)))
}

/// The two crossings of the slab |y| ≤ h, or the whole line when parallel inside it.
fn slab(h: f64, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    if d.y == 0.0 {
        return (o.y.abs() <= h).then_some((
            (f64::NEG_INFINITY, DVec3::ZERO),
            (f64::INFINITY, DVec3::ZERO),
        ));
    }
    let (ta, tb) = ((-h - o.y) / d.y, (h - o.y) / d.y);
    // Entering through the bottom face going up, or the top face going down.
    Some(if d.y > 0.0 {
        ((ta, DVec3::NEG_Y), (tb, DVec3::Y))
    } else {
        ((tb, DVec3::Y), (ta, DVec3::NEG_Y))
    })
}

/// The crossings of the infinite cylinder x² + z² ≤ r².
fn tube(r: f64, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    let a = d.x * d.x + d.z * d.z;
    let c = o.x * o.x + o.z * o.z - r * r;
    let radial = |t: f64| {
        let p = o + d * t;
        DVec3::new(p.x, 0.0, p.z).normalize_or_zero()
    };
    if a == 0.0 {
        // Along the axis: inside all the way or never.
        return (c <= 0.0).then_some((
            (f64::NEG_INFINITY, DVec3::ZERO),
            (f64::INFINITY, DVec3::ZERO),
        ));
    }
    let (t0, t1) = roots(a, 2.0 * (o.x * d.x + o.z * d.z), c)?;
    Some(((t0, radial(t0)), (t1, radial(t1))))
}

/// The crossings of a ball of radius `r` at `centre`.
fn ball(r: f64, centre: DVec3, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    let oc = o - centre;
    let (t0, t1) = roots(
        d.length_squared(),
        2.0 * oc.dot(d),
        oc.length_squared() - r * r,
    )?;
    let normal = |t: f64| (oc + d * t).normalize_or_zero();
    Some(((t0, normal(t0)), (t1, normal(t1))))
}

/// The overlap of two stretches (entry the later, exit the earlier).
fn both(a: (Cross, Cross), b: (Cross, Cross)) -> Option<(Cross, Cross)> {
    let enter = if a.0.0 >= b.0.0 { a.0 } else { b.0 };
    let exit = if a.1.0 <= b.1.0 { a.1 } else { b.1 };
    (enter.0 <= exit.0).then_some((enter, exit))
}

fn cylinder(r: f64, h: f64, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    both(slab(h, o, d)?, tube(r, o, d)?)
}

/// A capsule is convex and the union of its inner cylinder and two end balls, so along
/// a line it is the span of their stretches.
fn capsule(r: f64, h: f64, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    let pieces = [
        cylinder(r, h, o, d),
        ball(r, DVec3::Y * h, o, d),
        ball(r, DVec3::NEG_Y * h, o, d),
    ];
    pieces.into_iter().flatten().reduce(|a, b| {
        let enter = if a.0.0 <= b.0.0 { a.0 } else { b.0 };
        let exit = if a.1.0 >= b.1.0 { a.1 } else { b.1 };
        (enter, exit)
    })
}

/// A cone with its tip at y = h and its base of radius r at y = −h: inside the slab,
/// x² + z² ≤ k²(h − y)² with k = r / 2h. That quadric is a double cone; the slab cuts
/// off the upper one but for its tip.
fn cone(r: f64, h: f64, o: DVec3, d: DVec3) -> Option<(Cross, Cross)> {
    let k2 = (r / (2.0 * h)).powi(2);
    let w = h - o.y;
    let a = d.x * d.x + d.z * d.z - k2 * d.y * d.y;
    let b = 2.0 * (o.x * d.x + o.z * d.z + k2 * w * d.y);
    let c = o.x * o.x + o.z * o.z - k2 * w * w;
    let normal = |t: f64| {
        let p = o + d * t;
        DVec3::new(p.x, k2 * (h - p.y), p.z).normalize_or(DVec3::Y)
    };
    let slab = slab(h, o, d)?;
    let inf = |n| (f64::INFINITY, n);
    let neg_inf = |n| (f64::NEG_INFINITY, n);
    // The stretches where the quadric is ≤ 0: one between the roots (a > 0), or two
    // outside them (a < 0), or one half-line (a = 0).
    let stretches: [Option<(Cross, Cross)>; 2] = if a > 0.0 {
        let (t0, t1) = roots(a, b, c)?;
        [Some(((t0, normal(t0)), (t1, normal(t1)))), None]
    } else if a < 0.0 {
        match roots(a, b, c) {
            Some((t0, t1)) => [
                Some((neg_inf(DVec3::ZERO), (t0, normal(t0)))),
                Some(((t1, normal(t1)), inf(DVec3::ZERO))),
            ],
            // Never crossing: inside everywhere (c ≤ 0) or nowhere.
            None if c <= 0.0 => [Some((neg_inf(DVec3::ZERO), inf(DVec3::ZERO))), None],
            None => return None,
        }
    } else if b != 0.0 {
        let t = -c / b;
        [
            Some(if b > 0.0 {
                (neg_inf(DVec3::ZERO), (t, normal(t)))
            } else {
                ((t, normal(t)), inf(DVec3::ZERO))
            }),
            None,
        ]
    } else {
        return None;
    };
    // Within the slab only the lower cone is left (the upper meets it at the tip): the
    // longest stretch that overlaps the slab.
    stretches
        .into_iter()
        .flatten()
        .filter_map(|s| both(slab, s))
        .max_by(|x, y| (x.1.0 - x.0.0).total_cmp(&(y.1.0 - y.0.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Shape;

    fn run(shape: &Shape, o: Vec3, d: Vec3) -> Option<(Crossing, Crossing)> {
        interval(shape, o, d)
    }

    #[test]
    fn a_line_through_the_cone_meets_its_side_and_base() {
        let cone = Shape::Cone {
            radius: 1.0,
            half_height: 1.0,
        };
        // Cone r = 1, h = 1 (height 2): along x at y = 0 the radius is 0.5.
        let ((t0, n0), (t1, n1)) = run(&cone, Vec3::new(-5.0, 0.0, 0.0), Vec3::X).unwrap();
        assert!(
            (t0 - 4.5).abs() < 1e-6 && (t1 - 5.5).abs() < 1e-6,
            "{t0} {t1}"
        );
        // The side leans in by atan(r/2h): its normal is (−2, 1, 0)/√5 on the −x side.
        assert!(
            n0.abs_diff_eq(Vec3::new(-2.0, 1.0, 0.0) / 5f32.sqrt(), 1e-6),
            "{n0}"
        );
        assert!(
            n1.abs_diff_eq(Vec3::new(2.0, 1.0, 0.0) / 5f32.sqrt(), 1e-6),
            "{n1}"
        );
        // Straight up through the base, out at the tip.
        let ((t0, n0), (t1, _)) = run(&cone, Vec3::new(0.0, -5.0, 0.0), Vec3::Y).unwrap();
        assert!(
            (t0 - 4.0).abs() < 1e-6 && (t1 - 6.0).abs() < 1e-5,
            "{t0} {t1}"
        );
        assert_eq!(n0, Vec3::NEG_Y);
        // Above the tip, beside it: a miss (the upper cone does not count).
        assert!(run(&cone, Vec3::new(-5.0, 1.5, 0.0), Vec3::X).is_none());
    }

    #[test]
    fn a_capsule_is_its_cylinder_and_its_caps() {
        let capsule = Shape::Capsule {
            radius: 0.5,
            half_height: 1.0,
        };
        let ((t, n), _) = run(&capsule, Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y).unwrap();
        assert!((t - 3.5).abs() < 1e-6 && n == Vec3::Y, "{t} {n}");
        let ((t, n), (t1, _)) = run(&capsule, Vec3::new(-5.0, 0.3, 0.0), Vec3::X).unwrap();
        assert!(
            (t - 4.5).abs() < 1e-6 && n.abs_diff_eq(Vec3::NEG_X, 1e-6) && (t1 - 5.5).abs() < 1e-6
        );
        assert!(run(&capsule, Vec3::new(-5.0, 0.0, 0.6), Vec3::X).is_none());
    }
}
