//! Contact constraints: what the solver builds from a manifold, one soft normal row per
//! point and one friction anchor per manifold (a two-row friction disc at the points'
//! centre and a twist row about the normal), with the angular parts prepared once per
//! step.

use bevy::prelude::*;

use super::MAX_POINTS;
use super::{STATIC, SolverBody};
use crate::math::Softness;

/// The solver body every static collider shares: never moves, infinite mass.
pub(crate) const STATIC_BODY: SolverBody = SolverBody {
    v: Vec3::ZERO,
    w: Vec3::ZERO,
    dp: Vec3::ZERO,
    dq: Quat::IDENTITY,
    inv_mass: 0.0,
    inv_inertia: Mat3::ZERO,
};

/// One contact point of a [`ContactConstraint`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ConstraintPoint {
    /// Anchors from each body's centre to the contact point, world frame, start of step.
    pub ra: Vec3,
    pub rb: Vec3,
    /// Separation at the start of the step minus n·(rb − ra), so that the current
    /// separation is this plus n·(cb − ca) for the moved anchor points ca, cb.
    pub adjusted_separation: f32,
    /// The angular parts of the normal row.
    pub normal_row: AngularRow,
    /// kg.
    pub normal_mass: f32,
    /// N·s.
    pub normal_impulse: f32,
    /// Distance from the friction anchor (the points' centre) in the contact plane, m:
    /// this point's lever arm against twist.
    pub twist_arm: f32,
    /// Largest normal impulse this step; restitution only acts on points that pushed.
    pub max_normal_impulse: f32,
    /// Normal relative velocity at the start of the step, m/s, and from when the point
    /// first pushes, its speed then: the approach speed restitution reverses (see
    /// `ContactConstraint::approach_gain`).
    pub relative_velocity: f32,
    /// The separation the scalar pass last measured, m: the bodies move only between
    /// substeps, so a substep's later passes read it instead of turning the anchors again.
    pub separation: f32,
}

/// A manifold's friction, at one anchor: the points' centre, where a disc of two tangent
/// rows holds the slip, plus a twist row about the normal that holds the turn in the
/// contact plane. Three rows a manifold instead of two a point (eight for a box face):
/// the same sliding friction, μ·Σλn, and the twist limited to μ·Σ λn·arm, what the
/// points' own friction would give against a pure turn about the centre. Solved as one
/// anchor, it also has no order among the points: no corner is solved first to twist the
/// box before the next corner is.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FrictionAnchor {
    /// The anchor from each body's centre, world frame, start of step, m.
    pub ra: Vec3,
    pub rb: Vec3,
    /// The angular parts of the two tangent rows.
    pub tangent_rows: [AngularRow; 2],
    /// One mass for both tangent rows, kg; see `isotropic_tangent_mass`.
    pub tangent_mass: f32,
    /// Friction impulse along (tangent1, tangent2), N·s.
    pub tangent_impulse: Vec2,
    /// Ia⁻¹ n, Ib⁻¹ n: the twist row's images under the inverse inertias, 1/(kg·m²).
    pub twist_ia: Vec3,
    pub twist_ib: Vec3,
    /// kg·m²; 0 for a single point (no twist row).
    pub twist_mass: f32,
    /// Twist impulse about the normal, on B, N·m·s.
    pub twist_impulse: f32,
}

/// The angular parts of one velocity row along a direction d at a contact point:
/// r × d for each body and their images under the body's inverse inertia (which is fixed
/// over the step). With them a row's velocity is three dot products and its impulse
/// three scaled additions, with no cross products or matrix products per iteration.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct AngularRow {
    /// ra × d, rb × d.
    pub ra: Vec3,
    pub rb: Vec3,
    /// Ia⁻¹ (ra × d), Ib⁻¹ (rb × d).
    pub ia: Vec3,
    pub ib: Vec3,
}

impl AngularRow {
    #[inline]
    pub(crate) fn new(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, d: Vec3) -> Self {
        let (ra, rb) = (ra.cross(d), rb.cross(d));
        Self {
            ra,
            rb,
            ia: a.inv_inertia * ra,
            ib: b.inv_inertia * rb,
        }
    }

    /// The row's angular share of the inverse effective mass.
    #[inline]
    pub(crate) fn inv_mass(&self, spin: [bool; 2]) -> f32 {
        let a = if spin[0] { self.ra.dot(self.ia) } else { 0.0 };
        let b = if spin[1] { self.rb.dot(self.ib) } else { 0.0 };
        a + b
    }
}

/// Velocity of b relative to a along the row's direction `d`.
#[inline]
pub(crate) fn row_velocity(
    a: &SolverBody,
    b: &SolverBody,
    d: Vec3,
    row: &AngularRow,
    spin: [bool; 2],
) -> f32 {
    let mut v = d.dot(b.v - a.v);
    if spin[0] {
        v -= a.w.dot(row.ra);
    }
    if spin[1] {
        v += b.w.dot(row.rb);
    }
    v
}

