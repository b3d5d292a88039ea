//! Batching: the contacts of a step packed into [`ContactBatch`]es of [`LANES`]
//! contacts that share no moved body, solved side by side, without changing what the
//! scalar Gauss–Seidel pass computes. Every body still sees its contacts in contact order:
//! a contact joins a batch only if no contact before it that is still waiting shares one
//! of its bodies. Contacts apart in the order but not in their bodies (the rows of a
//! pyramid) then share batches; a body's contacts stay in sequence. The result is the
//! scalar pass's bit for bit (the reordered updates touch different bodies), so the
//! order that makes stacks converge (fixed contacts first, then contact order) stays.
//!
//! (Box2D v3 colours its contacts instead, which also lets threads split a colour; that
//! order propagates a stack's load one level per colour, and our 100-high flat pyramid's
//! top cube slid 2.4 m off in 220 steps, against 0.25 m in contact order.)

use std::ops::Range;

use bevy::prelude::*;

use super::{ContactBatch, ContactConstraint, PointLanes, STATIC, SolverBody};

/// Contacts solved side by side in one batch (SSE2's four f32 lanes).
pub(crate) const LANES: usize = 4;
/// A batch lane without a contact.
pub(crate) const NO_CONTACT: u32 = u32::MAX;
/// Waiting contacts a batch may look ahead over for independent ones. Measured on the
/// 5,050-cube flat pyramid, whose rows chain their cubes' contacts (solve ms, interleaved
/// runs): 64 → 61–72, 256 → 47–52, the scalar pass 68–82.
pub(crate) const WINDOW: usize = 256;

/// One step of a pass, in order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SolveStep {
    /// Batches solved lane by lane, one after another.
    Batches(Range<usize>),
    /// One contact solved by the scalar pass: one with a rolling motion, with rows
    /// refreshed every substep (a turning anisotropic body) or impulses reported.
    Scalar(u32),
}

/// This step's contacts as batches and scalar contacts, in solving order.
#[derive(Default, Debug)]
pub(crate) struct ContactBatches {
    /// The batches.
    pub batches: Vec<ContactBatch>,
    /// The batches' points, lane by lane ([`ContactBatch::range`]).
    pub points: Vec<PointLanes>,
    /// The pass: batches and scalar contacts, the contacts with fixed colliders first.
    pub steps: Vec<SolveStep>,
    /// How many steps, at the front, are those of the contacts with fixed colliders
    /// (which each pass runs again at its end).
    pub fixed_steps: usize,
    /// Per body: the last batch that took it or that it waits for (scratch).
    stamp: Vec<u32>,
    /// Per contact of the part being packed: the next waiting one (scratch).
    next: Vec<u32>,
}

/// Whether the solver moves body `i`: a dynamic body (a kinematic one has no inverse
/// mass or inertia, so no contact changes its velocity, and like the static body it may
/// sit in every lane of a batch).
#[inline]
pub(crate) fn moved_by_contacts(bodies: &[SolverBody], i: u32) -> bool {
    i != STATIC && {
        let b = &bodies[i as usize];
        b.inv_mass > 0.0 || b.inv_inertia != Mat3::ZERO
    }
}

/// Contacts the scalar pass solves (see [`SolveStep::Scalar`]).
fn scalar_only(c: &ContactConstraint) -> bool {
    c.anchoring.rolls() || c.refresh || c.report
}

impl ContactBatches {
    /// Packs `constraints`, whose first `fixed` are the contacts with fixed colliders
    /// (packed on their own, so that a pass can run them again).
    pub(crate) fn build(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        fixed: usize,
    ) {
        self.batches.clear();
        self.points.clear();
        self.steps.clear();
        self.stamp.clear();
        self.stamp.resize(bodies.len(), 0);
        self.pack(constraints, bodies, 0..fixed);
        self.fixed_steps = self.steps.len();
        self.pack(constraints, bodies, fixed..constraints.len());
        debug_assert!(self.is_valid(constraints, bodies), "a batch shares a body");
    }

