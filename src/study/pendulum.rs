//! The study's pendulums, on distance joints held at the bobs' centres of mass (so the
//! bobs' own spin is free and a bob is a point mass to the joint).
//!
//! - **Single pendulum** (1 m, let go from 60°): its period against the exact one,
//!   4√(L/g)·K(sin 30°), and its swing energy over 20 s (explicit Euler's grows: the
//!   seed engine's story).
//! - **Double pendulum** (two 1 m rods, two 1 kg bobs, let go from the horizontal):
//!   chaotic, so any error grows exponentially; the study measures when each run's lower
//!   bob parts by more than [`PARTED`] from a reference integrated in f64 by RK4 at
//!   ≤ 10 µs (its own step halved changes it by < 1e-9 m over the compared span).

use bevy::prelude::*;

use super::scenarios::Measure;
use super::{Config, headless_app};
use crate::prelude::*;

const G: f64 = 9.81;

/// When the double pendulum's lower bob is this far from the reference, m, the runs have
/// parted.
pub const PARTED: f64 = 0.05;

/// The longest the double pendulum is compared for, s.
pub const HORIZON: f64 = 20.0;

/// The complete elliptic integral of the first kind K(k), by the arithmetic–geometric
/// mean.
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// A 1 kg bob of radius 5 cm at `p`.
fn bob(app: &mut App, p: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.05),
            Mass(1.0),
            Transform::from_translation(p),
        ))
        .id()
}

/// The single pendulum's length, m, and release angle, rad.
const L: f32 = 1.0;
const RELEASE: f32 = std::f32::consts::FRAC_PI_3;

/// Runs the single pendulum for 20 s: per step, the time (s), the swing energy relative
/// to the start's (measured from the lowest point) and the bob's x from the pivot (m).
fn single_run(config: Config) -> Vec<(f64, f64, f64)> {
    let pivot = Vec3::new(0.0, 2.0, 0.0);
    let mut app = headless_app(config);
    let b = bob(
        &mut app,
        pivot + L * Vec3::new(RELEASE.sin(), -RELEASE.cos(), 0.0),
    );
    app.world_mut()
        .spawn(Joint::distance(None, b, L).with_local_anchors(pivot, Vec3::ZERO));
    let lowest = (pivot.y - L) as f64;
    let state = |app: &App| {
        let (p, v) = (
            app.world().get::<Transform>(b).unwrap().translation,
            app.world().get::<Velocity>(b).unwrap().linear,
        );
        let e = 0.5 * v.length_squared() as f64 + G * (p.y as f64 - lowest);
        (e, (p.x - pivot.x) as f64)
    };
    let (e0, x0) = state(&app);
    let (n, h) = ((config.hz * 20.0).round() as usize, 1.0 / config.hz);
    let mut out = vec![(0.0, 1.0, x0)];
    for k in 1..=n {
        app.update();
        let (e, x) = state(&app);
        out.push((k as f64 * h, e / e0, x));
    }
    out
}

/// The single pendulum's swing energy relative to the start's over 20 s: (t, E/E0).
pub fn pendulum_energy_series(config: Config) -> Vec<(f64, f64)> {
    single_run(config)
        .into_iter()
        .map(|(t, e, _)| (t, e))
        .collect()
}

/// The single pendulum: period error (relative, against the exact period at 60°) and
/// energy drift over 20 s.
pub fn pendulum(config: Config) -> (Measure, f64) {
    let exact = 4.0 * (L as f64 / G).sqrt() * elliptic_k((RELEASE as f64 / 2.0).sin());
    let run = single_run(config);
    let mut crossings = Vec::new();
    for w in run.windows(2) {
        let ((t0, _, a), (t1, _, b)) = (w[0], w[1]);
        if a > 0.0 && b <= 0.0 {
            crossings.push(t0 + (t1 - t0) * a / (a - b));
        }
    }
    let &(duration, e_end, _) = run.last().unwrap();
    let mut m = Measure {
        energy_drift: e_end - 1.0,
        ..default()
    };
    if crossings.len() >= 2 {
        let periods: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
        let mean = (crossings[crossings.len() - 1] - crossings[0]) / periods.len() as f64;
        m.error_final = (mean - exact).abs() / exact;
        m.error_max = periods
            .iter()
            .map(|p| (p - exact).abs() / exact)
            .fold(0.0, f64::max);
    } else {
        (m.error_final, m.error_max) = (1.0, 1.0);
    }
    (m, duration)
}

/// The double pendulum's state: angles from the vertical and their rates.
type State = [f64; 4];

