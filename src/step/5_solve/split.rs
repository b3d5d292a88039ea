//! A pass's wide levels split between two threads. The contacts of a level move disjoint
//! bodies (`ContactBatches`), so its batches can be solved in any order, by any thread,
//! and leave the same bits: the result does not depend on the thread count.
//!
//! The calling thread leads: it walks the pass in order, does the scalar contacts and
//! narrow levels itself, and opens each wide level in up to [`CHUNKS`] chunks. A
//! helper on Bevy's `ComputeTaskPool` (the step's crew, see `crew.rs`) claims chunks
//! beside it, from the level's back while the leader claims from its front; so a helper
//! that starts late costs only the claims. The leader moves on once every chunk of the
//! level is done.

use std::ops::Range;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

use super::crew::Crew;
use super::iterate::{solve_listed, warm_start_listed};
use super::steps::Pass;
use super::wide::{solve_batches, warm_start_batches};
use crate::world::{
    ContactBatches, ContactConstraint, RollingArms, Shared, SharedBodies, SolveStep, SolveWork,
    SolverBody,
};

/// The chunks a wide level is cut into, at most: enough for two threads to even out.
const CHUNKS: usize = 8;
/// The fewest batches in a chunk.
const MIN_CHUNK: usize = 2;
/// The fewest batches a level must hold to be split (two chunks). Measured at two
/// threads, interleaved: splitting from 16 batches in chunks of 8 left the large
/// pyramid (591 levels of 6.7 batches on average) at 45.0–45.6 ms; from 4 in up to 8
/// chunks, 39.9–43.7, the 100 pyramids and the ball pit unchanged within the noise.
const SPLIT_FROM: usize = 2 * MIN_CHUNK;
/// The fewest batches a pass's split levels must hold for a second thread to be worth
/// waking (per pass, each wait costs about a microsecond).
const PASS_FROM: usize = 256;
/// The fewest batches a pass's split levels must hold on average: each level ends in a
/// wait for both threads, and the bodies it moved cross to the other core's cache, so a
/// level of about 8 batches is too little work to pay for it. Measured in `peers` at two
/// threads, the pass on one thread against split, interleaved runs: levels of 45–71
/// batches (rain, the ball pit, the 100 pyramids) took 1.02–1.20 of the split time on
/// one thread, levels of 6.4–8.3 (the 385-cube and large pyramids) 0.86–0.95. Splitting
/// from 8 slowed the 385-cube pyramid's solve (2.15–2.22 ms to 2.33–4.35); the large
/// pyramid's it sped on some machines (26.9–28.8 ms to 25.1–26.3, the whole step within
/// the noise) and slowed on others (step 37.7–40.6 ms split from 8 against 34.4–34.6
/// from 16, solve 28.8–30.3 against 25.5–26.0): hence 16.
const LEVEL_FROM: usize = 16;

/// The claim word's step before the first level and after the last.
const IDLE: u32 = u32::MAX - 1;
const STOP: u32 = u32::MAX;

/// The chunks a step is split into, if it is split.
pub(crate) fn chunks(step: &SolveStep) -> Option<u32> {
    match step {
        SolveStep::Batches(r) if r.len() >= SPLIT_FROM => {
            Some(r.len().div_ceil(chunk_size(r.len())) as u32)
        }
        _ => None,
    }
}

/// Batches per chunk of a level of `len` batches.
fn chunk_size(len: usize) -> usize {
    len.div_ceil(CHUNKS).max(MIN_CHUNK)
}

/// Chunk `i`'s batches of a split step.
fn piece(step: &SolveStep, i: u32) -> Range<usize> {
    let SolveStep::Batches(r) = step else {
        unreachable!("only batch steps are split")
    };
    let chunk = chunk_size(r.len());
    let start = r.start + i as usize * chunk;
    start..(start + chunk).min(r.end)
}

/// Whether `steps` are worth splitting on this app's compute pool.
pub(crate) fn worth_splitting(batches: &ContactBatches, steps: &Range<usize>) -> bool {
    let threads = bevy::tasks::ComputeTaskPool::try_get().map_or(1, |p| p.thread_num());
    let (levels, split) = batches.steps[steps.clone()]
        .iter()
        .filter(|s| chunks(s).is_some())
        .fold((0, 0), |(levels, split), s| match s {
            SolveStep::Batches(r) => (levels + 1, split + r.len()),
            SolveStep::Scalar(_) => (levels, split),
        });
    threads >= 2 && split >= PASS_FROM && split >= LEVEL_FROM * levels
}

