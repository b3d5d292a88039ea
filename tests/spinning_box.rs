//! The tennis-racket theorem: a box spun about its intermediate axis flips over and back.
//! Box 1.0 × 0.1 × 0.4 m, 1 kg, no gravity, ω0 = 1 rad/s about the long axis and
//! 10 rad/s about the intermediate (0.4 m) one. The intermediate-axis spin changes sign
//! every 0.9080 s (first at 0.454 s). Semi-implicit Euler (implicit-midpoint gyroscopic
//! solve) and RK4 keep that period within 1% over 10 s and keep |L| and the kinetic
//! energy within 0.1%; explicit Euler — the 2015 engine's method — gains energy.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const PERIOD: f32 = 0.9080;

struct Run {
    flips: Vec<f32>,
    /// The largest |ΔL|/L and |ΔE|/E over every step.
    l_drift: f32,
    e_drift: f32,
    /// (E − E0)/E0 after the last step.
    e_final: f32,
}

fn spin(integrator: Integrator) -> Run {
    spin_with(integrator, SolverSettings::default().substeps)
}

fn spin_with(integrator: Integrator, substeps: u32) -> Run {
    let mut app = app_without_gravity();
    app.insert_resource(integrator);
    app.world_mut().resource_mut::<SolverSettings>().substeps = substeps;
    // Body axes: x long (1.0 m), y thin (0.1 m), z intermediate (0.4 m).
    let b = cuboid(&mut app, Vec3::new(0.5, 0.05, 0.2), 1.0, Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Velocity {
        linear: Vec3::ZERO,
        angular: Vec3::new(1.0, 0.0, 10.0),
    });
    let inertia = Vec3::new(0.01 + 0.16, 1.0 + 0.16, 1.0 + 0.01) / 12.0;
    let invariants = |app: &App| {
        let q = rot(app, b);
        let wb = q.inverse() * vel(app, b).angular;
        ((inertia * wb).length(), 0.5 * wb.dot(inertia * wb), wb.z)
    };
    let (l0, e0, mut prev) = invariants(&app);
    let mut run = Run {
        flips: Vec::new(),
        l_drift: 0.0,
        e_drift: 0.0,
        e_final: 0.0,
    };
    for k in 1..=600 {
        step(&mut app, 1);
        let (l, e, wz) = invariants(&app);
        run.l_drift = run.l_drift.max((l - l0).abs() / l0);
        run.e_drift = run.e_drift.max((e - e0).abs() / e0);
        run.e_final = (e - e0) / e0;
        if wz.signum() != prev.signum() {
            // Interpolate the zero crossing inside the step.
            run.flips.push((k as f32 - 1.0 + prev / (prev - wz)) * H);
        }
        prev = wz;
    }
    let mean = (run.flips.last().unwrap_or(&0.0) - run.flips.first().unwrap_or(&0.0))
        / (run.flips.len().max(2) - 1) as f32;
    eprintln!(
        "{integrator:?} × {substeps}: {} flips, mean interval {mean:.4} s, max |L| drift {:.2e}, max energy \
         drift {:.2e}, final {:+.2e}",
        run.flips.len(),
        run.l_drift,
        run.e_drift,
        run.e_final
    );
    run
}

#[test]
fn semi_implicit_and_rk4_flip_on_time_and_keep_energy() {
    for integrator in [Integrator::SemiImplicitEuler, Integrator::Rk4] {
        let run = spin(integrator);
        assert!(
            run.flips.len() >= 10,
            "{integrator:?}: flips at {:?}",
            run.flips
        );
        assert!(
            (run.flips[0] - PERIOD / 2.0).abs() < 0.01 * PERIOD,
            "{integrator:?}: first flip {}",
            run.flips[0]
        );
        let mean = (run.flips.last().unwrap() - run.flips[0]) / (run.flips.len() - 1) as f32;
        assert!(
            (mean - PERIOD).abs() < 0.01 * PERIOD,
            "{integrator:?}: interval {mean}"
        );
        // Bound on the worst step: the implicit midpoint rule conserves |L| and E (quadratic
        // invariants of torque-free motion) exactly, so only its two-iteration Newton solve
        // and f32 round-off remain (2,400 substeps × ~6e-8 ≈ 1.4e-4); RK4's local error is
        // O((|ω|·hs)⁵) = (10/240)⁵ ≈ 1.3e-7 a substep, ≤ 3e-4 over 2,400 substeps.
        assert!(
            run.l_drift < 1e-3,
            "{integrator:?}: |L| drift {}",
            run.l_drift
        );
        assert!(
            run.e_drift < 1e-3,
            "{integrator:?}: energy drift {}",
            run.e_drift
        );
    }
}

#[test]
fn explicit_euler_gains_energy() {
    let run = spin(Integrator::ExplicitEuler);
    assert!(
        run.e_final > 0.05,
        "explicit Euler energy drift {}",
        run.e_final
    );
}

/// More substeps must never cost accuracy: the free spin's energy stays within 2e-4 at
/// 4, 16 and 64 substeps (it drifted +1.9e-3 at 16 and +7.1e-3 at 64 while the body-frame
/// spin was carried through the world frame every substep: a round-off per substep).
#[test]
fn more_substeps_keep_the_spin_energy() {
    for substeps in [4, 16, 64] {
        let run = spin_with(Integrator::SemiImplicitEuler, substeps);
        assert!(
            run.e_drift < 2e-4,
            "{substeps} substeps: energy drift {:.2e}",
            run.e_drift
        );
        assert!(
            run.l_drift < 2e-4,
            "{substeps} substeps: |L| drift {:.2e}",
            run.l_drift
        );
    }
}