/// The contact of one manifold prepared for the solver.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ContactConstraint {
    /// Body indices, or [`STATIC`].
    pub a: u32,
    pub b: u32,
    /// The manifold the results go back to.
    pub manifold: u32,
    pub normal: Vec3,
    pub tangent1: Vec3,
    pub tangent2: Vec3,
    /// How each anchor moves with its body when measuring separation.
    pub anchoring: Anchoring,
    /// Whether each body can turn here (a dynamic body with rotation, or a spinning
    /// kinematic one). A static body or one with `LockRotation` runs no angular terms.
    pub spin: [bool; 2],
    /// A body here can turn and its inertia is not the same about every axis, so its
    /// world inertia changes as it turns: the rows are refreshed every substep
    /// ([`refresh_rows`]).
    pub refresh: bool,
    /// A collider here asked for collision events: sum the step's impulses for them.
    pub report: bool,
    pub friction: f32,
    pub restitution: f32,
    /// How much faster than at the start of the step a point may be approaching when it
    /// first pushes, m/s: what gravity adds in a step, |g|·dt. A ball falling onto a
    /// floor meets it up to a step after the contact was prepared, g·dt faster; a light
    /// box squeezed into the floor by a heavy ball is driven in by the solver, and that
    /// is no approach to bounce back from (it came back at 458 m/s).
    pub approach_gain: f32,
    pub softness: Softness,
    /// Fastest push-out, m/s, this contact may drive: the setting shared among the
    /// overlaps of the more crowded of its two bodies (`push_out_share`).
    pub max_push: f32,
    pub points: [ConstraintPoint; MAX_POINTS],
    pub len: usize,
    /// How the normal rows move each other (see [`normal_couplings`]), 1/kg.
    pub coupling: [f32; COUPLINGS],
    pub anchor: FrictionAnchor,
}

/// Pairs of a manifold's points, j > k: the couplings a constraint keeps.
pub(crate) const COUPLINGS: usize = MAX_POINTS * (MAX_POINTS - 1) / 2;

/// Where the coupling of points j > k is kept.
#[inline(always)]
pub(crate) const fn coupling_index(j: usize, k: usize) -> usize {
    j * (j - 1) / 2 + k
}

/// The couplings of a manifold's normal rows: for each pair of points j > k, how much a
/// unit normal impulse at k changes the normal velocity at j, 1/kg,
/// K_jk = 1/m_a + 1/m_b + (ra_j × n)·Ia⁻¹(ra_k × n) + (rb_j × n)·Ib⁻¹(rb_k × n)
/// (the off-diagonal of the manifold's effective-mass matrix; a side that cannot turn
/// has no angular term). With them a sweep over the points reads the bodies' velocities
/// once and moves them once: point j's velocity after the impulses before it is its
/// velocity before the sweep plus Σ K_jk·Δλ_k. Zero for pairs past `points`.
pub(crate) fn normal_couplings(
    points: &[ConstraintPoint],
    linear: f32,
    spin: [bool; 2],
) -> [f32; COUPLINGS] {
    let mut coupling = [0.0; COUPLINGS];
    for j in 1..points.len() {
        let rj = &points[j].normal_row;
        for (k, pk) in points[..j].iter().enumerate() {
            let a = if spin[0] {
                rj.ra.dot(pk.normal_row.ia)
            } else {
                0.0
            };
            let b = if spin[1] {
                rj.rb.dot(pk.normal_row.ib)
            } else {
                0.0
            };
            coupling[coupling_index(j, k)] = linear + (a + b);
        }
    }
    coupling
}

/// The knobs of the solver's constraint preparation: stiffness, substep, and whether friction runs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ContactParams {
    /// With friction off every constraint gets μ = 0 and its friction rows are skipped.
    pub friction: bool,
    pub hertz: f32,
    pub max_hertz: f32,
    /// |gravity|, to read a contact's load from its impulses.
    pub gravity: f32,
    pub damping_ratio: f32,
    /// Substep, s.
    pub h: f32,
    /// Step, s.
    pub dt: f32,
    /// Fastest push-out of one body, m/s (`SolverSettings::max_push_out`).
    pub max_push_out: f32,
    /// Allowed resting sag per contact, as a fraction of the smaller body's size.
    pub max_sag: f32,
    /// Normal approach speed below which a contact does not bounce this step, m/s.
    pub bounce_threshold: f32,
}

/// A constraint's body `i`: the solver body, or the shared static one.
#[inline]
pub(crate) fn body(bodies: &[SolverBody], i: u32) -> SolverBody {
    if i == STATIC {
        STATIC_BODY
    } else {
        bodies[i as usize]
    }
}

/// Stores a constraint's body's velocities back (nothing for the static one): all that
/// the velocity passes change. Storing the whole body (92 bytes, twice a constraint) made
/// the next constraint's load of it wait for the stores.
#[inline]
pub(crate) fn store(bodies: &mut [SolverBody], i: u32, b: SolverBody) {
    if i != STATIC {
        let s = &mut bodies[i as usize];
        (s.v, s.w) = (b.v, b.w);
    }
}

/// `Anchoring::roll` of a contact whose anchors simply turn with their bodies.
pub(crate) const NO_ROLL: u32 = u32::MAX;