/// The state the leader and the helper share over one pass.
pub(crate) struct Split<'a> {
    steps: &'a [SolveStep],
    /// The open step and its unclaimed chunks ([`word`]).
    claim: AtomicU64,
    /// Chunks of the open step finished.
    done: AtomicU32,
    /// Chunks the helper ran in all.
    helped: AtomicU32,
    /// Whether the leader claims chunks too (the tests leave them all to the helper, so
    /// that every level crosses threads whatever the scheduler does).
    leader_claims: bool,
}

/// The claim word: the open step, and the unclaimed chunks `front..back` of it (a level
/// has at most [`CHUNKS`]).
fn word(step: u32, front: u32, back: u32) -> u64 {
    debug_assert!(
        front <= back && back <= CHUNKS as u32,
        "chunks {front}..{back}"
    );
    ((step as u64) << 32) | ((back as u64) << 16) | front as u64
}

/// The step, front and back of a claim word.
fn unpack(c: u64) -> (u32, u32, u32) {
    (
        (c >> 32) as u32,
        c as u32 & 0xffff,
        (c >> 16) as u32 & 0xffff,
    )
}

/// Waits a little, then lets the other threads run (the machine may have no core free).
pub(crate) fn snooze(spins: &mut u32) {
    if *spins < 64 {
        std::hint::spin_loop();
        *spins += 1;
    } else {
        std::thread::yield_now();
    }
}

impl<'a> Split<'a> {
    pub(crate) fn new(steps: &'a [SolveStep], leader_claims: bool) -> Self {
        Self {
            leader_claims,
            steps,
            claim: AtomicU64::new(word(IDLE, 0, 0)),
            done: AtomicU32::new(0),
            helped: AtomicU32::new(0),
        }
    }

    /// Claims and runs chunks of the open step until none is left (counting them in
    /// `ran`); false once stopped. The leader claims from the level's front and the
    /// helper from its back, so each thread tends to meet the same bodies and points
    /// level after level and pass after pass (a level's contacts are in contact order).
    fn work(
        &self,
        bodies: &mut SharedBodies,
        chunk: &(impl Fn(&mut SharedBodies, Range<usize>) + ?Sized),
        ran: &mut u32,
        from_back: bool,
    ) -> bool {
        loop {
            let c = self.claim.load(Ordering::Acquire);
            let (step, front, back) = unpack(c);
            if step == STOP {
                return false;
            }
            if step == IDLE || front >= back {
                return true;
            }
            let (i, next) = if from_back {
                (back - 1, word(step, front, back - 1))
            } else {
                (front, word(step, front + 1, back))
            };
            if (self.claim)
                .compare_exchange_weak(c, next, Ordering::AcqRel, Ordering::Relaxed)
                .is_ok()
            {
                let s = &self.steps[step as usize];
                chunk(bodies, piece(s, i));
                *ran += 1;
                self.done.fetch_add(1, Ordering::Release);
            }
        }
    }

    /// The helper: claims chunks as levels open, until the leader stops.
    pub(crate) fn help(
        &self,
        mut bodies: SharedBodies,
        chunk: &(impl Fn(&mut SharedBodies, Range<usize>) + ?Sized),
    ) {
        let (mut spins, mut ran) = (0, 0);
        while self.work(&mut bodies, chunk, &mut ran, true) {
            snooze(&mut spins);
        }
        self.helped.store(ran, Ordering::Relaxed);
    }

    /// The leader: the pass in order, wide levels shared, the rest by `serial` (which
    /// runs while the helper only waits).
    pub(crate) fn lead(
        &self,
        mut bodies: SharedBodies,
        chunk: &(impl Fn(&mut SharedBodies, Range<usize>) + ?Sized),
        mut serial: impl FnMut(&mut SharedBodies, &SolveStep),
    ) {
        for (k, step) in self.steps.iter().enumerate() {
            let Some(n) = chunks(step) else {
                serial(&mut bodies, step);
                continue;
            };
            self.done.store(0, Ordering::Relaxed);
            // Release: the helper sees every body as the steps before left it.
            self.claim.store(word(k as u32, 0, n), Ordering::Release);
            if self.leader_claims {
                self.work(&mut bodies, chunk, &mut 0, false);
            }
            let mut spins = 0;
            // Acquire: and the leader sees the helper's chunks.
            while self.done.load(Ordering::Acquire) < n {
                snooze(&mut spins);
            }
        }
        self.stop();
    }

    /// Ends the pass: the helper leaves it.
    pub(crate) fn stop(&self) {
        self.claim.store(word(STOP, 0, 0), Ordering::Release);
    }
}

