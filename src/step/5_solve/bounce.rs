//! Restitution over a step's contacts where they are solved: the batches' contacts side
//! by side in their lanes, the scalar ones one at a time, in pass order. Each lane does
//! what [`apply_restitution`] does for one contact, point by point, in the same order,
//! so the result is the bits of `apply_restitution` over every constraint in pass order
//! (contact order where levels are wide, see [`ContactBatches`]). The batched contacts then need not be written out as constraints when a
//! step bounces (rain wrote, reread and stored 5,500 of them a step for this alone).

#[cfg(target_arch = "x86_64")]
use crate::math::lanes::avx::Y8;
use crate::math::lanes::{F8, Lane, eq, gt, max, neg, select};
#[cfg(target_arch = "x86_64")]
use crate::math::lanes::{three_operand, wide_registers};
use crate::world::{
    BodyView, ContactBatch, ContactBatches, ContactConstraint, PointLanes, SolveStep, SolverBody,
};

use super::iterate::apply_restitution;
use super::wide::{BodyLanes, Shape, dispatch, normal_velocity};

/// Restitution over the contacts of `batches`' pass (all its steps), the batched ones in
/// their lanes and the scalar ones in `constraints`: points that were approaching faster
/// than `threshold` (m/s) when they first pushed get their normal velocity driven to −e
/// times that approach (see [`apply_restitution`]).
pub(crate) fn restitution_steps(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    batches: &mut ContactBatches,
    threshold: f32,
) {
    for step in &batches.steps {
        match step {
            SolveStep::Batches(r) => {
                let range = batches.points_of(r);
                let points = &mut batches.points[range];
                restitution_batches(bodies, &batches.batches[r.clone()], points, threshold);
            }
            SolveStep::Scalar(c) => {
                let c = *c as usize;
                apply_restitution(bodies, &mut constraints[c..c + 1], threshold);
            }
        }
    }
}

dispatch! {
    /// [`apply_restitution`] over the batches. `points` starts at the first batch's.
    pub fn restitution_batches / restitution_wide / restitution_vex => restitution_any(
        batches: &[ContactBatch],
        points: &mut [PointLanes],
        threshold: f32,
    ) -> ()
}

#[inline(always)]
fn restitution_any<L: Lane>(
    bodies: &mut (impl BodyView + ?Sized),
    batches: &[ContactBatch],
    points: &mut [PointLanes],
    threshold: f32,
) {
    let zero = L::splat(0.0);
    let slowest = L::splat(-threshold);
    let base = batches.first().map_or(0, |b| b.first as usize);
    for c in batches {
        // A contact that cannot bounce is not even loaded (as the scalar pass skips it).
        let e = L::load(c.restitution);
        let bounces = gt(e, zero);
        if bounces.none() {
            continue;
        }
        let range = c.range();
        let point = &mut points[range.start - base..range.end - base];
        let (mut a, mut b) = (
            BodyLanes::<L>::gather(bodies, c.a),
            BodyLanes::<L>::gather(bodies, c.b),
        );
        let shape = Shape::of(c);
        let [ia, ib] = shape.inv_inertia;
        for (p, has) in point.iter_mut().zip(c.has) {
            // As the scalar pass: skipped unless it approached at least `threshold`
            // fast (a NaN approach is not skipped) and pushed at some point.
            let approach = L::load(p.relative_velocity);
            let most = L::load(p.max_normal_impulse);
            let on = bounces & L::load(has) & !gt(approach, slowest) & !eq(most, zero);
            if on.none() {
                continue;
            }
            let vn = normal_velocity(&a, &b, shape.normal, p);
            let impulse = L::load(p.normal_impulse);
            let lambda = neg(L::load(p.normal_mass)) * (vn + e * approach);
            let new = max(impulse + lambda, zero);
            let dl = select(on, new - impulse, zero);
            p.normal_impulse = select(on, new, impulse).store();
            p.max_normal_impulse = select(on, max(most, new), most).store();
            // Point by point, as `apply_normal`: the inverse inertia times r × n, then dl.
            let linear = shape.normal.scale(dl);
            a.push(linear, p.normal_ra.get().scale(ia).scale(dl), false);
            b.push(linear, p.normal_rb.get().scale(ib).scale(dl), true);
        }
        a.scatter(bodies, c.a, c.moved[0]);
        b.scatter(bodies, c.b, c.moved[1]);
    }
}