    fn pack(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        range: Range<usize>,
    ) {
        let moved = |i: u32| moved_by_contacts(bodies, i).then_some(i as usize);
        let (start, end, first_step) = (range.start, range.end, self.steps.len());
        // The waiting contacts as a list (each its successor's index, `end` last), so a
        // batch's look-ahead counts waiting contacts only.
        self.next.clear();
        self.next.extend(start as u32 + 1..=end as u32);
        let mut head = start;
        while head < end {
            if scalar_only(&constraints[head]) {
                self.steps.push(SolveStep::Scalar(head as u32));
                head = self.next[head - start] as usize;
                continue;
            }
            head = self.pack_batch(constraints, bodies, start, head, &moved);
            // Runs of batches grow within a part only (the fixed part ends one).
            let index = self.batches.len() - 1;
            let open = self.steps.len() > first_step;
            match self.steps.last_mut() {
                Some(SolveStep::Batches(r)) if open && r.end == index => r.end += 1,
                _ => self.steps.push(SolveStep::Batches(index..index + 1)),
            }
        }
    }

    /// One batch from the waiting contacts from `head` on (the first always joins);
    /// returns the new first waiting contact.
    fn pack_batch(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        start: usize,
        mut head: usize,
        moved: &impl Fn(u32) -> Option<usize>,
    ) -> usize {
        // Stamps: `id` for a body this batch takes, `id + 1` for one that a waiting
        // contact before holds (that contact keeps its turn on it); older stamps are
        // smaller, so nothing is cleared between batches.
        let id = 2 * (self.batches.len() as u32 + 1);
        let end = start + self.next.len();
        let (mut lanes, mut n) = ([NO_CONTACT; LANES], 0);
        let (mut k, mut before, mut looked) = (head, None::<usize>, 0);
        while k < end && looked < WINDOW && n < LANES {
            let after = self.next[k - start] as usize;
            let c = &constraints[k];
            let sides = [moved(c.a), moved(c.b)];
            if scalar_only(c) || sides.iter().flatten().any(|&i| self.stamp[i] >= id) {
                for i in sides.into_iter().flatten() {
                    self.stamp[i] = self.stamp[i].max(id + 1);
                }
                before = Some(k);
            } else {
                for i in sides.into_iter().flatten() {
                    self.stamp[i] = id;
                }
                lanes[n] = k as u32;
                n += 1;
                match before {
                    None => head = after,
                    Some(b) => self.next[b - start] = after as u32,
                }
            }
            (k, looked) = (after, looked + 1);
        }
        let batch = ContactBatch::new(constraints, bodies, lanes, &mut self.points);
        self.batches.push(batch);
        head
    }

    /// The batches' points, for a range of batches.
    pub(crate) fn points_of(&self, batches: &Range<usize>) -> Range<usize> {
        let first = self.batches[batches.start].first as usize;
        first..self.batches[batches.end - 1].range().end
    }

    /// The batches' accumulated impulses back into the constraints.
    pub(crate) fn write_back(&self, constraints: &mut [ContactConstraint]) {
        for b in &self.batches {
            b.write_back(&self.points, constraints);
        }
    }

    /// The invariant the lanes rely on: no two contacts of a batch share a moved body,
    /// and every contact is solved exactly once.
    pub(crate) fn is_valid(
        &self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
    ) -> bool {
        let mut seen = vec![0u8; constraints.len()];
        for batch in &self.batches {
            let lanes = batch.contact.iter().filter(|&&c| c != NO_CONTACT);
            let mut moved: Vec<u32> = lanes
                .clone()
                .flat_map(|&c| [constraints[c as usize].a, constraints[c as usize].b])
                .filter(|&i| moved_by_contacts(bodies, i))
                .collect();
            let n = moved.len();
            moved.sort_unstable();
            moved.dedup();
            if moved.len() != n {
                return false;
            }
            lanes.for_each(|&c| seen[c as usize] += 1);
        }
        for step in &self.steps {
            if let SolveStep::Scalar(c) = step {
                seen[*c as usize] += 1;
            }
        }
        seen.iter().all(|&s| s == 1)
    }
}
