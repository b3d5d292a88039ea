//! Contact batches: eight contacts that share no moved body (see
//! [`ContactBatches`](super::ContactBatches)) stored lane by lane (structure of arrays),
//! built once a step from their
//! [`ContactConstraint`]s, so that the solver's passes load whole lanes at once. The
//! accumulated impulses go back to the constraints when the passes are done.

use bevy::prelude::*;

use super::{
    COUPLINGS, ConstraintPoint, ContactConstraint, ContactKey, LANES, MAX_POINTS, NO_CONTACT,
    STATIC, SolverBody, body,
};
use crate::math::lanes::{F8, V3};

/// One point of each lane's contact; zeros past a contact's points. The normal row's
/// lever arms are kept as prepared; their images under the inverse inertia (see
/// [`AngularRow`](super::AngularRow)) are not kept: a sweep sums its impulses' moments
/// Σ Δλ·(r × n) and scales the sum by the batch's isotropic inertia once (loading them
/// cost more: the big scenes' constraints did not fit the cache).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PointLanes {
    /// The normal row's lever arms ra × n and rb × n, m.
    pub normal_ra: V3,
    pub normal_rb: V3,
    /// Effective mass, kg.
    pub normal_mass: F8,
    /// Accumulated impulse this substep, N·s.
    pub normal_impulse: F8,
    /// See [`ConstraintPoint::twist_arm`], m.
    pub twist_arm: F8,
    pub max_normal_impulse: F8,
    /// See [`ConstraintPoint::relative_velocity`], m/s.
    pub relative_velocity: F8,
    /// The separation now (positions move only between substeps), as the first pass
    /// after they moved measured it, m.
    pub separation: F8,
}

/// One point of each lane's contact, beside its [`PointLanes`] (`ContactBatches::anchors`,
/// the same index): what only the pass that measures the separations reads, kept apart
/// so that the other passes load less.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AnchorLanes {
    /// Anchors from each body's centre, world frame, start of step, m.
    pub ra: V3,
    pub rb: V3,
    /// See [`ConstraintPoint::adjusted_separation`], m.
    pub adjusted_separation: F8,
}

impl AnchorLanes {
    const ZERO: Self = Self {
        ra: V3::ZERO,
        rb: V3::ZERO,
        adjusted_separation: F8::ZERO,
    };
}

/// What the passes change of a batch's friction anchors (see
/// [`FrictionAnchor`](super::FrictionAnchor)), lane by lane: kept beside the batches
/// (`ContactBatches::friction`, one a batch), which the passes only read.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FrictionLanes {
    /// Accumulated friction impulse this substep along the two tangents, N·s.
    pub tangent_impulse: [F8; 2],
    /// Accumulated twist impulse about the normal, N·m·s.
    pub twist_impulse: F8,
}

/// Eight contacts that share no body the solver moves, lane by lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ContactBatch {
    /// The constraints in the lanes ([`NO_CONTACT`] for an empty lane).
    pub contact: [u32; LANES],
    /// Their bodies ([`STATIC`] for an empty lane).
    pub a: [u32; LANES],
    pub b: [u32; LANES],
    /// Whether the contacts move each lane's body on each side (see
    /// `moved_by_contacts`): only those velocities are written back.
    pub moved: [[bool; LANES]; 2],
    /// The normals; the tangents are made from them where needed
    /// ([`tangents`](Self::tangents)): 96 bytes a batch fewer to read in every pass.
    pub normal: V3,
    /// Each side's inverse inertia, 1/(kg·m²): the same about every axis for every
    /// body in a batch (an anisotropic body that turns has its rows refreshed every
    /// substep, so its contacts stay out of the batches), zero for a static side.
    pub inv_inertia: [F8; 2],
    /// All-ones lanes where each side's anchor turns with its body.
    pub turn: [F8; 2],
    pub friction: F8,
    /// See [`ContactConstraint::restitution`].
    pub restitution: F8,
    /// m/s, see [`ContactConstraint::approach_gain`].
    pub approach_gain: F8,
    pub bias_rate: F8,
    pub mass_scale: F8,
    pub impulse_scale: F8,
    /// m/s, see [`ContactConstraint::max_push`].
    pub max_push: F8,
    /// All-ones lanes whose contact has more than k points, per k. (Making them in the
    /// pass from a point count reads 48 bytes a batch fewer, 1.6 % fewer L2 misses on the
    /// pyramid, for 5.7 % more instructions.)
    pub has: [F8; MAX_POINTS],
    /// See [`ContactConstraint::coupling`], 1/kg.
    pub coupling: [F8; COUPLINGS],
    /// The tangent rows' lever arms at the friction anchors (see
    /// [`FrictionAnchor`](super::FrictionAnchor)) as prepared: ra × t and rb × t for
    /// each tangent t, m. (Making them in the pass from the anchors reads 96 bytes a
    /// batch fewer, 4 % fewer L2 misses on the pyramid, for 3 % more instructions.)
    pub tangent_ra: [V3; 2],
    pub tangent_rb: [V3; 2],
    /// kg, kg·m² (0: no twist row).
    pub tangent_mass: F8,
    pub twist_mass: F8,
    /// Where the batch's points start in the batches' point lanes, and how many it has
    /// (the most of any lane).
    pub first: u32,
    pub points: u32,
}

