//! Batching: the contacts of a step packed into [`ContactBatch`]es of [`LANES`]
//! contacts that share no moved body, solved side by side. Contacts go by levels, a
//! contact's level one more than that of the last contact before it on either of its
//! bodies, and a level's contacts share no body. A contact's result depends only on its
//! two bodies as the contacts before it on them left them, so where levels are wide,
//! every body still meets its contacts in contact order, and the batches compute the
//! scalar Gauss–Seidel pass's bits: the order that makes stacks converge (fixed contacts
//! first, then contact order) stays what the physics sees.
//!
//! A run of levels too narrow for a batch (a chain or a tower: one contact a level) is
//! coloured instead ([`ContactBatches::colour`]): there the pass order is its own, and
//! the batches compute the scalar pass's bits in pass order. (Box2D v3 colours all its
//! contacts, which also lets threads split a colour; that order propagates a stack's
//! load one level per colour, and our 100-high flat pyramid's top cube slid 2.4 m off in
//! 220 steps, against 0.25 m in contact order. A run of one contact a level is a chain,
//! for which red–black Gauss–Seidel converges as fast as in order.)

use std::ops::Range;

use bevy::prelude::*;

use crate::math::lanes::three_operand_copy;

use super::{
    AnchorLanes, ContactBatch, ContactConstraint, FrictionLanes, PointLanes, STATIC, SolverBody,
    body,
};

/// Contacts solved side by side in one batch (an AVX register's eight f32 lanes).
pub(crate) const LANES: usize = crate::math::lanes::WIDTH;
/// The fewest contacts a batch is built for; a level's last few below it take the scalar
/// pass.
pub(crate) const MIN_LANES: usize = 2;
/// The fewest batchable contacts a run of narrow levels must hold to be coloured
/// ([`ContactBatches::colour`]): enough for a batch of each of two colours.
const COLOUR_FROM: usize = 2 * MIN_LANES;
/// Colours a run may take (a body's colours are the bits of a `u64`); a contact that
/// finds none free takes the scalar pass.
const MAX_COLOURS: u32 = 64;
/// A batch lane without a contact.
pub(crate) const NO_CONTACT: u32 = u32::MAX;
/// One step of a pass, in order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SolveStep {
    /// Batches solved lane by lane, one after another.
    Batches(Range<usize>),
    /// One contact solved by the scalar pass: one with a rolling motion, with rows
    /// refreshed every substep (a turning anisotropic body) or impulses reported, or one
    /// of a level's last contacts too few for a batch ([`MIN_LANES`]).
    Scalar(u32),
}

/// This step's contacts as batches and scalar contacts, in solving order.
#[derive(Default, Debug)]
pub(crate) struct ContactBatches {
    /// The batches.
    pub batches: Vec<ContactBatch>,
    /// The batches' points, lane by lane ([`ContactBatch::range`]).
    pub points: Vec<PointLanes>,
    /// The points' anchors, the same index as `points`.
    pub anchors: Vec<AnchorLanes>,
    /// The batches' friction impulses, one a batch.
    pub friction: Vec<FrictionLanes>,
    /// The pass: batches and scalar contacts, the contacts with fixed colliders first.
    pub steps: Vec<SolveStep>,
    /// The contacts of the scalar steps, in pass order.
    pub scalar: Vec<u32>,
    /// How many steps, at the front, are those of the contacts with fixed colliders
    /// (which each pass runs again at its end).
    pub fixed_steps: usize,
    /// How many batches, at the front, are those of the contacts with fixed colliders.
    pub fixed_batches: usize,
    /// Per body: one more than the level of its last contact (scratch).
    stamp: Vec<u32>,
    /// Per contact of the part being packed: its level (scratch).
    level: Vec<u32>,
    /// Where each level starts in `order` (scratch).
    start: Vec<u32>,
    /// The part's contacts by level (scratch).
    order: Vec<u32>,
    /// Per body: the colours its contacts took in the run being coloured (scratch).
    used: Vec<u64>,
    /// A run's contacts with their colours, and one colour's contacts (scratch).
    coloured: Vec<(u8, u32)>,
    group: Vec<u32>,
    /// The scalar contacts in manifold order, the order they are built in (scratch;
    /// see the solver's `prepare_contacts`).
    pub scalar_in_order: Vec<u32>,
}

/// Work a contact pass did over its batches: sweeps over their normal rows, and batches
/// solved (see [`PhysicsWorld::normal_sweeps_per_batch`](super::PhysicsWorld::normal_sweeps_per_batch)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolveWork {
    pub sweeps: u64,
    pub batches: u64,
}

