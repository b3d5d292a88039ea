//! The study's SVG plots: work-precision (error against CPU time, log-log), convergence
//! (error against h with order-1 and order-4 guides and fitted orders), energy over time at
//! h = 1/60 (the spinning box, the pendulum), the near-separatrix box's period error
//! against its energy drift, and the double pendulum's time with its reference.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::combinators::LogCoord;
use plotters::prelude::*;

use super::pendulum::pendulum_energy_series;
use super::scenarios::spinning_energy_series;
use super::{Config, Row, SCENARIOS, fitted_order};
use crate::settings::Integrator;

type Res = Result<(), Box<dyn std::error::Error>>;

fn color(i: Integrator) -> RGBColor {
    match i {
        Integrator::ExplicitEuler => RGBColor(214, 39, 40),
        Integrator::SemiImplicitEuler => RGBColor(31, 119, 180),
        Integrator::Rk4 => RGBColor(44, 160, 44),
    }
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        (1e-9, 1.0)
    } else {
        (lo / 2.0, hi * 2.0)
    }
}

/// A white 720 × 480 SVG canvas at `path`.
fn canvas(path: &Path) -> Result<DrawingArea<SVGBackend<'_>, Shift>, Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (720, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    Ok(root)
}

/// Draws the legend and writes the file.
fn finish<'a, 'b, X: Ranged, Y: Ranged>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    root: &'a DrawingArea<SVGBackend<'b>, Shift>,
) -> Res {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// A log axis's label: decades only (`1e-3`), none between them (their labels ran into
/// each other: `6e-3 7e-38e-39e-3`).
fn decade(v: &f64) -> String {
    let exponent = v.log10();
    if (exponent - exponent.round()).abs() < 1e-6 {
        format!("1e{}", exponent.round() as i32)
    } else {
        String::new()
    }
}

/// A log-log chart in the study's style, axes drawn.
type LogLog<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

fn log_log_chart<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (x_desc, y_desc): (&str, &str),
) -> Result<LogLog<'a, 'b>, Box<dyn std::error::Error>> {
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(236, 236, 236))
        .y_label_formatter(&decade)
        .x_label_formatter(&decade)
        .x_desc(x_desc)
        .y_desc(y_desc)
        .draw()?;
    Ok(chart)
}

/// Writes every plot into `dir`.
pub fn write_plots(rows: &[Row], dir: &Path) -> Res {
    for s in SCENARIOS {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.scenario == s.name).collect();
        work_precision(&mine, s.unit, &dir.join(format!("pareto_{}.svg", s.name)))?;
    }
    convergence(rows, &dir.join("convergence.svg"))?;
    energy_over_time(&dir.join("energy_60hz.svg"))?;
    pendulum_energy(&dir.join("pendulum_energy_60hz.svg"))?;
    separatrix(rows, &dir.join("separatrix.svg"))?;
    Ok(())
}

fn work_precision(rows: &[&Row], unit: &str, path: &Path) -> Res {
    let root = canvas(path)?;
    let (x0, x1) = bounds(rows.iter().map(|r| r.cost));
    let (y0, y1) = bounds(rows.iter().map(|r| r.measure.error_max));
    let name = rows.first().map_or("", |r| r.scenario);
    let caption = format!("{name}: error against CPU time");
    let desc = ("CPU s per simulated s", unit);
    let mut chart = log_log_chart(&root, &caption, (x0, x1), (y0, y1), desc)?;
    for integrator in Integrator::ALL {
        for substeps in [1, 4] {
            let mut pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| {
                    r.config.integrator == integrator
                        && r.config.substeps == substeps
                        && r.measure.error_max > 0.0
                })
                .map(|r| (r.cost, r.measure.error_max))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            draw_family(&mut chart, integrator, substeps, pts)?;
        }
    }
    finish(&mut chart, &root)
}

/// One integrator × substeps family as a line with dots, labelled (4 substeps paler).
fn draw_family(
    chart: &mut LogLog<'_, '_>,
    integrator: Integrator,
    substeps: u32,
    pts: Vec<(f64, f64)>,
) -> Res {
    let c = color(integrator);
    let style = if substeps == 1 {
        c.stroke_width(2)
    } else {
        c.mix(0.5).stroke_width(2)
    };
    chart
        .draw_series(LineSeries::new(pts.clone(), style))?
        .label(format!("{integrator:?}, {substeps} substep(s)"))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
    Ok(())
}

fn convergence(rows: &[Row], path: &Path) -> Res {
    let root = canvas(path)?;
    let pick = |i: Integrator| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| {
                r.scenario == "linear_drag" && r.config.integrator == i && r.config.substeps == 1
            })
            .map(|r| (1.0 / r.config.hz, r.measure.error_max))
            .filter(|p| p.1 > 0.0)
            .collect()
    };
    let all: Vec<(f64, f64)> = Integrator::ALL.iter().flat_map(|&i| pick(i)).collect();
    let (x0, x1) = bounds(all.iter().map(|p| p.0));
    let (y0, y1) = bounds(all.iter().map(|p| p.1));
    let caption = "Convergence in free flight (stiff linear drag, 1 substep)";
    let desc = ("h (s)", "largest velocity error over 0.5 s (m/s)");
    let mut chart = log_log_chart(&root, caption, (x0, x1), (y0, y1), desc)?;
    for integrator in Integrator::ALL {
        let pts = pick(integrator);
        let order = fitted_order(&pts);
        let c = color(integrator);
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?
            .label(format!("{integrator:?}: fitted order {order:.2}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
    }
    // Each guide through the coarsest point of the family it compares with, over that
    // family's own step sizes, cut where it would leave the frame.
    for (order, anchor) in [
        (1.0, pick(Integrator::SemiImplicitEuler)),
        (4.0, pick(Integrator::Rk4)),
    ] {
        if let Some(&(h, e)) = anchor.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
            let lo = anchor.iter().map(|p| p.0).fold(f64::MAX, f64::min);
            // e·(x/h)^order stays within [y0, y1] for x in [h·(y0/e)^(1/order), h·(y1/e)^(1/order)].
            let x_lo = lo.max(h * (y0 / e).powf(1.0 / order));
            let x_hi = h.min(h * (y1 / e).powf(1.0 / order));
            let guide: Vec<(f64, f64)> = [x_lo, x_hi]
                .iter()
                .map(|&x| (x, e * (x / h).powf(order)))
                .collect();
            chart
                .draw_series(LineSeries::new(guide, BLACK.mix(0.4)))?
                .label(format!("slope {order}"))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.mix(0.4)));
        }
    }
    finish(&mut chart, &root)
}