/// Where the helper runs.
#[derive(Clone, Copy)]
pub(crate) enum Runner<'c> {
    /// The step's crew (see `crew.rs`: its helper is already running on Bevy's
    /// `ComputeTaskPool`).
    Crew(&'c Crew),
    /// A thread of its own, which runs every chunk (the tests': their pool has no
    /// threads).
    #[cfg(test)]
    Thread,
}

/// Runs `steps` with their wide levels split between this thread and a helper; returns
/// how many chunks the helper ran.
fn run(
    runner: Runner<'_>,
    bodies: SharedBodies,
    steps: &[SolveStep],
    chunk: &(impl Fn(&mut SharedBodies, Range<usize>) + Sync),
    serial: impl FnMut(&mut SharedBodies, &SolveStep),
) -> u32 {
    let leader_claims = match runner {
        Runner::Crew(crew) => crew.leader_claims,
        #[cfg(test)]
        Runner::Thread => false,
    };
    let split = Split::new(steps, leader_claims);
    let split = &split;
    match runner {
        Runner::Crew(crew) => crew.run(split, bodies, chunk, serial),
        #[cfg(test)]
        Runner::Thread => std::thread::scope(|scope| {
            scope.spawn(move || split.help(bodies, chunk));
            split.lead(bodies, chunk, serial);
        }),
    }
    split.helped.load(Ordering::Relaxed)
}

/// [`warm_start_steps`](super::warm_start_steps), split.
pub(crate) fn warm_start_steps(
    runner: Runner<'_>,
    bodies: &mut [SolverBody],
    constraints: &[ContactConstraint],
    batches: &ContactBatches,
    steps: Range<usize>,
) -> u32 {
    let chunk = |view: &mut SharedBodies, r: Range<usize>| {
        let points = &batches.points[batches.points_of(&r)];
        let friction = &batches.friction[r.clone()];
        warm_start_batches(view, &batches.batches[r], points, friction);
    };
    let serial = |view: &mut SharedBodies, step: &SolveStep| match step {
        SolveStep::Batches(r) => chunk(view, r.clone()),
        // SAFETY: the helper waits while the leader runs anything but a split level.
        SolveStep::Scalar(c) => warm_start_listed(unsafe { view.whole() }, constraints, &[*c]),
    };
    let view = SharedBodies::new(bodies);
    run(runner, view, &batches.steps[steps], &chunk, serial)
}

/// [`solve_steps`](super::solve_steps), split. Returns the work over the batches (the
/// same as on one thread) and how many chunks the helper ran.
pub(crate) fn solve_steps(
    runner: Runner<'_>,
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    batches: &mut ContactBatches,
    steps: Range<usize>,
    arms: &[RollingArms],
    pass: Pass,
) -> (SolveWork, u32) {
    let Pass {
        h,
        use_bias,
        measure,
    } = pass;
    let ContactBatches {
        batches: list,
        points,
        anchors,
        friction,
        steps: all,
        ..
    } = batches;
    let points = Shared::new(points);
    let friction = Shared::new(friction);
    let list = &list[..];
    let points_of = |r: &Range<usize>| list[r.start].first as usize..list[r.end - 1].range().end;
    let (sweeps, solved) = (AtomicU64::new(0), AtomicU64::new(0));
    let chunk = |view: &mut SharedBodies, r: Range<usize>| {
        // SAFETY: a chunk's points and friction lanes are its batches' own; no other
        // chunk has them.
        let (points, friction) =
            unsafe { (points.slice(points_of(&r)), friction.slice(r.clone())) };
        solved.fetch_add(r.len() as u64, Ordering::Relaxed);
        let anchors = measure.then(|| &anchors[points_of(&r)]);
        let n = solve_batches(view, &list[r], points, friction, h, use_bias, anchors);
        sweeps.fetch_add(u64::from(n), Ordering::Relaxed);
    };
    let serial = |view: &mut SharedBodies, step: &SolveStep| match step {
        SolveStep::Batches(r) => chunk(view, r.clone()),
        SolveStep::Scalar(c) => {
            // SAFETY: the helper waits while the leader runs anything but a split level.
            let bodies = unsafe { view.whole() };
            solve_listed(bodies, constraints, &[*c], arms, h, (use_bias, measure));
        }
    };
    let view = SharedBodies::new(bodies);
    let helped = run(runner, view, &all[steps], &chunk, serial);
    let work = SolveWork {
        sweeps: sweeps.into_inner(),
        batches: solved.into_inner(),
    };
    (work, helped)
}
