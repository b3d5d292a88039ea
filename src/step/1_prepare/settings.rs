//! Checking the global settings before the step reads them. A bad value in a resource
//! (a NaN from a slider, ∞ from a scene, 1e30 from a typo) is logged with the resource
//! and the field, and the last good value is put back, so it is in force for this step
//! and every body keeps simulating: no body is ever rejected because of a bad global.
//! Counts (`substeps`, `iterations`) are clamped into 1..=64 instead, and the fixed rate
//! into 1 Hz–10 kHz ([`guard_fixed_rate`], which runs before Bevy's fixed loop).
//!
//! Only resources that changed since the last step are looked at.

use bevy::prelude::*;

use crate::effects::Wind;
use crate::limits::{self, Invalid};
use crate::settings::{GlobalForce, Gravity, SleepSettings, SolverSettings};

/// The last value of each global that passed its check.
#[derive(Default)]
pub struct LastGood {
    gravity: Gravity,
    global: GlobalForce,
    wind: Wind,
    solver: SolverSettings,
    sleep: SleepSettings,
}

/// Checks one resource if it changed: remembers it when good, puts the last good value
/// back (and logs) when not.
fn guard<R: Resource<Mutability = bevy::ecs::component::Mutable> + Clone>(
    name: &str,
    res: &mut ResMut<R>,
    last: &mut R,
    check: impl Fn(&R) -> Result<(), Invalid>,
) {
    if !res.is_changed() {
        return;
    }
    match check(res) {
        Ok(()) => *last = (**res).clone(),
        Err(e) => {
            error!("tumble: resource {name}.{e}; keeping the last good value");
            **res = last.clone();
        }
    }
}

/// Validates `Gravity`, `GlobalForce`, `Wind`, `SolverSettings` and `SleepSettings`.
pub fn validate_settings(
    mut gravity: ResMut<Gravity>,
    mut global: ResMut<GlobalForce>,
    mut wind: ResMut<Wind>,
    mut solver: ResMut<SolverSettings>,
    mut sleep: ResMut<SleepSettings>,
    mut last: Local<LastGood>,
) {
    let last = &mut *last;
    guard("Gravity", &mut gravity, &mut last.gravity, Gravity::check);
    guard(
        "GlobalForce",
        &mut global,
        &mut last.global,
        GlobalForce::check,
    );
    guard("Wind", &mut wind, &mut last.wind, Wind::check);
    guard(
        "SleepSettings",
        &mut sleep,
        &mut last.sleep,
        SleepSettings::check,
    );
    if solver.is_changed() {
        let mut clamped = *solver;
        if let Some(why) = clamped.clamp_counts() {
            warn!("tumble: resource SolverSettings: {why}");
            *solver = clamped;
        }
    }
    guard(
        "SolverSettings",
        &mut solver,
        &mut last.solver,
        SolverSettings::check,
    );
}

/// Keeps `Time<Fixed>`'s rate within 1 Hz–10 kHz, whoever set it: a 1 ns step would run
/// millions of steps a frame, a 10 s step would tunnel everything. Runs every frame
/// before Bevy's fixed loop.
pub fn guard_fixed_rate(mut time: ResMut<Time<Fixed>>) {
    let timestep = time.timestep().as_secs_f64();
    let (hz, why) = limits::clamp_rate(1.0 / timestep);
    if let Some(why) = why {
        error!("tumble: resource Time<Fixed>: {why}");
        time.set_timestep_hz(hz);
    }
}