impl std::ops::AddAssign for SolveWork {
    fn add_assign(&mut self, other: Self) {
        self.sweeps += other.sweeps;
        self.batches += other.batches;
    }
}

/// Whether the solver moves body `i`: a dynamic body (a kinematic one has no inverse
/// mass or inertia, so no contact changes its velocity, and like the static body it may
/// sit in every lane of a batch).
#[inline]
pub(crate) fn moved_by_contacts(bodies: &[SolverBody], i: u32) -> bool {
    i != STATIC && moves(&bodies[i as usize])
}

/// Whether contacts change this solver body's velocity (see [`moved_by_contacts`]; the
/// shared static body does not move).
#[inline]
fn moves(b: &SolverBody) -> bool {
    b.inv_mass > 0.0 || b.inv_inertia != Mat3::ZERO
}

/// Contacts the scalar pass solves (see [`SolveStep::Scalar`]).
fn scalar_only(c: &ContactConstraint) -> bool {
    c.anchoring.rolls() || c.refresh || c.report
}

/// What packing reads of a contact: its bodies, whether the contacts move each, whether
/// only the scalar pass may solve it, and its point count. Twelve bytes, made from the
/// manifold before the contact is built ([`ContactKey::new`]), so that a contact can be
/// built straight into the lanes of its batch.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ContactKey {
    /// Body indices, or [`STATIC`].
    pub a: u32,
    pub b: u32,
    /// See [`moved_by_contacts`].
    pub moved: [bool; 2],
    /// See [`SolveStep::Scalar`].
    pub scalar: bool,
    /// Contact points.
    pub len: u8,
}

impl ContactKey {
    /// The key of constraint `c` among `bodies`.
    pub(crate) fn of(c: &ContactConstraint, bodies: &[SolverBody]) -> Self {
        let (a, b) = (body(bodies, c.a), body(bodies, c.b));
        Self::new((c.a, c.b), [&a, &b], scalar_only(c), c.len)
    }

    /// The key of a contact between bodies `a` and `b` (indices or [`STATIC`]) whose
    /// solver bodies (the shared static one for a static side) are `sides`.
    #[inline(always)]
    pub(crate) fn new(
        (a, b): (u32, u32),
        sides: [&SolverBody; 2],
        scalar: bool,
        len: usize,
    ) -> Self {
        Self {
            a,
            b,
            moved: sides.map(moves),
            scalar,
            len: len as u8,
        }
    }
}

three_operand_copy! {
    /// [`ContactBatches::pack_keyed`].
    fn pack_run / pack_vex => pack_any(
        this: &mut ContactBatches,
        keys: &[ContactKey],
        bodies: &[SolverBody],
        fixed: usize,
    )
}

#[inline(always)]
fn pack_any(this: &mut ContactBatches, keys: &[ContactKey], bodies: &[SolverBody], fixed: usize) {
    this.batches.clear();
    this.points.clear();
    this.anchors.clear();
    this.friction.clear();
    this.steps.clear();
    this.scalar.clear();
    this.stamp.clear();
    this.stamp.resize(bodies.len(), 0);
    this.used.clear();
    this.used.resize(bodies.len(), 0);
    this.pack(keys, 0..fixed);
    this.fixed_steps = this.steps.len();
    this.fixed_batches = this.batches.len();
    this.pack(keys, fixed..keys.len());
    debug_assert!(this.is_valid(keys, bodies), "a batch shares a body");
}

/// The bodies of a contact that contacts move (as indices), at most two.
#[inline(always)]
fn moved_sides(k: &ContactKey) -> [Option<usize>; 2] {
    let side = |i: u32, moved: bool| moved.then_some(i as usize);
    [side(k.a, k.moved[0]), side(k.b, k.moved[1])]
}

