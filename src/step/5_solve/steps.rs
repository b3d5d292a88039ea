//! The contact passes over a step's [`SolveStep`]s on one thread: batches side by side in
//! lanes, the rest by the scalar pass (`split.rs` shares them between two).

use std::ops::Range;

use super::iterate::{solve_listed, warm_start_listed};
use super::wide::{solve_batches, warm_start_batches};
use crate::world::{
    ContactBatches, ContactConstraint, RollingArms, SolveStep, SolveWork, SolverBody,
};

/// Warm starts the contacts of `steps` (see [`SolveStep`]) on this thread (`split` has
/// the same on two).
pub(crate) fn warm_start_steps(
    bodies: &mut [SolverBody],
    constraints: &[ContactConstraint],
    batches: &ContactBatches,
    steps: Range<usize>,
) {
    for step in &batches.steps[steps] {
        match step {
            SolveStep::Batches(r) => {
                let points = &batches.points[batches.points_of(r)];
                let friction = &batches.friction[r.clone()];
                warm_start_batches(bodies, &batches.batches[r.clone()], points, friction);
            }
            SolveStep::Scalar(c) => warm_start_listed(bodies, constraints, &[*c]),
        }
    }
}

/// What one contact pass is: its substep, whether it is soft with bias (Solve) or rigid
/// (Relax), and whether the bodies moved since the separations were last measured (see
/// [`solve_batches`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pass {
    /// Substep, s.
    pub h: f32,
    pub use_bias: bool,
    pub measure: bool,
}

/// One pass of the contacts of `steps` (see [`SolveStep`]) on this thread (`split` has
/// the same on two). Returns the work it did over the batches.
pub(crate) fn solve_steps(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    batches: &mut ContactBatches,
    steps: Range<usize>,
    arms: &[RollingArms],
    pass: Pass,
) -> SolveWork {
    let Pass {
        h,
        use_bias,
        measure,
    } = pass;
    let mut work = SolveWork::default();
    for step in &batches.steps[steps] {
        match step {
            SolveStep::Batches(r) => {
                let range = batches.points_of(r);
                let anchors = measure.then(|| &batches.anchors[range.clone()]);
                let points = &mut batches.points[range];
                let friction = &mut batches.friction[r.clone()];
                let list = &batches.batches[r.clone()];
                let sweeps = solve_batches(bodies, list, points, friction, h, use_bias, anchors);
                work.sweeps += u64::from(sweeps);
                work.batches += list.len() as u64;
            }
            SolveStep::Scalar(c) => {
                solve_listed(bodies, constraints, &[*c], arms, h, (use_bias, measure));
            }
        }
    }
    work
}
