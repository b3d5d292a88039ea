//! How long each stage of the last step took: a stamp at the start of every stage and
//! one after the last, read by the demo's panel (through Bevy diagnostics) and benches.

use bevy::platform::time::Instant;
use bevy::prelude::*;

use crate::systems::PhysicsSystems;

/// Stage names, in step order ([`PhysicsSystems::ORDER`]), as in [`StepTimings`].
pub const STAGES: [&str; PhysicsSystems::ORDER.len()] = {
    let mut names = [""; PhysicsSystems::ORDER.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = PhysicsSystems::ORDER[i].name();
        i += 1;
    }
    names
};

/// Wall time of each stage of the last step, milliseconds.
#[derive(Resource, Default, Clone, Debug)]
pub struct StepTimings {
    /// Wall time of each stage, ms, in the order of [`STAGES`].
    pub stage_ms: [f64; STAGES.len()],
    started: Option<Instant>,
    stage: usize,
}

impl StepTimings {
    /// The whole step, ms.
    pub fn total_ms(&self) -> f64 {
        self.stage_ms.iter().sum()
    }
}

/// Closes the previous stage's time and opens stage `S` (`S` = the number of stages closes
/// the last one).
pub(crate) fn stamp<const S: usize>(mut t: ResMut<StepTimings>) {
    let now = Instant::now();
    if let (Some(started), true) = (t.started, S > 0) {
        let prev = t.stage;
        t.stage_ms[prev] = (now - started).as_secs_f64() * 1e3;
    }
    t.started = Some(now);
    t.stage = S.min(STAGES.len() - 1);
}
