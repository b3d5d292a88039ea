//! Convergence orders in free flight, measured the way the accuracy study does: a body
//! falling against linear drag (c = 5 /s, so the velocity-dependent force matters) for
//! 0.8 s (while the transient still matters) at 15, 30 and 60 steps per second, one substep. The error against the exact
//! v(t) = v∞ + (v0 − v∞)·e^(−ct) must shrink like h¹ for both Euler variants and like h⁴
//! for RK4 (fitted slope ± 0.2). Orders, not timings: safe to assert.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const C: f64 = 5.0;
const G: f64 = 9.81;
const T: f64 = 0.8;

fn error_at(integrator: Integrator, hz: f64) -> f64 {
    let mut app = app();
    app.insert_resource(integrator)
        .insert_resource(Time::<Fixed>::from_hz(hz));
    app.world_mut().resource_mut::<SolverSettings>().substeps = 1;
    let v0 = 5.0;
    let b = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::Y * v0 as f32);
    app.world_mut()
        .entity_mut(b)
        .insert(LinearDamping(C as f32));
    step(&mut app, (hz * T) as usize);
    let v_inf = -G / C;
    let exact = v_inf + (v0 - v_inf) * (-C * T).exp();
    (vel(&app, b).linear.y as f64 - exact).abs()
}

/// Least-squares slope of log(error) against log(h).
pub fn fitted_order(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|&(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn orders_match_theory() {
    for (integrator, expected) in [
        (Integrator::ExplicitEuler, 1.0),
        (Integrator::SemiImplicitEuler, 1.0),
        (Integrator::Rk4, 4.0),
    ] {
        let points: Vec<(f64, f64)> = [15.0, 30.0, 60.0]
            .iter()
            .map(|&hz| (1.0 / hz, error_at(integrator, hz)))
            .collect();
        let order = fitted_order(&points);
        eprintln!("{integrator:?}: errors {points:?}, order {order:.3}");
        assert!(
            (order - expected).abs() < 0.2,
            "{integrator:?}: order {order}, errors {points:?}"
        );
    }
}
