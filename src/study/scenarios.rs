//! The study's scenarios, each with an exact reference. A scenario builds its bodies in a
//! fresh headless app, steps it, and measures itself; it returns the measure and the
//! simulated time, so the sweep can price it per simulated second.

use bevy::prelude::*;

use super::{Config, headless_app};
use crate::prelude::*;

/// What a run measured. Errors are in the scenario's own unit (see [`SCENARIOS`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Measure {
    /// The error at the end of the run.
    pub error_final: f64,
    /// The largest error during the run.
    pub error_max: f64,
    /// Relative change of the conserved energy over the run (0 where none is conserved).
    pub energy_drift: f64,
}

/// One scenario of the study: a run with an exact reference.
pub struct Scenario {
    /// Its name in the CSV and the plots.
    pub name: &'static str,
    /// What the error is.
    pub unit: &'static str,
    /// Runs it at a sweep point: what it measured, and CPU seconds per simulated second.
    pub run: fn(Config) -> (Measure, f64),
}

/// Every scenario, in the order of the CSV.
pub const SCENARIOS: &[Scenario] = &[
    Scenario {
        name: "projectile",
        unit: "position error (m)",
        run: projectile,
    },
    Scenario {
        name: "linear_drag",
        unit: "position error (m)",
        run: linear_drag,
    },
    Scenario {
        name: "spinning_box",
        unit: "flip interval error (relative)",
        run: spinning_box,
    },
    Scenario {
        name: "separatrix_box",
        unit: "period error (relative)",
        run: separatrix_box,
    },
    Scenario {
        name: "bouncing_ball",
        unit: "apex height error (relative)",
        run: bouncing_ball,
    },
    Scenario {
        name: "slide_to_roll",
        unit: "speed error vs 5/7·v0 (relative)",
        run: slide_to_roll,
    },
    Scenario {
        name: "pendulum",
        unit: "period error (relative, 60° swing)",
        run: super::pendulum::pendulum,
    },
    Scenario {
        name: "box_stack",
        unit: "top drift (m); max = deepest penetration (m)",
        run: box_stack,
    },
];

const G: f64 = 9.81;

fn steps(config: Config, seconds: f64) -> usize {
    (config.hz * seconds).round() as usize
}

fn ball(app: &mut App, r: f32, p: Vec3, v: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(r),
            Mass(1.0),
            Transform::from_translation(p),
            Velocity::linear(v),
        ))
        .id()
}

fn state(app: &App, e: Entity) -> (Vec3, Quat, Velocity) {
    let t = app.world().get::<Transform>(e).unwrap();
    (
        t.translation,
        t.rotation,
        *app.world().get::<Velocity>(e).unwrap(),
    )
}

fn projectile(config: Config) -> (Measure, f64) {
    let mut app = headless_app(config);
    let v0 = Vec3::new(3.0, 8.0, 0.0);
    let b = ball(&mut app, 0.1, Vec3::ZERO, v0);
    let (n, h) = (steps(config, 1.5), 1.0 / config.hz);
    let mut m = Measure::default();
    for k in 1..=n {
        app.update();
        let t = k as f64 * h;
        let (p, _, _) = state(&app, b);
        let exact = v0.as_dvec3() * t + bevy::math::DVec3::new(0.0, -0.5 * G * t * t, 0.0);
        m.error_final = (p.as_dvec3() - exact).length();
        m.error_max = m.error_max.max(m.error_final);
    }
    let (p, _, v) = state(&app, b);
    let energy = |y: f64, v: f64| 0.5 * v * v + G * y;
    let e0 = energy(0.0, v0.length() as f64);
    m.energy_drift = (energy(p.y as f64, v.linear.length() as f64) - e0) / e0;
    (m, n as f64 * h)
}