#[inline(always)]
fn set(v: &mut F8, l: usize, x: f32) {
    v.as_array_mut()[l] = x;
}

const ALL: f32 = f32::from_bits(u32::MAX);

impl PointLanes {
    const ZERO: Self = Self {
        normal_ra: V3::ZERO,
        normal_rb: V3::ZERO,
        normal_mass: F8::ZERO,
        normal_impulse: F8::ZERO,
        twist_arm: F8::ZERO,
        max_normal_impulse: F8::ZERO,
        relative_velocity: F8::ZERO,
        separation: F8::ZERO,
    };

    #[cfg(any(test, feature = "bench-internals"))]
    fn set(&mut self, l: usize, p: &ConstraintPoint) {
        self.normal_ra.set(l, p.normal_row.ra);
        self.normal_rb.set(l, p.normal_row.rb);
        set(&mut self.normal_mass, l, p.normal_mass);
        set(&mut self.normal_impulse, l, p.normal_impulse);
        set(&mut self.twist_arm, l, p.twist_arm);
        set(&mut self.max_normal_impulse, l, p.max_normal_impulse);
        set(&mut self.relative_velocity, l, p.relative_velocity);
    }

    /// Lane `l`'s accumulated impulses into its point.
    pub(crate) fn write_back(&self, l: usize, p: &mut ConstraintPoint) {
        p.normal_impulse = self.normal_impulse.as_array_ref()[l];
        p.max_normal_impulse = self.max_normal_impulse.as_array_ref()[l];
        p.relative_velocity = self.relative_velocity.as_array_ref()[l];
    }
}

impl ContactBatch {
    /// The batch of the listed contacts with its lanes not yet filled: their bodies and
    /// point count from `keys` (see [`set_lane`](Self::set_lane)), their points
    /// appended to `points` and `anchors` and their friction impulses to `friction`,
    /// zero.
    #[inline(always)]
    pub(crate) fn empty(
        keys: &[ContactKey],
        contact: [u32; LANES],
        (points, anchors): (&mut Vec<PointLanes>, &mut Vec<AnchorLanes>),
        friction: &mut Vec<FrictionLanes>,
    ) -> Self {
        let first = points.len();
        let len = |ci: u32| (ci != NO_CONTACT).then(|| keys[ci as usize].len as usize);
        let most = contact.iter().filter_map(|&ci| len(ci)).max().unwrap_or(0);
        points.resize(first + most, PointLanes::ZERO);
        anchors.resize(first + most, AnchorLanes::ZERO);
        friction.push(FrictionLanes::default());
        let mut b = Self {
            contact,
            a: [STATIC; LANES],
            b: [STATIC; LANES],
            moved: [[false; LANES]; 2],
            normal: V3::ZERO,
            inv_inertia: [F8::ZERO; 2],
            turn: [F8::ZERO; 2],
            friction: F8::ZERO,
            restitution: F8::ZERO,
            approach_gain: F8::ZERO,
            bias_rate: F8::ZERO,
            mass_scale: F8::ZERO,
            impulse_scale: F8::ZERO,
            max_push: F8::ZERO,
            has: [F8::ZERO; MAX_POINTS],
            coupling: [F8::ZERO; COUPLINGS],
            tangent_ra: [V3::ZERO; 2],
            tangent_rb: [V3::ZERO; 2],
            tangent_mass: F8::ZERO,
            twist_mass: F8::ZERO,
            first: first as u32,
            points: most as u32,
        };
        for (l, &ci) in contact.iter().enumerate() {
            if ci != NO_CONTACT {
                let k = &keys[ci as usize];
                (b.a[l], b.b[l]) = (k.a, k.b);
                b.moved[0][l] = k.moved[0];
                b.moved[1][l] = k.moved[1];
            }
        }
        b
    }