/// θ̈₁, θ̈₂ of the double pendulum of point masses m₁ = m₂ = 1 kg on rods L₁ = L₂ = 1 m.
fn double_rates(s: State) -> State {
    let [t1, t2, w1, w2] = s;
    let d = t1 - t2;
    let den = 3.0 - (2.0 * d).cos();
    let a1 = (-3.0 * G * t1.sin()
        - G * (t1 - 2.0 * t2).sin()
        - 2.0 * d.sin() * (w2 * w2 + w1 * w1 * d.cos()))
        / den;
    let a2 = 2.0 * d.sin() * (2.0 * w1 * w1 + 2.0 * G * t1.cos() + w2 * w2 * d.cos()) / den;
    [w1, w2, a1, a2]
}

fn rk4(s: State, dt: f64) -> State {
    let add = |a: State, b: State, k: f64| [0, 1, 2, 3].map(|i| a[i] + k * b[i]);
    let k1 = double_rates(s);
    let k2 = double_rates(add(s, k1, dt / 2.0));
    let k3 = double_rates(add(s, k2, dt / 2.0));
    let k4 = double_rates(add(s, k3, dt));
    [0, 1, 2, 3].map(|i| s[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The lower bob's position (relative to the pivot) at each of `n` steps of `h` s, by
/// RK4 with substeps of at most `max_dt` s.
pub fn double_reference(h: f64, n: usize, max_dt: f64) -> Vec<(f64, f64)> {
    let k = (h / max_dt).ceil() as usize;
    let dt = h / k as f64;
    let half = std::f64::consts::FRAC_PI_2;
    let mut s: State = [half, half, 0.0, 0.0];
    (0..n)
        .map(|_| {
            for _ in 0..k {
                s = rk4(s, dt);
            }
            let [t1, t2, ..] = s;
            (t1.sin() + t2.sin(), -t1.cos() - t2.cos())
        })
        .collect()
}

/// How long the double pendulum run at `config` stays within [`PARTED`] of the
/// reference, s (at most [`HORIZON`]).
pub fn double_pendulum_divergence(config: Config) -> f64 {
    let pivot = Vec3::new(0.0, 3.0, 0.0);
    let mut app = headless_app(config);
    let upper = bob(&mut app, pivot + Vec3::X);
    let lower = bob(&mut app, pivot + 2.0 * Vec3::X);
    app.world_mut()
        .spawn(Joint::distance(None, upper, 1.0).with_local_anchors(pivot, Vec3::ZERO));
    app.world_mut().spawn(Joint::distance(upper, lower, 1.0));
    let h = 1.0 / config.hz;
    let n = (HORIZON * config.hz).round() as usize;
    let reference = double_reference(h, n, 1e-5);
    for (k, &(x, y)) in reference.iter().enumerate() {
        app.update();
        let p = app.world().get::<Transform>(lower).unwrap().translation - pivot;
        let off = ((p.x as f64 - x).powi(2) + (p.y as f64 - y).powi(2)).sqrt();
        if off > PARTED {
            return k as f64 * h;
        }
    }
    HORIZON
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference is converged: halving its step moves the lower bob by < 1e-9 m over
    /// the first 8 s (the span the runs stay close over; chaos amplifies beyond).
    #[test]
    fn the_double_pendulum_reference_is_converged() {
        let (h, n) = (1.0 / 60.0, 480);
        let a = double_reference(h, n, 1e-5);
        let b = double_reference(h, n, 0.5e-5);
        let worst = a
            .iter()
            .zip(&b)
            .map(|(p, q)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "reference moved {worst} m");
    }

    /// The energy of the reference stays put (it conserves it to RK4's accuracy).
    #[test]
    fn the_double_pendulum_reference_conserves_energy() {
        let energy = |s: State| {
            let [t1, t2, w1, w2] = s;
            // Two unit masses: ½(2w1² + w2² + 2w1w2cos(t1−t2)) − g(2cos t1 + cos t2).
            0.5 * (2.0 * w1 * w1 + w2 * w2 + 2.0 * w1 * w2 * (t1 - t2).cos())
                - G * (2.0 * t1.cos() + t2.cos())
        };
        let half = std::f64::consts::FRAC_PI_2;
        let mut s: State = [half, half, 0.0, 0.0];
        let e0 = energy(s);
        for _ in 0..1_000_000 {
            s = rk4(s, 1e-5);
        }
        assert!((energy(s) - e0).abs() < 1e-9, "{} J", energy(s) - e0);
    }

    #[test]
    fn elliptic_k_of_sin_45_degrees() {
        assert!((elliptic_k(0.5f64.sqrt()) - 1.854_074_677_301_372).abs() < 1e-12);
    }
}
