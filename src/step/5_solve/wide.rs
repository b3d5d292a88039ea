//! The contact passes over the batches (see [`ContactBatches`](crate::world::ContactBatches)):
//! eight contacts that share no moved body, solved side by side in eight lanes (a
//! [`Lane`] type: one AVX register where the CPU has it). Each lane does exactly what
//! [`iterate`](super::iterate) does for one contact, in the same order (the scalar pass
//! stays as the reference these are tested against, bit for bit). A batch holds its
//! contacts lane by lane ([`ContactBatch`]) and gathers its bodies' velocities.

#[cfg(target_arch = "x86_64")]
use crate::math::lanes::avx::Y8;
use crate::math::lanes::{F8, Lane, Q8, V3, clamp, eq, gt, lanes, le, lt, max, neg, select};
#[cfg(target_arch = "x86_64")]
use crate::math::lanes::{three_operand, wide_registers};
use crate::world::{
    AnchorLanes, BodyView, ContactBatch, FrictionLanes, LANES, MAX_POINTS, PointLanes, SolverBody,
    coupling_index,
};

use super::iterate::{NORMAL_SWEEPS, NORMAL_TOL};

/// One side's bodies of a batch: what the passes change and read.
pub(super) struct BodyLanes<L> {
    v: V3<L>,
    w: V3<L>,
    inv_mass: L,
}

/// One side's bodies' motion since the step began: what the separations are measured
/// from.
struct PoseLanes<L> {
    dp: V3<L>,
    dq: Q8<L>,
}

/// The bodies of a batch's lanes on one side. (Written out: `index.map` was left a
/// call, four a batch.)
#[inline(always)]
fn at_lanes(bodies: &(impl BodyView + ?Sized), i: [u32; LANES]) -> [&SolverBody; LANES] {
    const { assert!(LANES == 8, "one entry a lane") };
    [
        bodies.at(i[0]),
        bodies.at(i[1]),
        bodies.at(i[2]),
        bodies.at(i[3]),
        bodies.at(i[4]),
        bodies.at(i[5]),
        bodies.at(i[6]),
        bodies.at(i[7]),
    ]
}

impl<L: Lane> PoseLanes<L> {
    #[inline(always)]
    fn gather(bodies: &(impl BodyView + ?Sized), index: [u32; LANES]) -> Self {
        let b = at_lanes(bodies, index);
        Self {
            dp: V3::gather(b.map(|b| b.dp)),
            dq: Q8::gather(b.map(|b| b.dq)),
        }
    }
}

impl<L: Lane> BodyLanes<L> {
    #[inline(always)]
    pub(super) fn gather(bodies: &(impl BodyView + ?Sized), index: [u32; LANES]) -> Self {
        let b = at_lanes(bodies, index);
        Self {
            v: V3::gather(b.map(|b| b.v)),
            w: V3::gather(b.map(|b| b.w)),
            inv_mass: L::load(lanes(b.map(|b| b.inv_mass))),
        }
    }

    /// Velocities back to the bodies the contacts move.
    #[inline(always)]
    pub(super) fn scatter(
        &self,
        bodies: &mut (impl BodyView + ?Sized),
        index: [u32; LANES],
        moved: [bool; LANES],
    ) {
        let (v, w) = (self.v.put(), self.w.put());
        for l in 0..LANES {
            if moved[l] {
                bodies.set_velocity(index[l], v.lane(l), w.lane(l));
            }
        }
    }

    /// Impulse `p` with its angular part on this side: +p on body b, −p on body a.
    #[inline(always)]
    pub(super) fn push(&mut self, p: V3<L>, angular: V3<L>, on_b: bool) {
        if on_b {
            self.v = self.v.add(p.scale(self.inv_mass));
            self.w = self.w.add(angular);
        } else {
            self.v = self.v.sub(p.scale(self.inv_mass));
            self.w = self.w.sub(angular);
        }
    }
}

/// What every pass reads of a batch besides its points, in the lanes it computes in.
pub(super) struct Shape<L> {
    pub normal: V3<L>,
    /// Each side's inverse inertia (see [`ContactBatch::inv_inertia`]).
    pub inv_inertia: [L; 2],
}

