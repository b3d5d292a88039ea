//! Free fall for 2 s with each integrator, against its own discrete recurrence and the
//! analytic parabola. The solver substeps the free motion, so each method's step is
//! hs = (1/60)/substeps.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const G: f64 = 9.81;

fn fall(integrator: Integrator) -> (f64, f64, f64) {
    let mut app = app();
    app.insert_resource(integrator);
    let substeps = app.world().resource::<SolverSettings>().substeps as usize;
    let e = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 120);
    // The recurrence in f64 with the same substep.
    let hs = (1.0 / 60.0) / substeps as f64;
    let (mut y, mut v) = (0.0f64, 0.0f64);
    for _ in 0..120 * substeps {
        match integrator {
            Integrator::ExplicitEuler => (y, v) = (y + hs * v, v - hs * G),
            Integrator::SemiImplicitEuler => {
                v -= hs * G;
                y += hs * v;
            }
            Integrator::Rk4 => (y, v) = (y + hs * v - 0.5 * G * hs * hs, v - hs * G),
        }
    }
    (pos(&app, e).y as f64, y, hs)
}

#[test]
fn each_integrator_follows_its_recurrence_and_known_error() {
    let t = 2.0;
    let exact = -0.5 * G * t * t;
    for integrator in Integrator::ALL {
        let (y, recurrence, hs) = fall(integrator);
        assert!(
            ((y - recurrence) / recurrence).abs() < 1e-5,
            "{integrator:?}: {y} vs recurrence {recurrence}"
        );
        // Explicit Euler moves with the old velocity: it stays ½·g·hs·t above the parabola.
        // Semi-implicit moves with the new one: ½·g·hs·t below. RK4 is exact for constant g.
        let expected_error = match integrator {
            Integrator::ExplicitEuler => 0.5 * G * hs * t,
            Integrator::SemiImplicitEuler => -0.5 * G * hs * t,
            Integrator::Rk4 => 0.0,
        };
        let err = y - exact;
        assert!(
            (err - expected_error).abs() < 1e-5 * exact.abs(),
            "{integrator:?}: error {err}, expected {expected_error}"
        );
    }
}

#[test]
fn rk4_free_fall_with_linear_drag_approaches_terminal_velocity() {
    // v(t) = −(g/c)(1 − e^{−ct}); RK4 at 240 Hz is accurate to f32 rounding.
    let mut app = app();
    app.insert_resource(Integrator::Rk4);
    let c = 2.0f32;
    let e = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    app.world_mut().entity_mut(e).insert(LinearDamping(c));
    step(&mut app, 120);
    let exact = -(9.81 / c) * (1.0 - (-c * 2.0f32).exp());
    let v = vel(&app, e).linear.y;
    assert!((v - exact).abs() < 1e-5, "{v} vs {exact}");
}
