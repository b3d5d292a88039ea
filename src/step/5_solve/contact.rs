//! Contact constraints, one per manifold: a soft non-penetration row per point, then
//! friction at one anchor (a two-row disc and a twist row, see [`FrictionAnchor`]). Plain functions over the solver-body and constraint
//! slices; each constraint loads its two bodies once and stores them once.

use bevy::prelude::*;

use super::push_out::PushOutShares;
use super::stiffness::{contact_softness, load_ratio, pair_size};
use crate::collider::Shape;
use crate::math::lanes::three_operand_copy;
use crate::world::{
    Anchoring, AngularRow, BodyState, COUPLINGS, ColliderEntry, ConstraintPoint, ContactConstraint,
    ContactKey, ContactParams, FrictionAnchor, MAX_POINTS, Manifold, NO_ROLL, RollingArms, STATIC,
    SolverBody, body, is_isotropic, normal_couplings, prefetch, row_velocity,
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
pub(super) fn mass_of(k: f32) -> f32 {
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

/// The friction rows of anchors `ra`, `rb` (the points' centre from each body's centre)
/// and the twist row about `normal` (a manifold of one point has none: `points` 1), with
/// no impulse yet.
pub(super) fn friction_anchor(
    a: &SolverBody,
    b: &SolverBody,
    (ra, rb): (Vec3, Vec3),
    c: &ContactConstraint,
    points: usize,
) -> FrictionAnchor {
    let tangent_rows = [
        AngularRow::new(a, b, ra, rb, c.tangent1),
        AngularRow::new(a, b, ra, rb, c.tangent2),
    ];
    let (twist_ia, twist_ib) = (a.inv_inertia * c.normal, b.inv_inertia * c.normal);
    let spin = c.spin;
    let k = |on: bool, i: Vec3| if on { c.normal.dot(i) } else { 0.0 };
    FrictionAnchor {
        ra,
        rb,
        tangent_rows,
        tangent_mass: isotropic_tangent_mass(a.inv_mass + b.inv_mass, &tangent_rows, spin),
        tangent_impulse: Vec2::ZERO,
        twist_ia,
        twist_ib,
        twist_mass: if points > 1 {
            mass_of(k(spin[0], twist_ia) + k(spin[1], twist_ib))
        } else {
            0.0
        },
        twist_impulse: 0.0,
    }
}

/// The distance of `d` from the normal's line through the anchor: a point's lever arm
/// against twist, m.
fn plane_distance(d: Vec3, normal: Vec3) -> f32 {
    (d - normal * normal.dot(d)).length()
}

/// What [`prepare_constraints`] found out about the step's constraints while building
/// them, so that no later pass reads the 648-byte constraints for a flag. (Measured on
/// the 5,050-cube pyramid: inside the noise; it is less work, not a visible win.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    /// The largest load ratio r of any contact (see [`contact_softness`]; an impact
    /// between like masses counts only the load that stays, see [`SQUEEZE_RATIO`]): it
    /// sets how many solve passes the step needs.
    pub ratio: f32,
    /// The ratio that sets the relax passes: the largest mass ratio of any pair of
    /// moving bodies (heavier over lighter), or the load ratio of a contact that bounces.
    pub relax_ratio: f32,
    /// How many constraints, at the front, involve a fixed collider.
    pub fixed: usize,
    /// Some constraint's rows are refreshed every substep (`ContactConstraint::refresh`).
    pub refresh: bool,
    /// Some constraint reports its impulses (`ContactConstraint::report`).
    pub report: bool,
    /// Some constraint bounces (restitution above zero).
    pub bounce: bool,
}

/// The mass ratio (heavier over lighter, or the heaviest body pressing on a contact over
/// its lighter body) from which an impact's impulse counts as a load for the passes: the
/// ratio at which the passes' rule (`iterations_for`) asks for a second pass. Below it,
/// impacts between like masses are not counted: the spheres in a box (1 and 8 kg balls,
/// bouncing) went from 1.98 to 1.02 solve passes a substep, rain (2,000 bodies falling
/// on each other) from 2.47 to 1.60.
pub const SQUEEZE_RATIO: f32 = 10.0;

/// Manifolds from which the solver splits [`prepare_constraints`] between two threads
/// (when the compute pool has them): a helper takes about 30 µs to wake. (On the
/// 385-cube pyramid's 2,432 manifolds, splitting from 1,024 or from 4,096 measured the
/// same within the noise; on 100 pyramids' 14,500 it took 1.2-1.4 ms off the step.)
pub const PARALLEL_PREPARE_FROM: usize = 1024;

/// Builds the constraint of every manifold into `out` (one a manifold, in order), and
/// says what it found ([`Prepared`]). `overlaps` and `heaviest`: per body, as the survey
/// found them (`survey::PerBody`). With `split`, the second half is built on the compute
/// pool (another thread if it has one) while the caller builds the first; each
/// constraint depends only on its manifold, so the result is the same bits.
pub fn prepare_constraints(
    manifolds: &[Manifold],
    colliders: &[ColliderEntry],
    states: &[BodyState],
    bodies: &[SolverBody],
    stiffness: ContactParams,
    per_body: (&[u32], &[f32]),
    (out, keys): (&mut Vec<ContactConstraint>, &mut Vec<ContactKey>),
    arms: &mut Vec<RollingArms>,
    split: bool,
) -> Prepared {
    out.resize_with(manifolds.len(), ContactConstraint::default);
    keys.resize(manifolds.len(), ContactKey::default());
    arms.clear();
    let shared = (colliders, states, bodies, stiffness, per_body);
    if !split {
        return prepare_run(manifolds, 0, shared, (out, keys), arms);
    }
    let half = manifolds.len() / 2;
    let (first, second) = manifolds.split_at(half);
    let (out_first, out_second) = out.split_at_mut(half);
    let (keys_first, keys_second) = keys.split_at_mut(half);
    // (Allocates only if the second half has a rolling contact.)
    let mut second_arms = Vec::new();
    let mut found = [None, None];
    bevy::tasks::ComputeTaskPool::get().scope(|scope| {
        let [f0, f1] = &mut found;
        let arms1 = &mut second_arms;
        scope.spawn(async move {
            *f1 = Some(prepare_run(
                second,
                half,
                shared,
                (out_second, keys_second),
                arms1,
            ));
        });
        *f0 = Some(prepare_run(first, 0, shared, (out_first, keys_first), arms));
    });
    let [Some(f0), Some(f1)] = found else {
        unreachable!("both halves ran");
    };
    // The second half's rolling motions after the first's.
    if !second_arms.is_empty() {
        let offset = arms.len() as u32;
        for c in out[half..].iter_mut().filter(|c| c.anchoring.rolls()) {
            c.anchoring.roll += offset;
        }
        arms.append(&mut second_arms);
    }
    Prepared {
        ratio: f0.ratio.max(f1.ratio),
        relax_ratio: f0.relax_ratio.max(f1.relax_ratio),
        fixed: f0.fixed + if f0.fixed == half { f1.fixed } else { 0 },
        refresh: f0.refresh || f1.refresh,
        report: f0.report || f1.report,
        bounce: f0.bounce || f1.bounce,
    }
}

/// How many manifolds ahead of the one being prepared its bodies and constraint are
/// fetched (its colliders twice as far).
const PREFETCH_AHEAD: usize = 4;

/// What every constraint reads besides its manifold.
type Shared<'a> = (
    &'a [ColliderEntry],
    &'a [BodyState],
    &'a [SolverBody],
    ContactParams,
    (&'a [u32], &'a [f32]),
);

