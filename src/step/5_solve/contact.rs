//! Contact constraints, one per manifold: a soft non-penetration row per point, then a
//! two-row friction disc per point. Plain functions over the solver-body and constraint
//! slices; each constraint loads its two bodies once and stores them once.

use bevy::prelude::*;

use super::stiffness::{contact_softness, pair_size};
use crate::collider::Shape;
use crate::world::{
    Anchoring, AngularRow, BodyState, ColliderEntry, ConstraintPoint, ContactConstraint,
    ContactParams, MAX_POINTS, Manifold, NO_ROLL, RollingArms, STATIC, SolverBody, body,
    is_isotropic, row_velocity,
};

/// A turning sphere's centre from its body's centre of mass (zero when they coincide,
/// and for every other shape: their whole anchor turns).
fn sphere_arm(c: &ColliderEntry, spin: bool, centre_of_mass: Vec3) -> Vec3 {
    match c.shape {
        Shape::Sphere { .. } if spin && c.offset != Vec3::ZERO => c.pos - centre_of_mass,
        _ => Vec3::ZERO,
    }
}

/// The world axis of a turning capsule, cylinder or cone whose axis passes through its
/// body's centre of mass (zero otherwise): turning about it leaves the shape in place.
fn symmetry_axis(c: &ColliderEntry, spin: bool, centre_of_mass: Vec3) -> Vec3 {
    if !spin
        || !matches!(
            c.shape,
            Shape::Capsule { .. } | Shape::Cylinder { .. } | Shape::Cone { .. }
        )
    {
        return Vec3::ZERO;
    }
    let axis = c.rot * Vec3::Y;
    let off_axis = (c.pos - centre_of_mass).cross(axis).length();
    if off_axis <= 1e-4 * c.shape.thickness() {
        axis
    } else {
        Vec3::ZERO
    }
}

/// Whether a body has angular terms in a contact: it turns now or impulses can turn it.
fn spins(b: &SolverBody) -> bool {
    b.w != Vec3::ZERO || b.inv_inertia != Mat3::ZERO
}