/// Asks the CPU for all of `x`'s cache lines, to be read or written soon (on x86_64; no
/// effect elsewhere).
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let p = (x as *const T).cast::<i8>();
        for line in (0..size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch reads nothing; the address is inside `x`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(line)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

impl ContactBatches {
    /// Packs `constraints` and fills the batches' lanes from them (the tests' and
    /// benchmarks' way; a step builds each contact straight into its lanes, see the
    /// solver's `prepare_contacts`).
    #[cfg(any(test, feature = "bench-internals"))]
    pub(crate) fn build(
        &mut self,
        constraints: &[ContactConstraint],
        bodies: &[SolverBody],
        fixed: usize,
    ) {
        let keys: Vec<ContactKey> = constraints
            .iter()
            .map(|c| ContactKey::of(c, bodies))
            .collect();
        self.pack_keyed(&keys, bodies, fixed);
        for (j, batch) in self.batches.iter_mut().enumerate() {
            let range = batch.range();
            let (point, anchor) = (&mut self.points[range.clone()], &mut self.anchors[range]);
            let contact = batch.contact;
            for (l, &ci) in contact.iter().enumerate() {
                if ci != NO_CONTACT {
                    let c = &constraints[ci as usize];
                    let lanes = (&mut *point, &mut *anchor);
                    batch.set_lane(l, c, bodies, lanes, &mut self.friction[j]);
                }
            }
        }
    }

    /// Packs the contacts of `keys` (one a contact, see [`ContactKey::new`]), whose
    /// first `fixed` are the contacts with fixed colliders (packed on their own, so that
    /// a pass can run them again), into batches whose lanes are left to fill
    /// ([`ContactBatch::set_lane`]) and the scalar steps.
    pub(crate) fn pack_keyed(&mut self, keys: &[ContactKey], bodies: &[SolverBody], fixed: usize) {
        pack_run(self, keys, bodies, fixed);
    }

    /// Packs one part by levels: a contact's level is one more than the highest level
    /// of the contacts before it on either of its moved bodies, so each body meets its
    /// contacts level after level in contact order, and the contacts of one level share
    /// no moved body. Each level is cut into batches in contact order; its scalar
    /// contacts follow its batches. Linear in the contacts.
    #[inline(always)]
    fn pack(&mut self, keys: &[ContactKey], range: Range<usize>) {
        // Per body: one more than the level of its last contact in this part (0: none).
        self.stamp.iter_mut().for_each(|s| *s = 0);
        self.level.clear();
        let mut levels = 0;
        for k in &keys[range.clone()] {
            let sides = moved_sides(k);
            let level = sides
                .iter()
                .flatten()
                .map(|&i| self.stamp[i])
                .max()
                .unwrap_or(0);
            for i in sides.into_iter().flatten() {
                self.stamp[i] = level + 1;
            }
            self.level.push(level);
            levels = levels.max(level as usize + 1);
        }
        // Contacts by level, in contact order within each (a counting sort).
        self.start.clear();
        self.start.resize(levels + 1, 0);
        for &l in &self.level {
            self.start[l as usize + 1] += 1;
        }
        for l in 0..levels {
            self.start[l + 1] += self.start[l];
        }
        self.order.clear();
        self.order.resize(self.level.len(), 0);
        // Filled level by level: `start[l]` moves on as level l takes its contacts, and
        // ends where level l + 1 begins; shifted back after.
        for (k, &l) in self.level.iter().enumerate() {
            self.order[self.start[l as usize] as usize] = (range.start + k) as u32;
            self.start[l as usize] += 1;
        }
        self.start.copy_within(0..levels, 1);
        self.start[0] = 0;
        // Levels are emitted as slices of `order` (it and `start` are taken out while
        // `emit` adds to the other lists, and put back).
        let (order, start) = (
            std::mem::take(&mut self.order),
            std::mem::take(&mut self.start),
        );
        let level = |m: usize| &order[start[m] as usize..start[m + 1] as usize];
        let batchable = |contacts: &[u32]| {
            contacts
                .iter()
                .filter(|&&c| !keys[c as usize].scalar)
                .count()
        };
        let mut l = 0;
        while l < levels {
            if batchable(level(l)) >= MIN_LANES {
                self.emit(keys, level(l));
                l += 1;
                continue;
            }
            // A run of narrow levels (a chain, a tower: one contact a level).
            let end = (l..levels)
                .find(|&m| batchable(level(m)) >= MIN_LANES)
                .unwrap_or(levels);
            let run = &order[start[l] as usize..start[end] as usize];
            if batchable(run) >= COLOUR_FROM {
                self.colour(keys, run);
            } else {
                (l..end).for_each(|m| self.emit(keys, level(m)));
            }
            l = end;
        }
        (self.order, self.start) = (order, start);
    }

    /// Colours a run of narrow levels (`order[run]`): each contact, in level order, takes
    /// the first colour neither of its moved bodies has taken, and each colour is emitted
    /// as a group ([`emit`](Self::emit)), colour after colour. A chain's contacts then go
    /// two colours, side by side, instead of one at a time: the passes solve it in
    /// red–black order rather than bottom to top (the same Gauss–Seidel fixed point; for
    /// a chain, the same rate of convergence), and the result is no longer the bits of
    /// the scalar pass in contact order, but of the scalar pass in pass order.
    fn colour(&mut self, keys: &[ContactKey], run: &[u32]) {
        let mut coloured = std::mem::take(&mut self.coloured);
        coloured.clear();
        for &c in run.iter().filter(|&&c| !keys[c as usize].scalar) {
            let sides = moved_sides(&keys[c as usize]);
            let taken = sides.iter().flatten().fold(0u64, |m, &i| m | self.used[i]);
            let colour = (!taken).trailing_zeros();
            if colour >= MAX_COLOURS {
                coloured.push((u8::MAX, c));
                continue;
            }
            sides
                .iter()
                .flatten()
                .for_each(|&i| self.used[i] |= 1 << colour);
            coloured.push((colour as u8, c));
        }
        for &c in run {
            moved_sides(&keys[c as usize])
                .iter()
                .flatten()
                .for_each(|&i| self.used[i] = 0);
        }
        // By colour, then contact (a colour's contacts share no moved body, so their
        // order within it is free; this one is fixed and sorts in place).
        coloured.sort_unstable();
        let mut group = std::mem::take(&mut self.group);
        for same in coloured.chunk_by(|x, y| x.0 == y.0) {
            group.clear();
            group.extend(same.iter().map(|&(_, c)| c));
            if same[0].0 == u8::MAX {
                self.scalar_steps(&group);
            } else {
                self.emit(keys, &group);
            }
        }
        self.group = group;
        self.coloured = coloured;
        for &c in run.iter().filter(|&&c| keys[c as usize].scalar) {
            self.scalar_steps(&[c]);
        }
    }

    /// Contacts that share no moved body (a level, or a colour), in order: cut into
    /// batches, its scalar contacts after them.
    fn emit(&mut self, keys: &[ContactKey], contacts: &[u32]) {
        let first = self.batches.len();
        let mut lanes = [NO_CONTACT; LANES];
        let mut n = 0;
        for &c in contacts.iter().filter(|&&c| !keys[c as usize].scalar) {
            lanes[n] = c;
            n += 1;
            if n == LANES {
                self.push_batch(keys, lanes);
                (lanes, n) = ([NO_CONTACT; LANES], 0);
            }
        }
        // A batch of few lanes costs about what a full one does: its contacts go to
        // the scalar pass.
        let lone = if n >= MIN_LANES {
            self.push_batch(keys, lanes);
            0
        } else {
            n
        };
        if self.batches.len() > first {
            self.steps
                .push(SolveStep::Batches(first..self.batches.len()));
        }
        self.scalar_steps(&lanes[..lone]);
        for &c in contacts.iter().filter(|&&c| keys[c as usize].scalar) {
            self.scalar_steps(&[c]);
        }
    }

    /// A batch of `lanes`, whose lanes are left to fill.
    fn push_batch(&mut self, keys: &[ContactKey], lanes: [u32; LANES]) {
        let lists = (&mut self.points, &mut self.anchors);
        let batch = ContactBatch::empty(keys, lanes, lists, &mut self.friction);
        self.batches.push(batch);
    }

    fn scalar_steps(&mut self, contacts: &[u32]) {
        self.scalar.extend_from_slice(contacts);
        self.steps
            .extend(contacts.iter().map(|&c| SolveStep::Scalar(c)));
    }

    /// The batches' points, for a range of batches.
    pub(crate) fn points_of(&self, batches: &Range<usize>) -> Range<usize> {
        let first = self.batches[batches.start].first as usize;
        first..self.batches[batches.end - 1].range().end
    }

    /// The accumulated impulses of a range of batches back into their constraints.
    pub(crate) fn write_back(&self, batches: Range<usize>, constraints: &mut [ContactConstraint]) {
        let friction = &self.friction[batches.clone()];
        for (b, f) in self.batches[batches].iter().zip(friction) {
            b.write_back(&self.points, f, constraints);
        }
    }

    /// The invariant the lanes rely on: no two contacts of a batch share a moved body,
    /// and every contact is solved exactly once.
    pub(crate) fn is_valid(&self, keys: &[ContactKey], bodies: &[SolverBody]) -> bool {
        let mut seen = vec![0u8; keys.len()];
        for batch in &self.batches {
            let lanes = batch.contact.iter().filter(|&&c| c != NO_CONTACT);
            let mut moved: Vec<u32> = lanes
                .clone()
                .flat_map(|&c| [keys[c as usize].a, keys[c as usize].b])
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
