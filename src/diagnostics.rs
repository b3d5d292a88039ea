//! Physics in a game's own diagnostics: [`PhysicsDiagnosticsPlugin`] registers the step's
//! and each stage's wall time and the world's counts with Bevy's `DiagnosticsStore`, so
//! they show in any diagnostics overlay or `LogDiagnosticsPlugin`, smoothed and with
//! history, like the frame time.
//!
//! For a profiler, build with Bevy's `trace` feature (and e.g. `trace_tracy`): every
//! stage's systems appear as spans under their names (`prepare_bodies`, `find_pairs`,
//! `collide_pairs`, `solve_contacts`, …), and the solver adds one span per stage of its
//! substep loop (`tumble::solve`, field `stage`, at trace level so that it costs nothing
//! unless a profiler's filter asks for it).

use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::prelude::*;

use crate::timings::{STAGES, StepTimings};
use crate::world::PhysicsWorld;

/// Registers and records the physics diagnostics (all in `FixedPostUpdate`, once a step):
/// - `physics/step` and `physics/<stage>` (`physics/prepare` … `physics/sleep`), ms;
/// - `physics/awake_bodies`, `physics/fixed_colliders` (static and sleeping),
///   `physics/contacts` (manifolds), `physics/substeps`.
///
/// Needs Bevy's `DiagnosticsPlugin` (in `DefaultPlugins`) to keep the values.
pub struct PhysicsDiagnosticsPlugin;

/// `physics/step`: the whole step, ms.
pub const STEP: DiagnosticPath = DiagnosticPath::const_new("physics/step");
/// `physics/awake_bodies`: dynamic and kinematic bodies stepped.
pub const AWAKE_BODIES: DiagnosticPath = DiagnosticPath::const_new("physics/awake_bodies");
/// `physics/fixed_colliders`: static colliders and sleeping bodies.
pub const FIXED_COLLIDERS: DiagnosticPath = DiagnosticPath::const_new("physics/fixed_colliders");
/// `physics/contacts`: contact manifolds this step.
pub const CONTACTS: DiagnosticPath = DiagnosticPath::const_new("physics/contacts");
/// `physics/substeps`: the contact solver's substeps this step.
pub const SUBSTEPS: DiagnosticPath = DiagnosticPath::const_new("physics/substeps");

/// `physics/<stage>`, ms, for stage index `stage` of [`STAGES`].
pub fn stage_path(stage: usize) -> DiagnosticPath {
    DiagnosticPath::new(format!("physics/{}", STAGES[stage].replace(' ', "_")))
}

impl Plugin for PhysicsDiagnosticsPlugin {
    fn build(&self, app: &mut App) {
        app.register_diagnostic(Diagnostic::new(STEP).with_suffix(" ms"));
        for stage in 0..STAGES.len() {
            app.register_diagnostic(Diagnostic::new(stage_path(stage)).with_suffix(" ms"));
        }
        for path in [AWAKE_BODIES, FIXED_COLLIDERS, CONTACTS, SUBSTEPS] {
            app.register_diagnostic(Diagnostic::new(path));
        }
        app.add_systems(FixedPostUpdate, record_diagnostics);
    }
}

/// Records this step's timings and counts.
pub fn record_diagnostics(
    timings: Res<StepTimings>,
    world: Res<PhysicsWorld>,
    mut diagnostics: Diagnostics,
) {
    diagnostics.add_measurement(&STEP, || timings.total_ms());
    for (stage, ms) in timings.stage_ms.iter().enumerate() {
        diagnostics.add_measurement(&stage_path(stage), || *ms);
    }
    diagnostics.add_measurement(&AWAKE_BODIES, || world.bodies.len() as f64);
    diagnostics.add_measurement(&FIXED_COLLIDERS, || world.fixed.len() as f64);
    diagnostics.add_measurement(&CONTACTS, || world.manifolds.len() as f64);
    diagnostics.add_measurement(&SUBSTEPS, || world.substeps as f64);
}