impl<L: Lane> Shape<L> {
    #[inline(always)]
    pub(super) fn of(c: &ContactBatch) -> Self {
        Self {
            normal: c.normal.get(),
            inv_inertia: c.inv_inertia.map(L::load),
        }
    }
}

/// The angular parts of one row along `d` at a point, lane by lane, as
/// [`AngularRow::new`](crate::world::AngularRow::new) makes them: r × d for each body and
/// their images under its inverse inertia (a multiple of the identity in a batch: the
/// same bits as the matrix product, but for the sign of a zero).
#[derive(Clone, Copy)]
struct RowLanes<L> {
    ra: V3<L>,
    rb: V3<L>,
    ia: V3<L>,
    ib: V3<L>,
}

impl<L: Lane> RowLanes<L> {
    /// The row of lever arms `ra` (r × d) and `rb`.
    #[inline(always)]
    fn of(inv_inertia: &[L; 2], ra: V3<L>, rb: V3<L>) -> Self {
        Self {
            ra,
            rb,
            ia: ra.scale(inv_inertia[0]),
            ib: rb.scale(inv_inertia[1]),
        }
    }
}

/// The row velocity of b relative to a along `d`, with the row's angular parts.
#[inline(always)]
fn row_velocity<L: Lane>(a: &BodyLanes<L>, b: &BodyLanes<L>, d: V3<L>, row: &RowLanes<L>) -> L {
    d.dot(b.v.sub(a.v)) - a.w.dot(row.ra) + b.w.dot(row.rb)
}

/// The normal velocity of b relative to a at a point, from its prepared lever arms (the
/// scalar pass's `row_velocity`, lane by lane).
#[inline(always)]
pub(super) fn normal_velocity<L: Lane>(
    a: &BodyLanes<L>,
    b: &BodyLanes<L>,
    n: V3<L>,
    p: &PointLanes,
) -> L {
    n.dot(b.v.sub(a.v)) - a.w.dot(p.normal_ra.get()) + b.w.dot(p.normal_rb.get())
}

/// Normal impulses `dl` at a batch's points, all at once (as `iterate::apply_normals`):
/// the warm start's, and each normal sweep's.
#[inline(always)]
fn apply_normals<L: Lane>(
    (a, b): (&mut BodyLanes<L>, &mut BodyLanes<L>),
    c: &Shape<L>,
    point: &[PointLanes],
    dl: impl IntoIterator<Item = L>,
) {
    let (mut total, mut ra, mut rb) = (L::splat(0.0), V3::zero(), V3::zero());
    for (p, dl) in point.iter().zip(dl) {
        total = total + dl;
        ra = ra.add(p.normal_ra.get().scale(dl));
        rb = rb.add(p.normal_rb.get().scale(dl));
    }
    let p = c.normal.scale(total);
    a.push(p, ra.scale(c.inv_inertia[0]), false);
    b.push(p, rb.scale(c.inv_inertia[1]), true);
}

/// A twist impulse `d` about the normal: +d on b, −d on a.
#[inline(always)]
fn apply_twist<L: Lane>(a: &mut BodyLanes<L>, b: &mut BodyLanes<L>, c: &Shape<L>, d: L) {
    a.w = a.w.sub(c.normal.scale(c.inv_inertia[0]).scale(d));
    b.w = b.w.add(c.normal.scale(c.inv_inertia[1]).scale(d));
}

/// The tangent rows at a batch's friction anchors.
#[inline(always)]
fn anchor_rows<L: Lane>(c: &ContactBatch, inv_inertia: &[L; 2]) -> [RowLanes<L>; 2] {
    [
        RowLanes::of(inv_inertia, c.tangent_ra[0].get(), c.tangent_rb[0].get()),
        RowLanes::of(inv_inertia, c.tangent_ra[1].get(), c.tangent_rb[1].get()),
    ]
}