    /// Lane `l` from its contact's constraint `c` (the lane's bodies and the batch's
    /// point count set by [`empty`](Self::empty)): `point` and `anchor` are the batch's
    /// points, `rubbing` its friction impulses.
    #[cfg(any(test, feature = "bench-internals"))]
    #[inline(always)]
    pub(crate) fn set_lane(
        &mut self,
        l: usize,
        c: &ContactConstraint,
        bodies: &[SolverBody],
        (point, anchor): (&mut [PointLanes], &mut [AnchorLanes]),
        rubbing: &mut FrictionLanes,
    ) {
        self.set_header(l, c, bodies);
        let b = self;
        for (lanes, &k) in b.coupling.iter_mut().zip(&c.coupling) {
            set(lanes, l, k);
        }
        let f = &c.anchor;
        for (k, row) in f.tangent_rows.iter().enumerate() {
            b.tangent_ra[k].set(l, row.ra);
            b.tangent_rb[k].set(l, row.rb);
        }
        set(&mut b.tangent_mass, l, f.tangent_mass);
        set(&mut b.twist_mass, l, f.twist_mass);
        set(&mut rubbing.tangent_impulse[0], l, f.tangent_impulse.x);
        set(&mut rubbing.tangent_impulse[1], l, f.tangent_impulse.y);
        set(&mut rubbing.twist_impulse, l, f.twist_impulse);
        for k in 0..c.len {
            set(&mut b.has[k], l, ALL);
            point[k].set(l, &c.points[k]);
            anchor[k].ra.set(l, c.points[k].ra);
            anchor[k].rb.set(l, c.points[k].rb);
            set(
                &mut anchor[k].adjusted_separation,
                l,
                c.points[k].adjusted_separation,
            );
        }
    }

    /// Lane `l`'s header from its contact's constraint `c` (whose points need not be
    /// built): its normal, inertias, turning anchors, friction and softness.
    #[inline(always)]
    pub(crate) fn set_header(&mut self, l: usize, c: &ContactConstraint, bodies: &[SolverBody]) {
        let b = self;
        debug_assert_eq!((b.a[l], b.b[l]), (c.a, c.b), "the lane's contact");
        debug_assert!(c.len <= b.points as usize, "the batch holds the points");
        b.normal.set(l, c.normal);
        debug_assert_eq!((c.tangent1, c.tangent2), c.normal.any_orthonormal_pair());
        for (side, i) in [c.a, c.b].into_iter().enumerate() {
            let m = body(bodies, i).inv_inertia;
            debug_assert_eq!(m, Mat3::from_diagonal(Vec3::splat(m.x_axis.x)), "batched");
            set(&mut b.inv_inertia[side], l, m.x_axis.x);
        }
        for side in 0..2 {
            set(
                &mut b.turn[side],
                l,
                if c.anchoring.turn[side] { ALL } else { 0.0 },
            );
        }
        set(&mut b.friction, l, c.friction);
        set(&mut b.restitution, l, c.restitution);
        set(&mut b.approach_gain, l, c.approach_gain);
        set(&mut b.bias_rate, l, c.softness.bias_rate);
        set(&mut b.mass_scale, l, c.softness.mass_scale);
        set(&mut b.impulse_scale, l, c.softness.impulse_scale);
        set(&mut b.max_push, l, c.max_push);
    }

    /// The lanes' friction tangents, as each constraint has them
    /// (`Vec3::any_orthonormal_pair` of the normal, bit for bit).
    #[inline(always)]
    pub(crate) fn tangents(&self) -> [V3; 2] {
        let (t1, t2) = self.normal.any_orthonormal_pair();
        [t1, t2]
    }

    /// Its points' range in the batches' point lanes.
    #[inline(always)]
    pub(crate) fn range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.points) as usize
    }

    /// The lanes' accumulated impulses (`friction`: this batch's) back into their
    /// constraints.
    pub(crate) fn write_back(
        &self,
        points: &[PointLanes],
        friction: &FrictionLanes,
        constraints: &mut [ContactConstraint],
    ) {
        let point = &points[self.range()];
        for (l, &ci) in self.contact.iter().enumerate() {
            if ci != NO_CONTACT {
                let c = &mut constraints[ci as usize];
                let lane = |v: &F8| v.as_array_ref()[l];
                let t = &friction.tangent_impulse;
                c.anchor.tangent_impulse = Vec2::new(lane(&t[0]), lane(&t[1]));
                c.anchor.twist_impulse = lane(&friction.twist_impulse);
                for (k, p) in c.points[..c.len].iter_mut().enumerate() {
                    point[k].write_back(l, p);
                }
            }
        }
    }
}