/// Stiff linear drag (c = 20 /s) so that RK4's error stays above f32 rounding at the
/// coarser steps and the orders can be read: v(t) = v∞ + (v0 − v∞)·e^(−ct), v∞ = −g/c.
/// The error is in the velocity, m/s, over the first 0.5 s (the transient).
fn linear_drag(config: Config) -> (Measure, f64) {
    let (c, v0) = (20.0f64, 8.0f64);
    let mut app = headless_app(config);
    let b = ball(&mut app, 0.1, Vec3::ZERO, Vec3::Y * v0 as f32);
    app.world_mut()
        .entity_mut(b)
        .insert(LinearDamping(c as f32));
    let (n, h) = (steps(config, 0.5), 1.0 / config.hz);
    let v_inf = -G / c;
    let mut m = Measure::default();
    for k in 1..=n {
        app.update();
        let t = k as f64 * h;
        let exact = v_inf + (v0 - v_inf) * (-c * t).exp();
        m.error_final = (state(&app, b).2.linear.y as f64 - exact).abs();
        m.error_max = m.error_max.max(m.error_final);
    }
    (m, n as f64 * h)
}

/// The 1.0 × 0.1 × 0.4 m, 1 kg box in zero gravity, spun at 10 rad/s about its
/// intermediate (z) axis and `off_axis` rad/s about its long (x) axis.
fn tumbling_box_app(app: &mut App, off_axis: f32) -> Entity {
    app.insert_resource(Gravity(Vec3::ZERO));
    let spin = Velocity {
        linear: Vec3::ZERO,
        angular: Vec3::new(off_axis, 0.0, 10.0),
    };
    let body = (
        RigidBody::Dynamic,
        Collider::cuboid(0.5, 0.05, 0.2),
        Mass(1.0),
        Transform::default(),
        spin,
    );
    app.world_mut().spawn(body).id()
}

/// Spins the 1.0 × 0.1 × 0.4 m box about its intermediate axis for 10 s and compares the
/// intervals between sign changes of that spin with `period`.
fn tumbling_box(config: Config, off_axis: f32, period: f64) -> (Measure, f64) {
    let mut app = headless_app(config);
    let b = tumbling_box_app(&mut app, off_axis);
    let inertia = Vec3::new(0.17, 1.16, 1.01) / 12.0;
    let measure = |app: &App| {
        let (_, q, v) = state(app, b);
        let wb = q.inverse() * v.angular;
        (0.5 * wb.dot(inertia * wb) as f64, wb.z as f64)
    };
    let (e0, mut prev) = measure(&app);
    let (n, h) = (steps(config, 10.0), 1.0 / config.hz);
    let mut flips = Vec::new();
    let mut energy = e0;
    for k in 1..=n {
        app.update();
        let (e, wz) = measure(&app);
        if wz.signum() != prev.signum() {
            flips.push((k as f64 - 1.0 + prev / (prev - wz)) * h);
        }
        (prev, energy) = (wz, e);
    }
    let mut m = Measure {
        energy_drift: (energy - e0) / e0,
        ..default()
    };
    if flips.len() >= 2 {
        let mean = (flips[flips.len() - 1] - flips[0]) / (flips.len() - 1) as f64;
        m.error_final = (mean - period).abs() / period;
        m.error_max = flips
            .windows(2)
            .map(|w| ((w[1] - w[0]) - period).abs() / period)
            .fold(0.0, f64::max);
    } else {
        (m.error_final, m.error_max) = (1.0, 1.0);
    }
    (m, n as f64 * h)
}

fn spinning_box(config: Config) -> (Measure, f64) {
    tumbling_box(config, 1.0, 0.9080)
}

fn separatrix_box(config: Config) -> (Measure, f64) {
    tumbling_box(config, 0.01, 2.2524)
}

