//! Contact constraints, one per manifold: a soft non-penetration row per point, then
//! friction at one anchor (a two-row disc and a twist row, see [`FrictionAnchor`]). Plain functions over the solver-body and constraint
//! slices; each constraint loads its two bodies once and stores them once.

use bevy::prelude::*;

use super::contact_load::{Load, LoadLanes};
use super::push_out::PushOutShares;
use super::stiffness::pair_size;
use crate::collider::Shape;
use crate::math::Softness;
use crate::world::{
    Anchoring, AngularRow, BodyState, BodyView, COUPLINGS, ColliderEntry, ConstraintPoint,
    ContactConstraint, ContactKey, ContactParams, FrictionAnchor, MAX_POINTS, Manifold, NO_ROLL,
    RollingArms, STATIC, SolverBody, body, is_isotropic, normal_couplings, prefetch, row_velocity,
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

/// What [`prepare_contacts`](super::prepare_contacts::prepare_contacts) found out about
/// the step's contacts while building them, so that no later pass reads the 688-byte
/// constraints for a flag. (Measured on the 5,050-cube pyramid: inside the noise; it is
/// less work, not a visible win.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    /// The largest load ratio r of any contact (see [`contact_softness`]; an impact
    /// between like masses counts only the load that stays, see
    /// [`SQUEEZE_RATIO`](super::contact_load::SQUEEZE_RATIO)): it sets how many solve
    /// passes the step needs.
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

/// What building a contact reads besides its manifold: the scene's colliders, bodies and
/// solver bodies, the contact settings, and per body the survey's counts of overlaps and
/// heaviest body pressing on it (`survey::PerBody`). Each contact depends only on its
/// manifold and these, so contacts can be built in any order, on any thread.
pub(super) struct Builder<'a> {
    colliders: &'a [ColliderEntry],
    states: &'a [BodyState],
    pub(super) bodies: &'a [SolverBody],
    pub(super) stiffness: ContactParams,
    overlaps: &'a [u32],
    heaviest: &'a [f32],
    shares: PushOutShares,
    /// Closing or parting slower than this, m/s, is resting: gravity changes speed so
    /// much in two steps.
    resting_speed: f32,
}

/// What a contact's key and its constraint both need: whether each side turns, and how
/// its anchors roll.
struct Sides {
    spin: [bool; 2],
    arm: [Vec3; 2],
    axis: [Vec3; 2],
    refresh: bool,
    report: bool,
}

impl Sides {
    fn rolls(&self) -> bool {
        self.arm != [Vec3::ZERO; 2] || self.axis != [Vec3::ZERO; 2]
    }
}

impl<'a> Builder<'a> {
    pub(super) fn new(
        colliders: &'a [ColliderEntry],
        states: &'a [BodyState],
        bodies: &'a [SolverBody],
        stiffness: ContactParams,
        (overlaps, heaviest): (&'a [u32], &'a [f32]),
    ) -> Self {
        Self {
            colliders,
            states,
            bodies,
            stiffness,
            overlaps,
            heaviest,
            shares: PushOutShares::new(stiffness.max_push_out),
            resting_speed: 2.0 * stiffness.gravity * stiffness.dt,
        }
    }

    /// A collider's body's centre of mass at the start of the step (a static collider's
    /// own position).
    #[inline(always)]
    fn centre(&self, c: &ColliderEntry) -> Vec3 {
        if c.body == STATIC {
            c.pos
        } else {
            self.states[c.body as usize].x0
        }
    }

    #[inline(always)]
    fn sides(
        &self,
        (ca, cb): (&ColliderEntry, &ColliderEntry),
        (sa, sb): (&SolverBody, &SolverBody),
    ) -> Sides {
        let anisotropic =
            |i: u32| i != STATIC && !is_isotropic(self.states[i as usize].inv_inertia);
        let spin = [spins(sa), spins(sb)];
        let arm = [
            sphere_arm(ca, spin[0], self.centre(ca)),
            sphere_arm(cb, spin[1], self.centre(cb)),
        ];
        let axis = [
            symmetry_axis(ca, spin[0], self.centre(ca)),
            symmetry_axis(cb, spin[1], self.centre(cb)),
        ];
        Sides {
            spin,
            arm,
            axis,
            refresh: (spin[0] && (anisotropic(ca.body) || arm[0] != Vec3::ZERO))
                || (spin[1] && (anisotropic(cb.body) || arm[1] != Vec3::ZERO)),
            report: ca.filter.events || cb.filter.events,
        }
    }

