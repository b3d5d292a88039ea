//! What accuracy costs in time: runs the accuracy study (every scenario × integrator ×
//! step rate 30…960 Hz × 1 or 4 substeps), writes `results.csv` and SVG plots into the
//! folder given (default `docs/accuracy`), and prints the headline numbers. Then the
//! contact scenarios at 60 Hz over substeps × iterations: `iterations.csv` and a table.
//!
//! `cargo run --release --features study --example accuracy_study`

use tumble::study::{
    CONTACT_SCENARIOS, KNOB_VALUES, RATES, fitted_order, iteration_sweep, sweep, to_csv,
    write_plots,
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
    Ok(())
}