fn bouncing_ball(config: Config) -> (Measure, f64) {
    let (r, h0, e) = (0.5f32, 5.0f64, 0.8f64);
    let mut app = headless_app(config);
    app.world_mut()
        .spawn((Collider::plane(), Transform::default()));
    let b = ball(&mut app, r, Vec3::Y * (r + h0 as f32), Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Restitution(e as f32));
    let (n, h) = (steps(config, 6.0), 1.0 / config.hz);
    let (mut prev_vy, mut top, mut bounce) = (0.0f32, 0.0f32, 0);
    let mut m = Measure::default();
    for _ in 0..n {
        app.update();
        let (p, _, v) = state(&app, b);
        let (y, vy) = (p.y - r, v.linear.y);
        top = top.max(y);
        if prev_vy > 0.0 && vy <= 0.0 {
            bounce += 1;
            let expected = e.powi(2 * bounce) * h0;
            if (2.0 * G * expected).sqrt() > 1.0 {
                m.error_final = (top as f64 - expected).abs() / expected;
                m.error_max = m.error_max.max(m.error_final);
            }
        }
        if vy > 0.0 && prev_vy <= 0.0 {
            top = y;
        }
        prev_vy = vy;
    }
    (m, n as f64 * h)
}

fn slide_to_roll(config: Config) -> (Measure, f64) {
    let (v0, mu, r) = (7.0f32, 0.3f32, 0.5f32);
    let mut app = headless_app(config);
    app.world_mut()
        .spawn((Collider::plane(), Transform::default(), Friction(mu)));
    let b = ball(&mut app, r, Vec3::Y * r, Vec3::X * v0);
    app.world_mut().entity_mut(b).insert(Friction(mu));
    let t_star = 2.0 * v0 as f64 / (7.0 * mu as f64 * G);
    let (n, h) = (steps(config, 1.5), 1.0 / config.hz);
    let target = 5.0 / 7.0 * v0 as f64;
    let mut m = Measure::default();
    for k in 1..=n {
        app.update();
        m.error_final = (state(&app, b).2.linear.length() as f64 - target).abs() / target;
        if k as f64 * h > t_star + 3.0 * h {
            m.error_max = m.error_max.max(m.error_final);
        }
    }
    (m, n as f64 * h)
}

fn box_stack(config: Config) -> (Measure, f64) {
    let mut app = headless_app(config);
    app.world_mut()
        .spawn((Collider::plane(), Transform::default()));
    let boxes: Vec<Entity> = (0..5)
        .map(|i| {
            let dx = if i % 2 == 0 { 0.01 } else { -0.01 };
            app.world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    Collider::cuboid(0.5, 0.5, 0.5),
                    Mass(1.0),
                    Transform::from_xyz(dx, 0.5 + i as f32, 0.0),
                ))
                .id()
        })
        .collect();
    let top0 = state(&app, boxes[4]).0;
    let (n, h) = (steps(config, 5.0), 1.0 / config.hz);
    let mut m = Measure::default();
    for _ in 0..n {
        app.update();
        let world = app.world().resource::<PhysicsWorld>();
        let deepest = world.deepest_overlap();
        m.error_max = m.error_max.max(deepest as f64);
    }
    m.error_final = (state(&app, boxes[4]).0 - top0).xz().length() as f64;
    (m, n as f64 * h)
}

/// Relative kinetic-energy change of the spinning box over 10 s, sampled every step.
pub fn spinning_energy_series(config: Config) -> Vec<(f64, f64)> {
    let mut app = headless_app(config);
    let b = tumbling_box_app(&mut app, 1.0);
    let inertia = Vec3::new(0.17, 1.16, 1.01) / 12.0;
    let energy = |app: &App| {
        let (_, q, v) = state(app, b);
        let wb = q.inverse() * v.angular;
        0.5 * wb.dot(inertia * wb) as f64
    };
    let e0 = energy(&app);
    let (n, h) = (steps(config, 10.0), 1.0 / config.hz);
    (1..=n)
        .map(|k| {
            app.update();
            (k as f64 * h, energy(&app) / e0)
        })
        .collect()
}