    /// Manifold `m`'s key: what packing needs before its contact is built.
    #[inline(always)]
    pub(super) fn key(&self, m: &Manifold) -> ContactKey {
        let (ca, cb) = (&self.colliders[m.a as usize], &self.colliders[m.b as usize]);
        let (sa, sb) = (self.bodies.at(ca.body), self.bodies.at(cb.body));
        let sides = self.sides((ca, cb), (sa, sb));
        let scalar = sides.rolls() || sides.refresh || sides.report;
        ContactKey::new((ca.body, cb.body), [sa, sb], scalar, m.len)
    }

    /// Asks the CPU for what building manifold `m`'s contact reads after the manifold:
    /// its colliders, or (`bodies`), once those have come, its bodies.
    #[inline(always)]
    pub(super) fn prefetch(&self, m: &Manifold, bodies: bool) {
        for c in [m.a, m.b] {
            let c = &self.colliders[c as usize];
            if !bodies {
                prefetch(c);
            } else if c.body != STATIC {
                prefetch(&self.states[c.body as usize]);
                prefetch(&self.bodies[c.body as usize]);
            }
        }
    }

    /// The constraint of manifold `m` (manifold `mi` of the step), built into `c`;
    /// what it found is added to `found` (not `fixed`); its rolling motion, if it has
    /// one, pushed onto `arms`. One scalar at a time: the reference the lanes' build is
    /// tested against.
    #[inline(always)]
    pub(super) fn build(
        &self,
        c: &mut ContactConstraint,
        mi: usize,
        m: &Manifold,
        arms: &mut Vec<RollingArms>,
        found: &mut Prepared,
    ) {
        let centres = self.header(c, mi, m, arms, found, None);
        let sides = [self.bodies.at(c.a), self.bodies.at(c.b)];
        prepare_points(c, m, sides, centres);
    }

    /// [`build`](Self::build) without the points, their couplings and the friction
    /// anchor (see [`prepare_points`]; zero, as for a new constraint), and the centres
    /// of mass of the constraint's two bodies (a static collider's position). Built in
    /// place: returned, the 688 bytes were read back before their stores had landed
    /// (rain's build spent a sixth of its time in that one load). With `lanes` (a
    /// batch's loads and this contact's lane), the contact is a batched one, and its
    /// softness is left to the lanes ([`LoadLanes::soften`]), and so are the ratios
    /// `found` would take.
    #[inline(always)]
    pub(super) fn header(
        &self,
        c: &mut ContactConstraint,
        mi: usize,
        m: &Manifold,
        arms: &mut Vec<RollingArms>,
        found: &mut Prepared,
        lanes: Option<(&mut LoadLanes, usize)>,
    ) -> [Vec3; 2] {
        let stiffness = &self.stiffness;
        let (ca, cb) = (&self.colliders[m.a as usize], &self.colliders[m.b as usize]);
        let (sa, sb) = (self.bodies.at(ca.body), self.bodies.at(cb.body));
        // A batched contact (`lanes`) has no rolling motion, no turning anisotropic
        // body and no events (its key said so): only its sides' spins to find.
        let sides = if lanes.is_some() {
            Sides {
                spin: [spins(sa), spins(sb)],
                arm: [Vec3::ZERO; 2],
                axis: [Vec3::ZERO; 2],
                refresh: false,
                report: false,
            }
        } else {
            self.sides((ca, cb), (sa, sb))
        };
        let (t1, t2) = m.normal.any_orthonormal_pair();
        let spin = sides.spin;
        // The heaviest body touching either side (or about to) presses through it from
        // the substep it lands; its impulses would show the load only a step late.
        let by = [ca.body, cb.body].map(|i| {
            if i == STATIC {
                0.0
            } else {
                self.heaviest[i as usize]
            }
        });
        let heaviest = by[0].max(by[1]);
        let weight = heaviest * stiffness.gravity * stiffness.h;
        let load = Load {
            inv_mass: [sa.inv_mass, sb.inv_mass],
            load: m
                .points()
                .iter()
                .map(|p| p.normal_impulse)
                .sum::<f32>()
                .max(weight),
            heaviest,
            weight,
            size: pair_size(&ca.shape, &cb.shape),
            resting: m.normal.dot(sb.v - sa.v).abs() <= self.resting_speed,
            previous_load: m.previous_load,
            restitution: m.restitution,
        };
        let softness = match lanes {
            Some((lanes, l)) => {
                // Softened in lanes, with the batch's other contacts.
                lanes.set(l, &load);
                Softness::default()
            }
            None => {
                let soft = load.soften(stiffness);
                found.ratio = found.ratio.max(soft.ratio);
                found.relax_ratio = found.relax_ratio.max(soft.relax);
                soft.softness
            }
        };
        let count = |body: u32| {
            if body == STATIC {
                0
            } else {
                self.overlaps[body as usize]
            }
        };
        *c = ContactConstraint {
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
                roll: if sides.rolls() {
                    arms.push(RollingArms {
                        arm: sides.arm,
                        axis: sides.axis,
                    });
                    arms.len() as u32 - 1
                } else {
                    NO_ROLL
                },
            },
            spin,
            refresh: sides.refresh,
            report: sides.report,
            friction: if stiffness.friction { m.friction } else { 0.0 },
            restitution: m.restitution,
            approach_gain: stiffness.gravity * stiffness.dt,
            softness,
            // A static side cannot pass a push along, so it pushes at the full limit.
            max_push: if ca.body == STATIC || cb.body == STATIC {
                stiffness.max_push_out
            } else {
                self.shares.get(count(ca.body), count(cb.body))
            },
            points: [ConstraintPoint::default(); MAX_POINTS],
            len: m.len,
            coupling: [0.0; COUPLINGS],
            anchor: FrictionAnchor::default(),
        };
        found.refresh |= c.refresh;
        found.report |= c.report;
        found.bounce |= c.restitution > 0.0;
        [self.centre(ca), self.centre(cb)]
    }
}

