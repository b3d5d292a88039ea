//! The accuracy study: what accuracy costs in time. Scenarios with exact references run
//! through the real plugin in a headless app, swept over integrator × step rate ×
//! substeps; each run reports its error, energy drift and CPU time per simulated second.
//! `examples/accuracy_study.rs` writes the CSV and SVG plots.

mod pendulum;
mod plots;
mod scenarios;

pub use pendulum::{HORIZON, PARTED, double_pendulum_divergence, pendulum_energy_series};
pub use plots::{write_double_pendulum_plot, write_plots};
pub use scenarios::{Measure, SCENARIOS, Scenario};

use std::time::Instant;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;

use crate::prelude::*;

/// One point of the sweep.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    /// The free-motion integrator.
    pub integrator: Integrator,
    /// Fixed steps per second, Hz.
    pub hz: f64,
    /// Contact solver substeps per step.
    pub substeps: u32,
    /// Solver passes per substep (at least; heavy loads add more, see `iterations_for`).
    pub iterations: u32,
}

/// A result row.
#[derive(Clone, Debug)]
pub struct Row {
    /// The scenario's name (see [`SCENARIOS`]).
    pub scenario: &'static str,
    /// The sweep point it ran at.
    pub config: Config,
    /// What it measured.
    pub measure: Measure,
    /// Median CPU seconds per simulated second.
    pub cost: f64,
}

/// The step rates swept, Hz (h = 1/30 … 1/960 s).
pub const RATES: [f64; 6] = [30.0, 60.0, 120.0, 240.0, 480.0, 960.0];

/// A headless app stepping exactly once per `update()`, sleeping off.
pub fn headless_app(config: Config) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        TransformPlugin,
        TumblePlugin { hz: config.hz },
    ))
    .insert_resource(TimeUpdateStrategy::FixedTimesteps(1))
    .insert_resource(config.integrator)
    .insert_resource(Effects {
        sleeping: false,
        ..default()
    });
    let mut settings = app.world_mut().resource_mut::<SolverSettings>();
    settings.substeps = config.substeps;
    settings.iterations = config.iterations;
    app.update();
    app
}

/// Runs one scenario under one configuration `repeats` times after a warm-up run; the
/// measure is from the last run, the cost the median.
pub fn run(scenario: &Scenario, config: Config, repeats: usize) -> Row {
    let mut costs = Vec::with_capacity(repeats);
    let mut measure = (scenario.run)(config).0;
    for _ in 0..repeats {
        let started = Instant::now();
        let (m, sim_seconds) = (scenario.run)(config);
        costs.push(started.elapsed().as_secs_f64() / sim_seconds);
        measure = m;
    }
    costs.sort_by(f64::total_cmp);
    Row {
        scenario: scenario.name,
        config,
        measure,
        cost: costs[costs.len() / 2],
    }
}

/// The whole sweep.
pub fn sweep(repeats: usize) -> Vec<Row> {
    let mut rows = Vec::new();
    for scenario in SCENARIOS {
        for integrator in Integrator::ALL {
            for &hz in &RATES {
                for substeps in [1, 4] {
                    rows.push(run(
                        scenario,
                        Config {
                            integrator,
                            hz,
                            substeps,
                            iterations: 1,
                        },
                        repeats,
                    ));
                }
            }
        }
    }
    rows
}

/// The contact scenarios stepped at 60 Hz with the semi-implicit integrator for every
/// pair of substeps × iterations in {1, 2, 4, 8}: which knob buys accuracy cheaper.
pub fn iteration_sweep(repeats: usize) -> Vec<Row> {
    let mut rows = Vec::new();
    for scenario in SCENARIOS
        .iter()
        .filter(|s| CONTACT_SCENARIOS.contains(&s.name))
    {
        for substeps in KNOB_VALUES {
            for iterations in KNOB_VALUES {
                let config = Config {
                    integrator: Integrator::SemiImplicitEuler,
                    hz: 60.0,
                    substeps,
                    iterations,
                };
                rows.push(run(scenario, config, repeats));
            }
        }
    }
    rows
}

/// The double pendulum at every integrator × step rate × {1, 4} substeps: how long each
/// run stays with the reference (s).
pub fn double_pendulum_sweep() -> Vec<(Config, f64)> {
    let mut out = Vec::new();
    for integrator in Integrator::ALL {
        for &hz in &RATES {
            for substeps in [1, 4] {
                let config = Config {
                    integrator,
                    hz,
                    substeps,
                    iterations: 1,
                };
                out.push((config, double_pendulum_divergence(config)));
            }
        }
    }
    out
}

/// The substep counts the substep sweep tries (`SUBSTEPS`).
pub const SUBSTEPS: [u32; 7] = [1, 2, 4, 8, 16, 32, 64];

/// The spinning box and the pendulum at 60 Hz, semi-implicit, over [`SUBSTEPS`]: more
/// substeps must never cost accuracy (energy drift and error).
pub fn substep_sweep(repeats: usize) -> Vec<Row> {
    let mut rows = Vec::new();
    for scenario in SCENARIOS
        .iter()
        .filter(|s| ["spinning_box", "pendulum"].contains(&s.name))
    {
        for substeps in SUBSTEPS {
            let config = Config {
                integrator: Integrator::SemiImplicitEuler,
                hz: 60.0,
                substeps,
                iterations: 1,
            };
            rows.push(run(scenario, config, repeats));
        }
    }
    rows
}

/// The scenarios whose error comes from contacts.
pub const CONTACT_SCENARIOS: [&str; 2] = ["box_stack", "bouncing_ball"];

/// The substep and iteration counts the iteration sweep tries.
pub const KNOB_VALUES: [u32; 4] = [1, 2, 4, 8];

/// Errors below this (m/s, on speeds of ~8 m/s) are f32 rounding, not truncation.
pub const ROUNDING_FLOOR: f64 = 1e-5;

/// Least-squares slope of log(error) against log(h), over the points above the f32
/// rounding floor.
pub fn fitted_order(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.1 > ROUNDING_FLOOR)
        .map(|&(h, e)| (h.ln(), e.ln()))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// The rows as CSV.
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scenario,integrator,hz,substeps,iterations,error_final,error_max,energy_drift,cpu_s_per_sim_s\n",
    );
    for r in rows {
        out += &format!(
            "{},{:?},{},{},{},{:.6e},{:.6e},{:.6e},{:.6e}\n",
            r.scenario,
            r.config.integrator,
            r.config.hz,
            r.config.substeps,
            r.config.iterations,
            r.measure.error_final,
            r.measure.error_max,
            r.measure.energy_drift,
            r.cost
        );
    }
    out
}