impl Default for Anchoring {
    fn default() -> Self {
        Self {
            turn: [false; 2],
            roll: NO_ROLL,
        }
    }
}

/// How a contact's anchors move as their bodies turn, when measuring separation. Eight
/// bytes: the rare rolling motions live in a side list (`PhysicsWorld::rolling_arms`),
/// so contacts that have none (nearly all) keep the constraint small.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Anchoring {
    /// Whether each anchor turns with its body. A sphere's contact point stays under its
    /// centre as it rolls, so its anchor does not turn.
    pub turn: [bool; 2],
    /// For a contact with a rolling shape (see [`RollingArms`]): the index of its
    /// motion in the side list; else [`NO_ROLL`].
    pub roll: u32,
}

/// How a rolling shape's anchor moves, per side (zero vectors for a side that does not
/// roll):
/// - `arm`, for a sphere whose centre of mass is off its centre: the sphere's centre
///   from the centre of mass, world frame, start of step. That arm turns with the body
///   while the contact point stays under the sphere's centre, so the anchor moves by the
///   arm's turn alone.
/// - `axis`, for a capsule, cylinder or cone whose axis passes through its body's centre
///   of mass: the axis, world frame, start of step. Turning about it leaves the shape
///   where it was (a rolling cylinder's contact stays under it), so the anchor turns by
///   the rest of the turn only (the swing of a swing–twist split). Turned whole, a
///   cylinder rolling at 1.7 m/s measured its contact 2 mm apart every step.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RollingArms {
    pub arm: [Vec3; 2],
    pub axis: [Vec3; 2],
}

/// The part of `q` that is not a turn about the unit `axis` (q = swing · twist).
#[inline]
pub(crate) fn swing(q: Quat, axis: Vec3) -> Quat {
    let along = axis * Vec3::new(q.x, q.y, q.z).dot(axis);
    let twist = Quat::from_xyzw(along.x, along.y, along.z, q.w);
    let len = twist.length();
    if len < 1e-9 {
        // A half turn about an axis across this one: all swing.
        return q;
    }
    q * (twist / len).conjugate()
}

impl Anchoring {
    /// Whether a rolling motion applies here.
    #[inline]
    pub(crate) fn rolls(&self) -> bool {
        self.roll != NO_ROLL
    }

    /// Point `p`'s anchors on A and B now, from the bodies' start-of-step centres.
    /// Without a rolling motion (nearly every contact) they turn with their bodies or
    /// stay; the few with one take the cold path.
    #[inline(always)]
    pub(crate) fn anchors(
        &self,
        p: &ConstraintPoint,
        a: &SolverBody,
        b: &SolverBody,
        arms: &[RollingArms],
    ) -> (Vec3, Vec3) {
        if self.rolls() {
            return self.rolling_anchors(p, a, b, arms);
        }
        self.plain_anchors(p, a, b)
    }

    /// [`anchors`](Self::anchors) of a contact known to have no rolling motion. (The
    /// passes do not turn anchors: they measure with [`normal_images`](Self::normal_images).)
    #[inline(always)]
    fn plain_anchors(&self, p: &ConstraintPoint, a: &SolverBody, b: &SolverBody) -> (Vec3, Vec3) {
        let ca = if self.turn[0] { a.dq * p.ra } else { p.ra };
        let cb = if self.turn[1] { b.dq * p.rb } else { p.rb };
        (ca, cb)
    }

    /// The normal `n` in each body's start-of-step frame, for a contact without a rolling
    /// motion: n·(dq r) = (dq⁻¹ n)·r, so a point's separation is then two dot products
    /// (`iterate::solve_one`, the batched pass the same), not two rotations of its anchors.
    /// A side whose anchor does not turn keeps `n`.
    #[inline(always)]
    pub(crate) fn normal_images(&self, n: Vec3, a: &SolverBody, b: &SolverBody) -> (Vec3, Vec3) {
        let na = if self.turn[0] {
            a.dq.conjugate() * n
        } else {
            n
        };
        let nb = if self.turn[1] {
            b.dq.conjugate() * n
        } else {
            n
        };
        (na, nb)
    }

    /// [`anchors`](Self::anchors) under a rolling motion: a side that turns takes only
    /// its body's swing off the axis it rolls about; a side that stays is carried by the
    /// arm's turn. Out of the solver loops' line (one copy of each loop, not two).
    #[cold]
    #[inline(never)]
    fn rolling_anchors(
        &self,
        p: &ConstraintPoint,
        a: &SolverBody,
        b: &SolverBody,
        arms: &[RollingArms],
    ) -> (Vec3, Vec3) {
        let m = arms[self.roll as usize];
        let side = |dq: Quat, arm: Vec3, axis: Vec3, turns: bool, r: Vec3| {
            if !turns {
                return r + (dq * arm - arm);
            }
            let rot = if axis == Vec3::ZERO {
                dq
            } else {
                swing(dq, axis)
            };
            rot * r
        };
        (
            side(a.dq, m.arm[0], m.axis[0], self.turn[0], p.ra),
            side(b.dq, m.arm[1], m.axis[1], self.turn[1], p.rb),
        )
    }
}
