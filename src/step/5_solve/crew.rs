//! One helper for all of a step's split passes (see `split.rs`). A helper task spawned
//! for each pass began about 30 µs after its pass did, the time a sleeping pool thread
//! takes to wake here: the ball pit splits 20 passes a step, so for 0.6 ms of each step
//! the helper did nothing, and it ran only 35–38 % of the chunks. The crew's helper is
//! spawned once, before the first substep, and takes each split pass as the leader
//! offers it; between passes it waits, spinning a little, then yielding.
//!
//! The pass (its [`Split`] and its chunk closure) lives on the leader's stack: the helper
//! reads it only between taking the offer and saying it has finished, and the leader
//! does not return from [`Crew::run`] before the offer is taken back or finished.

use std::cell::UnsafeCell;
use std::ops::Range;
use std::sync::atomic::{AtomicU32, Ordering};

use super::split::{Split, snooze};
use crate::world::{SharedBodies, SolveStep};

/// What the helper runs of a level: a chunk of its batches.
pub(crate) type Chunk<'a> = dyn Fn(&mut SharedBodies, Range<usize>) + Sync + 'a;

/// No pass on offer.
const IDLE: u32 = 0;
/// A pass on offer ([`Crew::job`] written).
const OFFERED: u32 = 1;
/// The helper took the offered pass and is in it.
const TAKEN: u32 = 2;
/// The helper is out of the pass it took.
const FINISHED: u32 = 3;
/// The step's passes are over: the helper returns.
const STOPPED: u32 = 4;

/// The pass on offer, its lifetimes erased (see the module's note).
struct Job {
    split: *const Split<'static>,
    bodies: SharedBodies,
    chunk: *const Chunk<'static>,
}

/// The helper's side of a step's split passes.
pub(crate) struct Crew {
    state: AtomicU32,
    /// Written by the leader only while [`IDLE`], read by the helper only after taking
    /// the offer.
    job: UnsafeCell<Option<Job>>,
    /// Whether the leader claims chunks too (the tests leave them all to the helper).
    pub(crate) leader_claims: bool,
}

// SAFETY: `job` is handed over by `state` (see its note); the pass it points to is Sync
// (atomics, shared slices and a Sync closure) and outlives the helper's use of it.
unsafe impl Sync for Crew {}

impl Crew {
    pub(crate) fn new(leader_claims: bool) -> Self {
        Self {
            state: AtomicU32::new(IDLE),
            job: UnsafeCell::new(None),
            leader_claims,
        }
    }

    /// The helper: takes each offered pass and helps with it, until stopped.
    pub(crate) fn serve(&self) {
        let mut spins = 0;
        loop {
            match self.state.load(Ordering::Acquire) {
                STOPPED => return,
                OFFERED
                    if (self.state)
                        .compare_exchange(OFFERED, TAKEN, Ordering::AcqRel, Ordering::Relaxed)
                        .is_ok() =>
                {
                    // SAFETY: taken: the leader wrote the job before offering it, and
                    // keeps its pass alive until this thread says it has finished.
                    let (split, bodies, chunk) = unsafe {
                        let job = (*self.job.get()).as_ref().expect("an offered job");
                        (&*job.split, job.bodies, &*job.chunk)
                    };
                    split.help(bodies, chunk);
                    self.state.store(FINISHED, Ordering::Release);
                    spins = 0;
                }
                _ => snooze(&mut spins),
            }
        }
    }

    /// The leader: offers the pass, leads it, and takes it back (waiting for the helper
    /// to finish with it if it took it).
    pub(crate) fn run<'a>(
        &self,
        split: &Split<'a>,
        bodies: SharedBodies,
        chunk: &Chunk<'a>,
        serial: impl FnMut(&mut SharedBodies, &SolveStep),
    ) {
        debug_assert_eq!(
            self.state.load(Ordering::Relaxed),
            IDLE,
            "one pass at a time"
        );
        // SAFETY: the lifetimes are erased only while the pass is on offer or taken:
        // `TakeBack` below ends both before this function returns, even by a panic.
        let job = unsafe {
            Job {
                split: std::mem::transmute::<*const Split<'a>, *const Split<'static>>(split),
                bodies,
                chunk: std::mem::transmute::<*const Chunk<'a>, *const Chunk<'static>>(chunk),
            }
        };
        // SAFETY: IDLE: the helper does not read the job.
        unsafe { *self.job.get() = Some(job) };
        self.state.store(OFFERED, Ordering::Release);
        let _back = TakeBack { crew: self, split };
        split.lead(bodies, chunk, serial);
    }

    /// Ends the step's passes: the helper returns.
    pub(crate) fn stop(&self) {
        self.state.store(STOPPED, Ordering::Release);
    }
}

/// Takes an offered pass back when the leader is done with it (or unwinds out of it).
struct TakeBack<'c, 'a> {
    crew: &'c Crew,
    split: &'c Split<'a>,
}

impl Drop for TakeBack<'_, '_> {
    fn drop(&mut self) {
        let state = &self.crew.state;
        // Untaken: withdrawn. Taken: the helper leaves once the pass is stopped (which
        // `lead` does at its end; again here for a leader that unwound).
        if (state.compare_exchange(OFFERED, IDLE, Ordering::AcqRel, Ordering::Acquire)).is_err() {
            self.split.stop();
            let mut spins = 0;
            while state.load(Ordering::Acquire) != FINISHED {
                snooze(&mut spins);
            }
            state.store(IDLE, Ordering::Release);
        }
        // SAFETY: IDLE again: the helper does not read the job.
        unsafe { *self.crew.job.get() = None };
    }
}

/// Stops the crew when dropped: at the end of the step's passes, or when the leader
/// unwinds out of them (a helper left waiting would hold the scope open for ever).
pub(crate) struct StopOnDrop<'c>(pub &'c Crew);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.stop();
    }
}