/// The points, couplings and friction anchor of constraint `c` (its header built) of
/// manifold `m` between `sides` with centres `centres`, one scalar at a time
/// (`ContactLanes` does the same eight at a time).
fn prepare_points(
    c: &mut ContactConstraint,
    m: &Manifold,
    [sa, sb]: [&SolverBody; 2],
    [ca, cb]: [Vec3; 2],
) {
    let spin = c.spin;
    let linear = sa.inv_mass + sb.inv_mass;
    let mid = m.points().iter().map(|p| p.point).sum::<Vec3>() / m.len.max(1) as f32;
    for (cp, p) in c.points.iter_mut().zip(m.points()) {
        let (ra, rb) = (p.point - ca, p.point - cb);
        let normal_row = AngularRow::new(sa, sb, ra, rb, m.normal);
        *cp = ConstraintPoint {
            ra,
            rb,
            adjusted_separation: p.separation - m.normal.dot(rb - ra),
            normal_row,
            normal_mass: mass_of(linear + normal_row.inv_mass(spin)),
            normal_impulse: p.normal_impulse,
            twist_arm: plane_distance(p.point - mid, m.normal),
            max_normal_impulse: 0.0,
            relative_velocity: row_velocity(sa, sb, m.normal, &normal_row, spin),
            separation: 0.0,
        };
    }
    c.coupling = normal_couplings(&c.points[..m.len], linear, spin);
    c.anchor = friction_anchor(sa, sb, (mid - ca, mid - cb), c, m.len);
    // Last step's friction, from the shares of the points that persist.
    let tangent = m.points().iter().map(|p| p.tangent_impulse).sum::<Vec3>();
    c.anchor.tangent_impulse = Vec2::new(tangent.dot(c.tangent1), tangent.dot(c.tangent2));
    if m.len > 1 {
        c.anchor.twist_impulse = m.points().iter().map(|p| p.twist_impulse).sum();
    }
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
///
/// Only the scalar pass solves such a contact (`scalar`: its contacts), and only theirs
/// are kept as constraints.
pub fn refresh_rows(
    bodies: &[SolverBody],
    constraints: &mut [ContactConstraint],
    scalar: &[u32],
    arms: &[RollingArms],
) {
    for &ci in scalar {
        let c = &mut constraints[ci as usize];
        if !c.refresh {
            continue;
        }
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