/// 1/k for an inverse effective mass k, 0 when nothing can move.
fn mass_of(k: f32) -> f32 {
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// The friction rows' mass: the harmonic mean of the two tangent directions' effective
/// masses, the same in every direction. With a separate mass per row, an off-centre point
/// (a box corner) is heavier along one tangent than the other, the friction impulse is
/// then not opposite the slip, and a sliding box's point frictions fan out so their sum
/// falls short of μN (measured: 0.4% short, 1.3% on the acceleration of a box sliding
/// down a 0.25 rad ramp at μ = 0.2). A single mass keeps friction opposite the slip in
/// every direction, which is also what makes the cone round.
fn isotropic_tangent_mass(linear: f32, rows: &[AngularRow; 2], spin: [bool; 2]) -> f32 {
    let k = |row: &AngularRow| linear + row.inv_mass(spin);
    mass_of(0.5 * (k(&rows[0]) + k(&rows[1])))
}

/// Overlap at spawn: a body buried in k others is pushed out by k contacts at once. If
/// each could push at the full `max_push_out`, their pushes would add up along chains of
/// bodies (300 boxes spawned at one point flew apart at 73 m/s). So each body's push-out
/// is shared among its overlapping contacts: a contact may push at most
/// `max_push_out / k^0.6` for the larger k of its two bodies. Measured on 300 boxes at
/// one point in zero g, five different spawn orders: k^0.6 peaks at 2.1–2.7 m/s for a
/// 3 m/s limit and parts the pile in 2.9 s; √k peaked at 3.8–4.0 m/s (chains of pushes
/// still add up); 1/k was still parting it after 10 s. Resting contacts are barely
/// overlapping and push far slower than any share, so they don't notice.
pub const PUSH_OUT_SHARE_EXPONENT: f32 = 0.6;

/// The fastest push-out one contact may drive, given how many overlapping contacts each
/// of its bodies has (see [`PUSH_OUT_SHARE_EXPONENT`]).
pub fn push_out_share(max_push_out: f32, overlaps_a: u32, overlaps_b: u32) -> f32 {
    max_push_out / (overlaps_a.max(overlaps_b).max(1) as f32).powf(PUSH_OUT_SHARE_EXPONENT)
}

/// Counts, per body, the manifolds in which it overlaps another moving body (a point with
/// negative separation), into `counts` (one per body).
fn count_overlaps(
    manifolds: &[Manifold],
    colliders: &[ColliderEntry],
    n_bodies: usize,
    counts: &mut Vec<u32>,
) {
    counts.clear();
    counts.resize(n_bodies, 0);
    for m in manifolds {
        let (a, b) = (colliders[m.a as usize].body, colliders[m.b as usize].body);
        if a != STATIC && b != STATIC && m.points().iter().any(|p| p.separation < 0.0) {
            counts[a as usize] += 1;
            counts[b as usize] += 1;
        }
    }
}

/// Builds the constraint of every manifold. Returns the largest load ratio r of any
/// contact (see [`contact_softness`]), which sets how many iterations the step needs.
pub fn prepare_constraints(
    manifolds: &[Manifold],
    colliders: &[ColliderEntry],
    states: &[BodyState],
    bodies: &[SolverBody],
    stiffness: ContactParams,
    overlaps: &mut Vec<u32>,
    heaviest: &mut Vec<f32>,
    out: &mut Vec<ContactConstraint>,
    arms: &mut Vec<RollingArms>,
) -> f32 {
    out.clear();
    arms.clear();
    count_overlaps(manifolds, colliders, states.len(), overlaps);
    heaviest.clear();
    heaviest.resize(states.len(), 0.0);
    for m in manifolds {
        let [a, b] = [m.a, m.b].map(|c| colliders[c as usize].body);
        for (i, j) in [(a, b), (b, a)] {
            if i != STATIC {
                let other = mass_of(body(bodies, j).inv_mass);
                heaviest[i as usize] = heaviest[i as usize].max(other);
            }
        }
    }
    let count = |body: u32| {
        if body == STATIC {
            0
        } else {
            overlaps[body as usize]
        }
    };
    let anisotropic = |i: u32| i != STATIC && !is_isotropic(states[i as usize].inv_inertia);
    let mut max_ratio = 1.0f32;
    for (mi, m) in manifolds.iter().enumerate() {
        let (ca, cb) = (&colliders[m.a as usize], &colliders[m.b as usize]);
        let centre = |c: &ColliderEntry| {
            if c.body == STATIC {
                c.pos
            } else {
                states[c.body as usize].x0
            }
        };
        let (sa, sb) = (body(bodies, ca.body), body(bodies, cb.body));
        let (t1, t2) = m.normal.any_orthonormal_pair();
        let spin = [spins(&sa), spins(&sb)];
        // The heaviest body touching either side (or about to) presses through it from
        // the substep it lands; its impulses would show the load only a step late.
        let by = [ca.body, cb.body].map(|i| {
            if i == STATIC {
                0.0
            } else {
                heaviest[i as usize]
            }
        });
        let weight = by[0].max(by[1]) * stiffness.gravity * stiffness.h;
        let load = m
            .points()
            .iter()
            .map(|p| p.normal_impulse)
            .sum::<f32>()
            .max(weight);
        let size = pair_size(&ca.shape, &cb.shape);
        let (softness, r) =
            contact_softness(&stiffness, sa.inv_mass, sb.inv_mass, load, weight, size);
        max_ratio = max_ratio.max(r);
        let arm = [
            sphere_arm(ca, spin[0], centre(ca)),
            sphere_arm(cb, spin[1], centre(cb)),
        ];
        let axis = [
            symmetry_axis(ca, spin[0], centre(ca)),
            symmetry_axis(cb, spin[1], centre(cb)),
        ];
        let mut c = ContactConstraint {
            a: ca.body,
            b: cb.body,
            manifold: mi as u32,
            normal: m.normal,
            tangent1: t1,
            tangent2: t2,
            anchoring: Anchoring {
                turn: [
                    spin[0] && !matches!(ca.shape, Shape::Sphere { .. }),
                    spin[1] && !matches!(cb.shape, Shape::Sphere { .. }),
                ],
                roll: if arm == [Vec3::ZERO; 2] && axis == [Vec3::ZERO; 2] {
                    NO_ROLL
                } else {
                    arms.push(RollingArms { arm, axis });
                    arms.len() as u32 - 1
                },
            },
            spin,
            refresh: (spin[0] && (anisotropic(ca.body) || arm[0] != Vec3::ZERO))
                || (spin[1] && (anisotropic(cb.body) || arm[1] != Vec3::ZERO)),
            report: ca.filter.events || cb.filter.events,
            friction: if stiffness.friction { m.friction } else { 0.0 },
            restitution: m.restitution,
            approach_gain: stiffness.gravity * stiffness.dt,
            softness,
            // A static side cannot pass a push along, so it pushes at the full limit.
            max_push: if ca.body == STATIC || cb.body == STATIC {
                stiffness.max_push_out
            } else {
                push_out_share(stiffness.max_push_out, count(ca.body), count(cb.body))
            },
            points: [ConstraintPoint::default(); MAX_POINTS],
            len: m.len,
        };
        let linear = sa.inv_mass + sb.inv_mass;
        for (cp, p) in c.points.iter_mut().zip(m.points()) {
            let (ra, rb) = (p.point - centre(ca), p.point - centre(cb));
            let normal_row = AngularRow::new(&sa, &sb, ra, rb, m.normal);
            // Two calls, not `[t1, t2].map(..)`: the array map's closure was not inlined
            // and made this loop 87 % slower (perf, 385-cube pyramid).
            let tangent_rows = [
                AngularRow::new(&sa, &sb, ra, rb, t1),
                AngularRow::new(&sa, &sb, ra, rb, t2),
            ];
            *cp = ConstraintPoint {
                ra,
                rb,
                adjusted_separation: p.separation - m.normal.dot(rb - ra),
                normal_row,
                tangent_rows,
                normal_mass: mass_of(linear + normal_row.inv_mass(spin)),
                tangent_mass: isotropic_tangent_mass(linear, &tangent_rows, spin),
                normal_impulse: p.normal_impulse,
                tangent_impulse: Vec2::new(p.tangent_impulse.dot(t1), p.tangent_impulse.dot(t2)),
                max_normal_impulse: 0.0,
                relative_velocity: 0.0,
            };
            cp.relative_velocity = row_velocity(&sa, &sb, m.normal, &normal_row, spin);
        }
        out.push(c);
    }
    max_ratio
}

/// Re-derives the inverse-inertia images of the rows and the point masses of constraints
/// with a turning anisotropic body, from the bodies' current world inertia.
///
/// A thin rod's inertia about its long axis is thousands of times smaller than across
/// it. Prepared once per step, the rows keep the start-of-step world inertia while the
/// rod turns a tenth of a radian: an impulse then spins it about where its long axis
/// *was*, which is mostly across the rod now, and the step hands it hundreds of joules
/// (`tests/regress_turning_rod_inertia.rs`). The anchors stay at the start of the step:
/// impulses along any fixed row with the true mass matrix cannot add energy.
pub fn refresh_rows(
    bodies: &[SolverBody],
    constraints: &mut [ContactConstraint],
    arms: &[RollingArms],
) {
    for c in constraints.iter_mut().filter(|c| c.refresh) {
        let (a, b) = (body(bodies, c.a), body(bodies, c.b));
        let linear = a.inv_mass + b.inv_mass;
        let anchoring = c.anchoring;
        let rolls = anchoring.rolls() && arms[anchoring.roll as usize].arm != [Vec3::ZERO; 2];
        for p in c.points[..c.len].iter_mut() {
            if rolls {
                // A sphere rolling about an off-centre centre of mass: its contact point
                // stays under its centre, so the lever arm turns with the centre, and
                // the rows follow it (a start-of-step arm lags the rocking and pumps it:
                // a weeble's swing grew 20 % in three periods).
                let (ra, rb) = anchoring.anchors(p, &a, &b, arms);
                p.normal_row = AngularRow::new(&a, &b, ra, rb, c.normal);
                p.tangent_rows = [
                    AngularRow::new(&a, &b, ra, rb, c.tangent1),
                    AngularRow::new(&a, &b, ra, rb, c.tangent2),
                ];
            }
            let rows = std::iter::once(&mut p.normal_row).chain(p.tangent_rows.iter_mut());
            for row in rows {
                row.ia = a.inv_inertia * row.ra;
                row.ib = b.inv_inertia * row.rb;
            }
            p.normal_mass = mass_of(linear + p.normal_row.inv_mass(c.spin));
            p.tangent_mass = isotropic_tangent_mass(linear, &p.tangent_rows, c.spin);
        }
    }
}

/// Adds each point's accumulated impulses (what one substep applied) to its manifold's
/// totals for the step, for constraints that report them. Run after every substep but
/// the last, and once after restitution for the last (whose impulse restitution and the
/// final stop add to).
pub fn sum_impulses(constraints: &[ContactConstraint], manifolds: &mut [Manifold]) {
    for c in constraints.iter().filter(|c| c.report) {
        let m = &mut manifolds[c.manifold as usize];
        for (mp, p) in m.points_mut().iter_mut().zip(&c.points) {
            mp.total_normal_impulse += p.normal_impulse;
            mp.total_tangent_impulse +=
                c.tangent1 * p.tangent_impulse.x + c.tangent2 * p.tangent_impulse.y;
        }
    }
}
