//! What accuracy costs in time: runs the accuracy study (every scenario × integrator ×
//! step rate 30…960 Hz × 1 or 4 substeps), writes `results.csv` and SVG plots into the
//! folder given (default `docs/accuracy`), and prints the headline numbers. Then the
//! contact scenarios at 60 Hz over substeps × iterations: `iterations.csv` and a table;
//! the spinning box and the pendulum over 1…64 substeps (`substeps.csv`, a table); and
//! the double pendulum's time with its reference per integrator and step
//! (`double_pendulum.csv`, `double_pendulum.svg`, a table).
//!
//! `cargo run --release --features study --example accuracy_study`

use tumble::study::{
    CONTACT_SCENARIOS, HORIZON, KNOB_VALUES, RATES, SUBSTEPS, double_pendulum_sweep, fitted_order,
    iteration_sweep, substep_sweep, sweep, to_csv, write_double_pendulum_plot, write_plots,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "docs/accuracy".into()),
    );
    std::fs::create_dir_all(&dir)?;
    let rows = sweep(3);
    std::fs::write(dir.join("results.csv"), to_csv(&rows))?;
    write_plots(&rows, &dir)?;

    println!(
        "| scenario | integrator | substeps | {} |",
        RATES.map(|r| format!("{r} Hz: err · cost")).join(" | ")
    );
    println!("|---|---|---|{}", "---|".repeat(RATES.len()));
    for scenario in tumble::study::SCENARIOS {
        for integrator in tumble::prelude::Integrator::ALL {
            for substeps in [1, 4] {
                let cells: Vec<String> = rows
                    .iter()
                    .filter(|r| {
                        r.scenario == scenario.name
                            && r.config.integrator == integrator
                            && r.config.substeps == substeps
                    })
                    .map(|r| format!("{:.1e} · {:.1e}", r.measure.error_max, r.cost))
                    .collect();
                println!(
                    "| {} | {integrator:?} | {substeps} | {} |",
                    scenario.name,
                    cells.join(" | ")
                );
            }
        }
    }
    for integrator in tumble::prelude::Integrator::ALL {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| {
                r.scenario == "linear_drag"
                    && r.config.integrator == integrator
                    && r.config.substeps == 1
            })
            .map(|r| (1.0 / r.config.hz, r.measure.error_max))
            .collect();
        println!(
            "fitted order, linear drag, {integrator:?}: {:.2}",
            fitted_order(&pts)
        );
    }
    let knobs = iteration_sweep(3);
    std::fs::write(dir.join("iterations.csv"), to_csv(&knobs))?;
    for scenario in CONTACT_SCENARIOS {
        println!(
            "\n{scenario} at 60 Hz, worst error · CPU s per simulated s\n\n| substeps \\ iterations | {} |\n|---|{}",
            KNOB_VALUES.map(|i| i.to_string()).join(" | "),
            "---|".repeat(KNOB_VALUES.len())
        );
        for substeps in KNOB_VALUES {
            let cells: Vec<String> = knobs
                .iter()
                .filter(|r| r.scenario == scenario && r.config.substeps == substeps)
                .map(|r| format!("{:.1e} · {:.1e}", r.measure.error_max, r.cost))
                .collect();
            println!("| {substeps} | {} |", cells.join(" | "));
        }
    }

    let subs = substep_sweep(3);
    std::fs::write(dir.join("substeps.csv"), to_csv(&subs))?;
    println!(
        "\nAt 60 Hz, semi-implicit: |energy drift| over the run · worst error, per substeps\n\n| scenario | {} |\n|---|{}",
        SUBSTEPS.map(|s| s.to_string()).join(" | "),
        "---|".repeat(SUBSTEPS.len())
    );
    for scenario in ["spinning_box", "pendulum"] {
        let cells: Vec<String> = subs
            .iter()
            .filter(|r| r.scenario == scenario)
            .map(|r| {
                format!(
                    "{:.1e} · {:.1e}",
                    r.measure.energy_drift.abs(),
                    r.measure.error_max
                )
            })
            .collect();
        println!("| {scenario} | {} |", cells.join(" | "));
    }

    let double = double_pendulum_sweep();
    let mut csv = String::from("integrator,hz,substeps,seconds_with_reference\n");
    for (c, t) in &double {
        csv += &format!("{:?},{},{},{t:.4}\n", c.integrator, c.hz, c.substeps);
    }
    std::fs::write(dir.join("double_pendulum.csv"), csv)?;
    write_double_pendulum_plot(&double, &dir.join("double_pendulum.svg"))?;
    println!(
        "\nDouble pendulum: seconds until 5 cm off the reference (at most {HORIZON})\n\n| integrator | substeps | {} |\n|---|---|{}",
        RATES.map(|r| format!("{r} Hz")).join(" | "),
        "---|".repeat(RATES.len())
    );
    for integrator in tumble::prelude::Integrator::ALL {
        for substeps in [1, 4] {
            let cells: Vec<String> = double
                .iter()
                .filter(|(c, _)| c.integrator == integrator && c.substeps == substeps)
                .map(|(_, t)| format!("{t:.2}"))
                .collect();
            println!("| {integrator:?} | {substeps} | {} |", cells.join(" | "));
        }
    }
    Ok(())
}
