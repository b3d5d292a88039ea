//! The constraint graph: the contacts of a step coloured so that no two contacts of a
//! colour share a body the solver moves, and each colour cut into [`ContactBatch`]es of
//! [`LANES`] contacts solved side by side (Box2D v3's recipe, `constraint_graph.c`).
//! The colours and the contacts inside them follow the contact order, never threads.

use bevy::prelude::*;

use super::{ContactBatch, ContactConstraint, PointLanes, STATIC, SolverBody};

/// Contacts solved side by side in one batch (SSE2's four f32 lanes).
pub(crate) const LANES: usize = 4;
/// A batch lane without a contact.
pub(crate) const NO_CONTACT: u32 = u32::MAX;
/// Colours tried before a contact goes to the overflow (a body's colours fit a `u64`).
pub(crate) const COLOURS: usize = 64;

/// This step's colouring of the contact constraints.
#[derive(Default, Debug)]
pub(crate) struct ConstraintGraph {
    /// The batches: first those of the contacts with fixed colliders, colour after
    /// colour, then the others'; each colour's contacts in contact order.
    pub batches: Vec<ContactBatch>,
    /// The batches' points, lane by lane ([`ContactBatch::range`]).
    pub points: Vec<PointLanes>,
    /// How many batches, at the front, hold the contacts with fixed colliders.
    pub fixed_batches: usize,
    /// Contacts solved one at a time after the batches, in contact order: those with a
    /// rolling motion, with rows refreshed every substep (a turning anisotropic body) or
    /// impulses reported, and those whose bodies had no colour left in common. Which
    /// contacts go here depends on each contact alone, never on the others in the scene.
    pub overflow: Vec<u32>,
    /// Colours in use.
    pub colours: usize,
    /// Per body: the colours its contacts took (scratch).
    used: Vec<u64>,
    /// Per colour: its contacts (scratch).
    buckets: Vec<Vec<u32>>,
}

/// Whether the solver moves body `i`: a dynamic body (a kinematic one has no inverse
/// mass or inertia, so no contact changes its velocity and it may sit in many contacts
/// of one colour, as the static body does).
#[inline]
pub(crate) fn moved_by_contacts(bodies: &[SolverBody], i: u32) -> bool {
    i != STATIC && {
        let b = &bodies[i as usize];
        b.inv_mass > 0.0 || b.inv_inertia != Mat3::ZERO
    }
}

impl ConstraintGraph {
    /// Colours `constraints`, whose first `fixed` are the contacts with fixed colliders:
    /// each contact, in order, takes the lowest colour that neither of its moved bodies
    /// has yet. Those first `fixed` are coloured on their own and go first, so that a
    /// pass still works up from the ground and the solver can run them again at its end.
    pub(crate) fn build(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        fixed: usize,
    ) {
        self.batches.clear();
        self.points.clear();
        self.overflow.clear();
        self.colours = 0;
        self.colour(constraints, bodies, 0..fixed);
        self.fixed_batches = self.batches.len();
        self.colour(constraints, bodies, fixed..constraints.len());
        self.overflow.sort_unstable();
        debug_assert!(self.is_valid(constraints, bodies), "a batch shares a body");
    }

    fn colour(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        range: std::ops::Range<usize>,
    ) {
        self.used.clear();
        self.used.resize(bodies.len(), 0);
        for b in &mut self.buckets {
            b.clear();
        }
        let moved = |i: u32| moved_by_contacts(bodies, i).then_some(i as usize);
        for ci in range {
            let c = &constraints[ci];
            let (a, b) = (moved(c.a), moved(c.b));
            let taken = a.map_or(0, |a| self.used[a]) | b.map_or(0, |b| self.used[b]);
            let colour = (!taken).trailing_zeros() as usize;
            // Rows refreshed and impulses summed every substep stay in the constraints.
            let scalar = c.anchoring.rolls() || c.refresh || c.report;
            if scalar || colour >= COLOURS {
                self.overflow.push(ci as u32);
                continue;
            }
            for i in [a, b].into_iter().flatten() {
                self.used[i] |= 1 << colour;
            }
            if self.buckets.len() <= colour {
                self.buckets.resize_with(colour + 1, Vec::new);
            }
            self.buckets[colour].push(ci as u32);
        }
        self.colours += self.buckets.iter().filter(|b| !b.is_empty()).count();
        for bucket in &self.buckets {
            for chunk in bucket.chunks(LANES) {
                let mut lanes = [NO_CONTACT; LANES];
                lanes[..chunk.len()].copy_from_slice(chunk);
                let batch = ContactBatch::new(constraints, bodies, lanes, &mut self.points);
                self.batches.push(batch);
            }
        }
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
        self.overflow.iter().for_each(|&c| seen[c as usize] += 1);
        seen.iter().all(|&s| s == 1)
    }
}
