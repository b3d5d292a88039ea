//! The contact passes over the batches (see [`ContactBatches`](crate::world::ContactBatches)):
//! four contacts that share no moved body, solved side by side in `f32x4` lanes. Each lane does exactly what
//! [`iterate`](super::iterate) does for one contact, in the same order (the scalar pass
//! stays as the reference these are tested against, bit for bit). A batch holds its
//! contacts lane by lane ([`ContactBatch`]) and gathers its bodies' velocities.

#[cfg(target_arch = "x86_64")]
use crate::math::lanes::three_operand;
use crate::math::lanes::{F4, Q4, V3, clamp, eq, gt, lanes, le, lt, max, neg, select};
use crate::world::{
    AnchorLanes, BodyView, ContactBatch, FrictionLanes, LANES, MAX_POINTS, PointLanes,
    coupling_index,
};

use super::iterate::{NORMAL_SWEEPS, NORMAL_TOL};

/// One side's bodies of a batch: what the passes change and read.
struct BodyLanes {
    v: V3,
    w: V3,
    inv_mass: F4,
}

/// One side's bodies' motion since the step began: what the separations are measured
/// from.
struct PoseLanes {
    dp: V3,
    dq: Q4,
}

impl PoseLanes {
    #[inline(always)]
    fn gather(bodies: &(impl BodyView + ?Sized), index: [u32; LANES]) -> Self {
        let (b0, b1) = (bodies.at(index[0]), bodies.at(index[1]));
        let (b2, b3) = (bodies.at(index[2]), bodies.at(index[3]));
        Self {
            dp: V3::gather([b0.dp, b1.dp, b2.dp, b3.dp]),
            dq: Q4::gather([b0.dq, b1.dq, b2.dq, b3.dq]),
        }
    }
}

impl BodyLanes {
    #[inline(always)]
    fn gather(bodies: &(impl BodyView + ?Sized), index: [u32; LANES]) -> Self {
        let (b0, b1) = (bodies.at(index[0]), bodies.at(index[1]));
        let (b2, b3) = (bodies.at(index[2]), bodies.at(index[3]));
        Self {
            v: V3::gather([b0.v, b1.v, b2.v, b3.v]),
            w: V3::gather([b0.w, b1.w, b2.w, b3.w]),
            inv_mass: lanes([b0.inv_mass, b1.inv_mass, b2.inv_mass, b3.inv_mass]),
        }
    }

    /// Velocities back to the bodies the contacts move.
    #[inline(always)]
    fn scatter(
        &self,
        bodies: &mut (impl BodyView + ?Sized),
        index: [u32; LANES],
        moved: [bool; LANES],
    ) {
        for l in 0..LANES {
            if moved[l] {
                bodies.set_velocity(index[l], self.v.lane(l), self.w.lane(l));
            }
        }
    }

    /// Impulse `p` with its angular part on this side: +p on body b, −p on body a.
    #[inline(always)]
    fn push(&mut self, p: V3, angular: V3, on_b: bool) {
        if on_b {
            self.v = self.v.add(p.scale(self.inv_mass));
            self.w = self.w.add(angular);
        } else {
            self.v = self.v.sub(p.scale(self.inv_mass));
            self.w = self.w.sub(angular);
        }
    }
}

/// The angular parts of one row along `d` at a point, lane by lane, as
/// [`AngularRow::new`](crate::world::AngularRow::new) makes them: r × d for each body and
/// their images under its inverse inertia (a multiple of the identity in a batch: the
/// same bits as the matrix product, but for the sign of a zero).
#[derive(Clone, Copy)]
struct RowLanes {
    ra: V3,
    rb: V3,
    ia: V3,
    ib: V3,
}