/// A friction impulse `d` along the two tangents at the friction anchor.
#[inline(always)]
fn apply_tangent<L: Lane>(
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    t: &(V3<L>, V3<L>),
    rows: &[RowLanes<L>; 2],
    d: [L; 2],
) {
    let p = t.0.scale(d[0]).add(t.1.scale(d[1]));
    a.push(p, rows[0].ia.scale(d[0]).add(rows[1].ia.scale(d[1])), false);
    b.push(p, rows[0].ib.scale(d[0]).add(rows[1].ib.scale(d[1])), true);
}

/// The copies of a pass over the batches: `$any`, generic over the lanes it computes
/// in, is compiled plain (with [`F8`]), for AVX2 (with [`Y8`]) and for AVX-512's 32
/// registers (with `Y8`), and `$name` runs the widest this CPU has. The operations are
/// the same in every copy, with no fused multiply-add: the same bits.
macro_rules! dispatch {
    ($(#[$doc:meta])* pub fn $name:ident / $wide:ident / $vex:ident => $any:ident
        ($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        $(#[$doc])*
        pub fn $name(bodies: &mut (impl BodyView + ?Sized), $($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if wide_registers() {
                // SAFETY: the CPU has the features (checked just above).
                return unsafe { $wide(bodies, $($arg),*) };
            }
            #[cfg(target_arch = "x86_64")]
            if three_operand() {
                // SAFETY: the CPU has the features (checked just above).
                return unsafe { $vex(bodies, $($arg),*) };
            }
            $any::<F8>(bodies, $($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx,avx2,avx512f,avx512vl")]
        fn $wide(bodies: &mut (impl BodyView + ?Sized), $($arg: $ty),*) -> $ret {
            $any::<Y8>(bodies, $($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx,avx2")]
        fn $vex(bodies: &mut (impl BodyView + ?Sized), $($arg: $ty),*) -> $ret {
            $any::<Y8>(bodies, $($arg),*)
        }
    };
}
pub(super) use dispatch;

dispatch! {
    /// [`warm_start_listed`](super::iterate::warm_start_listed) over the batches.
    /// `points` starts at the first batch's; `friction` holds the batches' own.
    pub fn warm_start_batches / warm_start_wide / warm_start_vex => warm_start_any(
        batches: &[ContactBatch],
        points: &[PointLanes],
        friction: &[FrictionLanes],
    ) -> ()
}

#[inline(always)]
fn warm_start_any<L: Lane>(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &[PointLanes],
    friction: &[FrictionLanes],
) {
    let base = batches.first().map_or(0, |b| b.first as usize);
    for (c, f) in batches.iter().zip(friction) {
        let (mut a, mut b) = (
            BodyLanes::<L>::gather(bodies, c.a),
            BodyLanes::<L>::gather(bodies, c.b),
        );
        let shape = Shape::of(c);
        let range = c.range();
        let point = &points[range.start - base..range.end - base];
        let impulses = point.iter().map(|p| L::load(p.normal_impulse));
        apply_normals((&mut a, &mut b), &shape, point, impulses);
        let tangents = shape.normal.any_orthonormal_pair();
        let tangent = anchor_rows(c, &shape.inv_inertia);
        let rubbing = f.tangent_impulse.map(L::load);
        apply_tangent(&mut a, &mut b, &tangents, &tangent, rubbing);
        apply_twist(&mut a, &mut b, &shape, L::load(f.twist_impulse));
        a.scatter(bodies, c.a, c.moved[0]);
        b.scatter(bodies, c.b, c.moved[1]);
    }
}

dispatch! {
    /// [`solve_listed`](super::iterate::solve_listed) over the batches (contacts without a
    /// rolling motion). `points` starts at the first batch's. `measure`, the points'
    /// anchors (the same index as `points`): the bodies have moved since the last pass, so
    /// measure the separations again (the scalar pass measures them in every pass;
    /// positions move only between substeps, so a stage's later passes, and the fixed
    /// contacts' second solve, reuse the same bits). `friction` holds the batches' own.
    /// Returns the sweeps over the batches' normal rows, all batches together (each batch
    /// sweeps at least once).
    pub fn solve_batches / solve_wide / solve_vex => solve_any(
        batches: &[ContactBatch],
        points: &mut [PointLanes],
        friction: &mut [FrictionLanes],
        h: f32,
        use_bias: bool,
        measure: Option<&[AnchorLanes]>,
    ) -> u32
}

#[inline(always)]
fn solve_any<L: Lane>(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    friction: &mut [FrictionLanes],
    h: f32,
    use_bias: bool,
    measure: Option<&[AnchorLanes]>,
) -> u32 {
    let inv_h = L::splat(1.0 / h);
    let base = batches.first().map_or(0, |b| b.first as usize);
    let mut sweeps = 0;
    for (c, f) in batches.iter().zip(friction) {
        let range = c.range();
        let range = range.start - base..range.end - base;
        let shape = Shape::of(c);
        if let Some(anchors) = measure {
            measure_batch::<L>(
                bodies,
                c,
                &shape,
                &mut points[range.clone()],
                &anchors[range.clone()],
            );
        }
        let points = &mut points[range];
        sweeps += solve_batch(bodies, c, &shape, points, f, inv_h, use_bias);
    }
    sweeps
}

/// Each point's separation now, from the bodies' motion since the step began.
#[inline(always)]
fn measure_batch<L: Lane>(
    bodies: &(impl BodyView + ?Sized),
    c: &ContactBatch,
    shape: &Shape<L>,
    point: &mut [PointLanes],
    anchor: &[AnchorLanes],
) {
    let (a, b) = (
        PoseLanes::<L>::gather(bodies, c.a),
        PoseLanes::<L>::gather(bodies, c.b),
    );
    // n·(q r) = (q⁻¹ n)·r: the normal turned back into each body's start-of-step frame
    // once, then a dot product a point (see `Anchoring::normal_images`).
    let n = shape.normal;
    let moved = n.dot(b.dp.sub(a.dp));
    let na = V3::select(L::load(c.turn[0]), a.dq.rotate_back(n), n);
    let nb = V3::select(L::load(c.turn[1]), b.dq.rotate_back(n), n);
    for (p, r) in point.iter_mut().zip(anchor) {
        let (ra, rb) = (r.ra.get(), r.rb.get());
        let adjusted = L::load(r.adjusted_separation);
        p.separation = (moved + nb.dot(rb) - na.dot(ra) + adjusted).store();
    }
}

#[inline(always)]
fn solve_batch<L: Lane>(
    bodies: &mut (impl BodyView + ?Sized),
    c: &ContactBatch,
    shape: &Shape<L>,
    point: &mut [PointLanes],
    f: &mut FrictionLanes,
    inv_h: L,
    use_bias: bool,
) -> u32 {
    let (zero, one) = (L::splat(0.0), L::splat(1.0));
    let (mut a, mut b) = (
        BodyLanes::<L>::gather(bodies, c.a),
        BodyLanes::<L>::gather(bodies, c.b),
    );
    let n = point.len();
    debug_assert!(n <= MAX_POINTS, "a batch holds at most MAX_POINTS points");
    let normal = shape.normal;
    let has = c.has.map(L::load);
    let (bias_rate, max_push) = (L::load(c.bias_rate), L::load(c.max_push));
    let (soft_mass, soft_impulse) = (L::load(c.mass_scale), L::load(c.impulse_scale));
    let approach_gain = L::load(c.approach_gain);
    // The normal sweeps: a lane stops as the scalar pass does (one sweep for a single
    // point, at most NORMAL_SWEEPS, none after a settled or capped one). Each reads the
    // points' normal velocities once, passes each point's impulse on to the points after
    // it through the couplings, and moves the bodies once at its end (as the scalar pass
    // does).
    let multi = has[1];
    let mut active = has[0];
    let mut sweeps = 0;
    for sweep in 0..NORMAL_SWEEPS {
        if sweep > 0 {
            active = active & multi;
        }
        if active.none() {
            break;
        }
        sweeps += 1;
        let mut vn = [zero; MAX_POINTS];
        for (v, p) in vn.iter_mut().zip(&*point) {
            *v = normal_velocity(&a, &b, normal, p);
        }
        let mut dls = [zero; MAX_POINTS];
        let (mut largest, mut total, mut capped) = (zero, zero, zero);
        for k in 0..n {
            let p = &mut point[k];
            let s = L::load(p.separation);
            let on = active & has[k];
            let speculative = gt(s, zero);
            let (bias, mass_scale, impulse_scale) = if use_bias {
                let soft = bias_rate * s;
                let cap = neg(max_push);
                capped = capped | (on & !speculative & lt(soft, cap));
                (
                    select(speculative, s * inv_h, max(soft, cap)),
                    select(speculative, one, soft_mass),
                    select(speculative, zero, soft_impulse),
                )
            } else {
                (select(speculative, s * inv_h, zero), one, zero)
            };
            let vn_k = vn[k];
            let (impulse, most) = (L::load(p.normal_impulse), L::load(p.max_normal_impulse));
            let lambda =
                neg(L::load(p.normal_mass)) * mass_scale * (vn_k + bias) - impulse_scale * impulse;
            let new = max(impulse + lambda, zero);
            // A point's first push of the step records its approach speed: after that
            // no lane needs it, so it is tested for before the clamp is paid.
            let first = on & eq(most, zero) & gt(new, zero);
            if first.any() {
                let prepared = L::load(p.relative_velocity);
                let approach = clamp(vn_k, prepared - approach_gain, prepared);
                p.relative_velocity = select(first, approach, prepared).store();
            }
            let dl = select(on, new - impulse, zero);
            p.normal_impulse = select(on, new, impulse).store();
            p.max_normal_impulse = select(on, max(most, new), most).store();
            dls[k] = dl;
            for j in k + 1..n {
                vn[j] = vn[j] + L::load(c.coupling[coupling_index(j, k)]) * dl;
            }
            largest = max(largest, dl.abs());
            total = total + select(on, new, zero);
        }
        apply_normals((&mut a, &mut b), shape, point, dls);
        let settled = capped | le(largest, L::splat(NORMAL_TOL) * total);
        active = active & !settled;
    }
    // Friction at the anchors (lanes of frictionless pairs do nothing): the disc, then
    // the twist.
    let friction = L::load(c.friction);
    let rubs = gt(friction, zero);
    let (mut total, mut moment) = (zero, zero);
    for p in &*point {
        let impulse = L::load(p.normal_impulse);
        total = total + impulse;
        moment = moment + impulse * L::load(p.twist_arm);
    }
    let tangents = normal.any_orthonormal_pair();
    let tangent = anchor_rows(c, &shape.inv_inertia);
    let vt0 = row_velocity(&a, &b, tangents.0, &tangent[0]);
    let vt1 = row_velocity(&a, &b, tangents.1, &tangent[1]);
    let [old0, old1] = f.tangent_impulse.map(L::load);
    let tangent_mass = L::load(c.tangent_mass);
    let limit = friction * total;
    let (free0, free1) = (old0 - tangent_mass * vt0, old1 - tangent_mass * vt1);
    let length_squared = free0 * free0 + free1 * free1;
    let over = gt(length_squared, limit * limit);
    let length = length_squared.sqrt();
    let new0 = select(over, limit * (free0 / length), free0);
    let new1 = select(over, limit * (free1 / length), free1);
    let finite = new0.is_finite() & new1.is_finite();
    let (new0, new1) = (select(finite, new0, zero), select(finite, new1, zero));
    let d = [
        select(rubs, new0 - old0, zero),
        select(rubs, new1 - old1, zero),
    ];
    f.tangent_impulse = [select(rubs, new0, old0), select(rubs, new1, old1)].map(L::store);
    apply_tangent(&mut a, &mut b, &tangents, &tangent, d);
    let twist_mass = L::load(c.twist_mass);
    let twists = rubs & gt(twist_mass, zero);
    if twists.any() {
        let limit = friction * moment;
        let old = L::load(f.twist_impulse);
        let vw = b.w.dot(normal) - a.w.dot(normal);
        let new = clamp(old - twist_mass * vw, neg(limit), limit);
        let new = select(new.is_finite(), new, zero);
        let d = select(twists, new - old, zero);
        f.twist_impulse = select(twists, new, old).store();
        apply_twist(&mut a, &mut b, shape, d);
    }
    a.scatter(bodies, c.a, c.moved[0]);
    b.scatter(bodies, c.b, c.moved[1]);
    sweeps
}