fn energy_over_time(path: &Path) -> Res {
    let root = canvas(path)?;
    let series: Vec<(Integrator, Vec<(f64, f64)>)> = Integrator::ALL
        .iter()
        .map(|&i| {
            (
                i,
                spinning_energy_series(Config {
                    integrator: i,
                    hz: 60.0,
                    substeps: 1,
                    iterations: 1,
                }),
            )
        })
        .collect();
    // Explicit Euler's energy runs away (to overflow); show the band that tells the story.
    let (y0, y1) = (0.5, 20.0);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Spinning box: kinetic energy / initial, h = 1/60, 1 substep",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..10.0, (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(236, 236, 236))
        .y_label_formatter(&decade)
        .x_desc("t (s)")
        .y_desc("E / E0")
        .draw()?;
    for (integrator, pts) in series {
        let c = color(integrator);
        chart
            .draw_series(LineSeries::new(
                pts.into_iter().filter(|p| p.1.is_finite() && p.1 < y1),
                c.stroke_width(2),
            ))?
            .label(format!("{integrator:?}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    finish(&mut chart, &root)
}

fn separatrix(rows: &[Row], path: &Path) -> Res {
    let root = canvas(path)?;
    let pts: Vec<(Integrator, f64, f64)> = rows
        .iter()
        .filter(|r| r.scenario == "separatrix_box")
        .map(|r| {
            (
                r.config.integrator,
                r.measure.energy_drift.abs(),
                r.measure.error_final,
            )
        })
        .filter(|p| p.1 > 0.0 && p.2 > 0.0)
        .collect();
    let (x0, x1) = bounds(pts.iter().map(|p| p.1));
    let (y0, y1) = bounds(pts.iter().map(|p| p.2));
    let caption = "Box near the separatrix: period error against energy drift";
    let desc = (
        "|energy drift| over 10 s (relative)",
        "period error (relative)",
    );
    let mut chart = log_log_chart(&root, caption, (x0, x1), (y0, y1), desc)?;
    for integrator in Integrator::ALL {
        let c = color(integrator);
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.0 == integrator)
                    .map(|p| Circle::new((p.1, p.2), 4, c.filled())),
            )?
            .label(format!("{integrator:?}"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
    }
    finish(&mut chart, &root)
}

/// The single pendulum's swing energy over 20 s at h = 1/60, 1 substep, per integrator.
fn pendulum_energy(path: &Path) -> Res {
    let root = canvas(path)?;
    let series: Vec<(Integrator, Vec<(f64, f64)>)> = Integrator::ALL
        .iter()
        .map(|&i| {
            let config = Config {
                integrator: i,
                hz: 60.0,
                substeps: 1,
                iterations: 1,
            };
            (i, pendulum_energy_series(config))
        })
        .collect();
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, p)| p.iter().map(|q| q.1))
        .filter(|v| v.is_finite())
        .fold((1.0f64, 1.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let pad = (hi - lo).max(1e-3) * 0.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Pendulum (1 m, 60°): swing energy / initial, h = 1/60, 1 substep",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..20.0, (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(236, 236, 236))
        .x_desc("t (s)")
        .y_desc("E / E0")
        .draw()?;
    for (integrator, pts) in series {
        let c = color(integrator);
        chart
            .draw_series(LineSeries::new(
                pts.into_iter().filter(|p| p.1.is_finite()),
                c.stroke_width(2),
            ))?
            .label(format!("{integrator:?}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    finish(&mut chart, &root)
}

/// The double pendulum: how long each run stays within `PARTED` of the reference,
/// against the step.
pub fn write_double_pendulum_plot(points: &[(Config, f64)], path: &Path) -> Res {
    let root = canvas(path)?;
    let (x0, x1) = bounds(points.iter().map(|p| 1.0 / p.0.hz));
    let (y0, y1) = bounds(points.iter().map(|p| p.1));
    let caption = "Double pendulum from the horizontal: time until 5 cm off the reference";
    let desc = ("h (s)", "time with the reference (s)");
    let mut chart = log_log_chart(&root, caption, (x0, x1), (y0, y1), desc)?;
    for integrator in Integrator::ALL {
        for substeps in [1, 4] {
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.0.integrator == integrator && p.0.substeps == substeps)
                .map(|p| (1.0 / p.0.hz, p.1))
                .collect();
            draw_family(&mut chart, integrator, substeps, pts)?;
        }
    }
    finish(&mut chart, &root)
}