impl RowLanes {
    /// The row of lever arms `ra` (r × d) and `rb`.
    #[inline(always)]
    fn of(inv_inertia: &[F4; 2], ra: V3, rb: V3) -> Self {
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
fn row_velocity(a: &BodyLanes, b: &BodyLanes, d: V3, row: &RowLanes) -> F4 {
    d.dot(b.v.sub(a.v)) - a.w.dot(row.ra) + b.w.dot(row.rb)
}

/// The normal velocity of b relative to a at a point, from its prepared lever arms (the
/// scalar pass's `row_velocity`, lane by lane).
#[inline(always)]
fn normal_velocity(a: &BodyLanes, b: &BodyLanes, n: V3, p: &PointLanes) -> F4 {
    n.dot(b.v.sub(a.v)) - a.w.dot(p.normal_ra) + b.w.dot(p.normal_rb)
}

/// Normal impulses `dl` at a batch's points, all at once (as `iterate::apply_normals`):
/// the warm start's, and each normal sweep's.
#[inline(always)]
fn apply_normals(
    (a, b): (&mut BodyLanes, &mut BodyLanes),
    c: &ContactBatch,
    point: &[PointLanes],
    dl: impl IntoIterator<Item = F4>,
) {
    let (mut total, mut ra, mut rb) = (F4::ZERO, V3::ZERO, V3::ZERO);
    for (p, dl) in point.iter().zip(dl) {
        total = total + dl;
        ra = ra.add(p.normal_ra.scale(dl));
        rb = rb.add(p.normal_rb.scale(dl));
    }
    let p = c.normal.scale(total);
    a.push(p, ra.scale(c.inv_inertia[0]), false);
    b.push(p, rb.scale(c.inv_inertia[1]), true);
}

/// A twist impulse `d` about the normal `n`: +d on b, −d on a.
#[inline(always)]
fn apply_twist(a: &mut BodyLanes, b: &mut BodyLanes, inv_inertia: &[F4; 2], n: V3, d: F4) {
    a.w = a.w.sub(n.scale(inv_inertia[0]).scale(d));
    b.w = b.w.add(n.scale(inv_inertia[1]).scale(d));
}

/// The tangent rows at a batch's friction anchors.
#[inline(always)]
fn anchor_rows(c: &ContactBatch) -> [RowLanes; 2] {
    [
        RowLanes::of(&c.inv_inertia, c.tangent_ra[0], c.tangent_rb[0]),
        RowLanes::of(&c.inv_inertia, c.tangent_ra[1], c.tangent_rb[1]),
    ]
}

/// A friction impulse `d` along the two tangents at the friction anchor.
#[inline(always)]
fn apply_tangent(
    a: &mut BodyLanes,
    b: &mut BodyLanes,
    t: &[V3; 2],
    rows: &[RowLanes; 2],
    d: [F4; 2],
) {
    let p = t[0].scale(d[0]).add(t[1].scale(d[1]));
    a.push(p, rows[0].ia.scale(d[0]).add(rows[1].ia.scale(d[1])), false);
    b.push(p, rows[0].ib.scale(d[0]).add(rows[1].ib.scale(d[1])), true);
}

/// [`warm_start_listed`](super::iterate::warm_start_listed) over the batches.
/// `points` starts at the first batch's; `friction` holds the batches' own.
pub fn warm_start_batches(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &[PointLanes],
    friction: &[FrictionLanes],
) {
    #[cfg(target_arch = "x86_64")]
    if wide_registers() {
        // SAFETY: the CPU has the features (checked just above).
        return unsafe { warm_start_wide(bodies, batches, points, friction) };
    }
    #[cfg(target_arch = "x86_64")]
    if three_operand() {
        // SAFETY: the CPU has the features (checked just above).
        return unsafe { warm_start_vex(bodies, batches, points, friction) };
    }
    warm_start_any(bodies, batches, points, friction)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl")]
fn warm_start_wide(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &[PointLanes],
    friction: &[FrictionLanes],
) {
    warm_start_any(bodies, batches, points, friction)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
fn warm_start_vex(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &[PointLanes],
    friction: &[FrictionLanes],
) {
    warm_start_any(bodies, batches, points, friction)
}

#[inline(always)]
fn warm_start_any(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &[PointLanes],
    friction: &[FrictionLanes],
) {
    let base = batches.first().map_or(0, |b| b.first as usize);
    for (c, f) in batches.iter().zip(friction) {
        let (mut a, mut b) = (
            BodyLanes::gather(bodies, c.a),
            BodyLanes::gather(bodies, c.b),
        );
        let range = c.range();
        let point = &points[range.start - base..range.end - base];
        let impulses = point.iter().map(|p| p.normal_impulse);
        apply_normals((&mut a, &mut b), c, point, impulses);
        let tangents = c.tangents();
        let tangent = anchor_rows(c);
        apply_tangent(&mut a, &mut b, &tangents, &tangent, f.tangent_impulse);
        apply_twist(&mut a, &mut b, &c.inv_inertia, c.normal, f.twist_impulse);
        a.scatter(bodies, c.a, c.moved[0]);
        b.scatter(bodies, c.b, c.moved[1]);
    }
}

/// [`solve_listed`](super::iterate::solve_listed) over the batches (contacts without a
/// rolling motion). `points` starts at the first batch's. `measure`, the points'
/// anchors (the same index as `points`): the bodies have moved since the last pass, so
/// measure the separations again (the scalar pass measures them in every pass;
/// positions move only between substeps, so a stage's later passes, and the fixed
/// contacts' second solve, reuse the same bits). `friction` holds the batches' own.
/// Returns the sweeps over the batches' normal rows, all batches together (each batch
/// sweeps at least once).
pub fn solve_batches(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    friction: &mut [FrictionLanes],
    h: f32,
    use_bias: bool,
    measure: Option<&[AnchorLanes]>,
) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if wide_registers() {
        // SAFETY: the CPU has the features (checked just above).
        return unsafe { solve_wide(bodies, batches, points, friction, h, use_bias, measure) };
    }
    #[cfg(target_arch = "x86_64")]
    if three_operand() {
        // SAFETY: the CPU has the features (checked just above).
        return unsafe { solve_vex(bodies, batches, points, friction, h, use_bias, measure) };
    }
    solve_any(bodies, batches, points, friction, h, use_bias, measure)
}

/// The CPU has AVX-512's 32 vector registers for 128-bit lanes: the passes are compiled
/// twice, and on such a CPU run the copy that may use them (fewer spills; the same
/// operations, so the same bits). Checked once a pass; the answer is cached by std.
#[cfg(target_arch = "x86_64")]
#[inline]
fn wide_registers() -> bool {
    #[cfg(test)]
    if crate::math::lanes::PLAIN_ONLY.get() {
        return false;
    }
    std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx512vl")
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl")]
fn solve_wide(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    friction: &mut [FrictionLanes],
    h: f32,
    use_bias: bool,
    measure: Option<&[AnchorLanes]>,
) -> u32 {
    solve_any(bodies, batches, points, friction, h, use_bias, measure)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
fn solve_vex(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    friction: &mut [FrictionLanes],
    h: f32,
    use_bias: bool,
    measure: Option<&[AnchorLanes]>,
) -> u32 {
    solve_any(bodies, batches, points, friction, h, use_bias, measure)
}

#[inline(always)]
fn solve_any(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    friction: &mut [FrictionLanes],
    h: f32,
    use_bias: bool,
    measure: Option<&[AnchorLanes]>,
) -> u32 {
    let inv_h = F4::splat(1.0 / h);
    let base = batches.first().map_or(0, |b| b.first as usize);
    let mut sweeps = 0;
    for (c, f) in batches.iter().zip(friction) {
        let range = c.range();
        let range = range.start - base..range.end - base;
        if let Some(anchors) = measure {
            measure_batch(
                bodies,
                c,
                &mut points[range.clone()],
                &anchors[range.clone()],
            );
        }
        let points = &mut points[range];
        sweeps += solve_batch(bodies, c, points, f, inv_h, use_bias);
    }
    sweeps
}

/// Each point's separation now, from the bodies' motion since the step began.
#[inline(always)]
fn measure_batch(
    bodies: &(impl BodyView + ?Sized),
    c: &ContactBatch,
    point: &mut [PointLanes],
    anchor: &[AnchorLanes],
) {
    let (a, b) = (
        PoseLanes::gather(bodies, c.a),
        PoseLanes::gather(bodies, c.b),
    );
    // n·(q r) = (q⁻¹ n)·r: the normal turned back into each body's start-of-step frame
    // once, then a dot product a point (see `Anchoring::normal_images`).
    let moved = c.normal.dot(b.dp.sub(a.dp));
    let na = V3::select(c.turn[0], a.dq.rotate_back(c.normal), c.normal);
    let nb = V3::select(c.turn[1], b.dq.rotate_back(c.normal), c.normal);
    for (p, r) in point.iter_mut().zip(anchor) {
        p.separation = moved + nb.dot(r.rb) - na.dot(r.ra) + r.adjusted_separation;
    }
}

#[inline(always)]
fn solve_batch(
    bodies: &mut (impl BodyView + ?Sized),
    c: &ContactBatch,
    point: &mut [PointLanes],
    f: &mut FrictionLanes,
    inv_h: F4,
    use_bias: bool,
) -> u32 {
    let (zero, one) = (F4::ZERO, F4::ONE);
    let (mut a, mut b) = (
        BodyLanes::gather(bodies, c.a),
        BodyLanes::gather(bodies, c.b),
    );
    let n = point.len();
    debug_assert!(n <= MAX_POINTS, "a batch holds at most MAX_POINTS points");
    // The normal sweeps: a lane stops as the scalar pass does (one sweep for a single
    // point, at most NORMAL_SWEEPS, none after a settled or capped one). Each reads the
    // points' normal velocities once, passes each point's impulse on to the points after
    // it through the couplings, and moves the bodies once at its end (as the scalar pass
    // does).
    let multi = c.has[1];
    let mut active = c.has[0];
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
            *v = normal_velocity(&a, &b, c.normal, p);
        }
        let mut dls = [zero; MAX_POINTS];
        let (mut largest, mut total, mut capped) = (zero, zero, zero);
        for k in 0..n {
            let p = &mut point[k];
            let s = p.separation;
            let on = active & c.has[k];
            let speculative = gt(s, zero);
            let (bias, mass_scale, impulse_scale) = if use_bias {
                let soft = c.bias_rate * s;
                let cap = neg(c.max_push);
                capped = capped | (on & !speculative & lt(soft, cap));
                (
                    select(speculative, s * inv_h, max(soft, cap)),
                    select(speculative, one, c.mass_scale),
                    select(speculative, zero, c.impulse_scale),
                )
            } else {
                (select(speculative, s * inv_h, zero), one, zero)
            };
            let vn_k = vn[k];
            let lambda =
                neg(p.normal_mass) * mass_scale * (vn_k + bias) - impulse_scale * p.normal_impulse;
            let new = max(p.normal_impulse + lambda, zero);
            // A point's first push of the step records its approach speed: after that
            // no lane needs it, so it is tested for before the clamp is paid.
            let first = on & eq(p.max_normal_impulse, zero) & gt(new, zero);
            if first.any() {
                let prepared = p.relative_velocity;
                let approach = clamp(vn_k, prepared - c.approach_gain, prepared);
                p.relative_velocity = select(first, approach, prepared);
            }
            let dl = select(on, new - p.normal_impulse, zero);
            p.normal_impulse = select(on, new, p.normal_impulse);
            p.max_normal_impulse = select(on, max(p.max_normal_impulse, new), p.max_normal_impulse);
            dls[k] = dl;
            for j in k + 1..n {
                vn[j] = vn[j] + c.coupling[coupling_index(j, k)] * dl;
            }
            largest = max(largest, dl.abs());
            total = total + select(on, new, zero);
        }
        apply_normals((&mut a, &mut b), c, point, dls);
        let settled = capped | le(largest, F4::splat(NORMAL_TOL) * total);
        active = active & !settled;
    }
    // Friction at the anchors (lanes of frictionless pairs do nothing): the disc, then
    // the twist.
    let rubs = gt(c.friction, zero);
    let (mut total, mut moment) = (zero, zero);
    for p in &*point {
        total = total + p.normal_impulse;
        moment = moment + p.normal_impulse * p.twist_arm;
    }
    let tangents = c.tangents();
    let tangent = anchor_rows(c);
    let vt0 = row_velocity(&a, &b, tangents[0], &tangent[0]);
    let vt1 = row_velocity(&a, &b, tangents[1], &tangent[1]);
    let [old0, old1] = f.tangent_impulse;
    let limit = c.friction * total;
    let (free0, free1) = (old0 - c.tangent_mass * vt0, old1 - c.tangent_mass * vt1);
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
    f.tangent_impulse = [select(rubs, new0, old0), select(rubs, new1, old1)];
    apply_tangent(&mut a, &mut b, &tangents, &tangent, d);
    let twists = rubs & gt(c.twist_mass, zero);
    if twists.any() {
        let limit = c.friction * moment;
        let old = f.twist_impulse;
        let vw = b.w.dot(c.normal) - a.w.dot(c.normal);
        let new = clamp(old - c.twist_mass * vw, neg(limit), limit);
        let new = select(new.is_finite(), new, zero);
        let d = select(twists, new - old, zero);
        f.twist_impulse = select(twists, new, old);
        apply_twist(&mut a, &mut b, &c.inv_inertia, c.normal, d);
    }
    a.scatter(bodies, c.a, c.moved[0]);
    b.scatter(bodies, c.b, c.moved[1]);
    sweeps
}