three_operand_copy! {
    /// [`prepare_constraints`] of a run of manifolds, the first of which is manifold
    /// `first`, into `out` and `keys` (as long as the run); its rolling motions pushed onto
    /// `arms`. `Prepared::fixed` counts the run's own leading fixed contacts.
    fn prepare_run / prepare_vex => prepare_any(
        manifolds: &[Manifold],
        first: usize,
        shared: Shared,
        out: (&mut [ContactConstraint], &mut [ContactKey]),
        arms: &mut Vec<RollingArms>,
    ) -> Prepared
}

#[inline(always)]
fn prepare_any(
    manifolds: &[Manifold],
    first: usize,
    (colliders, states, bodies, stiffness, (overlaps, heaviest)): Shared,
    (out, keys): (&mut [ContactConstraint], &mut [ContactKey]),
    arms: &mut Vec<RollingArms>,
) -> Prepared {
    debug_assert_eq!(manifolds.len(), out.len(), "one constraint a manifold");
    debug_assert_eq!(manifolds.len(), keys.len(), "one key a manifold");
    let count = |body: u32| {
        if body == STATIC {
            0
        } else {
            overlaps[body as usize]
        }
    };
    let anisotropic = |i: u32| i != STATIC && !is_isotropic(states[i as usize].inv_inertia);
    let shares = PushOutShares::new(stiffness.max_push_out);
    // Closing or parting slower than gravity changes speed in two steps.
    let resting_speed = 2.0 * stiffness.gravity * stiffness.dt;
    let mut found = Prepared {
        ratio: 1.0,
        relax_ratio: 1.0,
        fixed: 0,
        refresh: false,
        report: false,
        bounce: false,
    };
    for (mi, m) in manifolds.iter().enumerate() {
        // What a later manifold reads and writes, fetched ahead: its colliders (a scene's
        // colliders by index, in no order the manifolds follow), then, once they have
        // come, its bodies, and the constraint it fills.
        if let Some(next) = manifolds.get(mi + 2 * PREFETCH_AHEAD) {
            prefetch(&colliders[next.a as usize]);
            prefetch(&colliders[next.b as usize]);
        }
        if let Some(next) = manifolds.get(mi + PREFETCH_AHEAD) {
            for i in [
                colliders[next.a as usize].body,
                colliders[next.b as usize].body,
            ] {
                if i != STATIC {
                    prefetch(&states[i as usize]);
                    prefetch(&bodies[i as usize]);
                }
            }
            prefetch(&out[mi + PREFETCH_AHEAD]);
        }
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
        // The passes the contact asks for. An impact's impulse between bodies of like
        // mass is no load: a pair closing or parting fast counts only its mass ratio
        // and the heaviest body pressing on it, and a resting pair the smaller of its
        // last two steps' loads (a body struck from above passes the blow on to the
        // floor for one step). Unless that ratio is a squeeze's (`SQUEEZE_RATIO`): a
        // heavy body landing on a light one squeezes it, and the squeeze needs the
        // passes its impulse asks for (tests/regress_squeezed_box_restitution.rs).
        let (lo, hi) = (sa.inv_mass.min(sb.inv_mass), sa.inv_mass.max(sb.inv_mass));
        let mass_ratio = if lo > 0.0 { hi / lo } else { 1.0 };
        let pressing = mass_ratio.max(by[0].max(by[1]) * hi).max(1.0);
        let resting = m.normal.dot(sb.v - sa.v).abs() <= resting_speed;
        let r = if pressing >= SQUEEZE_RATIO {
            r
        } else if resting {
            // A load that stays: the smaller of the last two steps' (an impact's impulse
            // lasts one).
            let steady = load.min(m.previous_load.max(weight));
            load_ratio(&stiffness, lo, hi, steady)
        } else {
            pressing
        };
        found.ratio = found.ratio.max(r);
        let relax = if m.restitution > 0.0 { r } else { mass_ratio };
        found.relax_ratio = found.relax_ratio.max(relax);
        let arm = [
            sphere_arm(ca, spin[0], centre(ca)),
            sphere_arm(cb, spin[1], centre(cb)),
        ];
        let axis = [
            symmetry_axis(ca, spin[0], centre(ca)),
            symmetry_axis(cb, spin[1], centre(cb)),
        ];
        let c = &mut out[mi];
        *c = ContactConstraint {
            a: ca.body,
            b: cb.body,
            manifold: (first + mi) as u32,
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
                shares.get(count(ca.body), count(cb.body))
            },
            points: [ConstraintPoint::default(); MAX_POINTS],
            len: m.len,
            coupling: [0.0; COUPLINGS],
            anchor: FrictionAnchor::default(),
        };
        if (c.a == STATIC || c.b == STATIC) && found.fixed == mi {
            found.fixed += 1;
        }
        keys[mi] = ContactKey::of_sides(c, [&sa, &sb]);
        found.refresh |= c.refresh;
        found.report |= c.report;
        found.bounce |= c.restitution > 0.0;
        let linear = sa.inv_mass + sb.inv_mass;
        let mid = m.points().iter().map(|p| p.point).sum::<Vec3>() / m.len.max(1) as f32;
        for (cp, p) in c.points.iter_mut().zip(m.points()) {
            let (ra, rb) = (p.point - centre(ca), p.point - centre(cb));
            let normal_row = AngularRow::new(&sa, &sb, ra, rb, m.normal);
            *cp = ConstraintPoint {
                ra,
                rb,
                adjusted_separation: p.separation - m.normal.dot(rb - ra),
                normal_row,
                normal_mass: mass_of(linear + normal_row.inv_mass(spin)),
                normal_impulse: p.normal_impulse,
                twist_arm: plane_distance(p.point - mid, m.normal),
                max_normal_impulse: 0.0,
                relative_velocity: 0.0,
                separation: 0.0,
            };
            cp.relative_velocity = row_velocity(&sa, &sb, m.normal, &normal_row, spin);
        }
        c.coupling = normal_couplings(&c.points[..m.len], linear, spin);
        c.anchor = friction_anchor(&sa, &sb, (mid - centre(ca), mid - centre(cb)), c, m.len);
        // Last step's friction, from the shares of the points that persist.
        let tangent = m.points().iter().map(|p| p.tangent_impulse).sum::<Vec3>();
        c.anchor.tangent_impulse = Vec2::new(tangent.dot(t1), tangent.dot(t2));
        if m.len > 1 {
            c.anchor.twist_impulse = m.points().iter().map(|p| p.twist_impulse).sum();
        }
    }
    found
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
        let mut mid = [Vec3::ZERO; 2];
        for p in c.points[..c.len].iter_mut() {
            if rolls {
                // A sphere rolling about an off-centre centre of mass: its contact point
                // stays under its centre, so the lever arm turns with the centre, and
                // the rows follow it (a start-of-step arm lags the rocking and pumps it:
                // a weeble's swing grew 20 % in three periods).
                let (ra, rb) = anchoring.anchors(p, &a, &b, arms);
                p.normal_row = AngularRow::new(&a, &b, ra, rb, c.normal);
                mid[0] += ra;
                mid[1] += rb;
            }
            p.normal_row.ia = a.inv_inertia * p.normal_row.ra;
            p.normal_row.ib = b.inv_inertia * p.normal_row.rb;
            p.normal_mass = mass_of(linear + p.normal_row.inv_mass(c.spin));
        }
        c.coupling = normal_couplings(&c.points[..c.len], linear, c.spin);
        let anchor = if rolls {
            let n = c.len.max(1) as f32;
            (mid[0] / n, mid[1] / n)
        } else {
            (c.anchor.ra, c.anchor.rb)
        };
        let impulses = (c.anchor.tangent_impulse, c.anchor.twist_impulse);
        c.anchor = friction_anchor(&a, &b, anchor, c, c.len);
        (c.anchor.tangent_impulse, c.anchor.twist_impulse) = impulses;
    }
}
