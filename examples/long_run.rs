//! The long run: 1,000 boxes in 100 ten-high stacks, stepped for a simulated hour
//! (216,000 steps at 60 Hz), headless. After 10 s of settling it checks, to the end:
//! - every box stays within 1 mm of where it settled (resting bodies don't creep);
//! - the total energy (kinetic + potential) never rises above its settled value;
//! - the process's resident memory stays flat (no buffer grows step after step).
//!
//! It prints a line every simulated 6 minutes and exits non-zero if a check fails.
//!
//! ```sh
//! cargo run --release --example long_run                 # sleeping on (the default)
//! cargo run --release --example long_run -- 60 awake     # sleeping off: all 1,000 solved
//! ```
//! The first argument is the simulated minutes (60 by default).

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::prelude::*;

const SIDE: usize = 10;
const HEIGHT: usize = 10;
const HALF: f32 = 0.25;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let minutes: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(60.0);
    let awake = args.iter().any(|a| a == "awake");
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
        .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
    app.world_mut().resource_mut::<Effects>().sleeping = !awake;
    app.update();
    app.world_mut()
        .spawn((Collider::plane(), Transform::default()));
    let mut boxes = Vec::new();
    for i in 0..SIDE {
        for k in 0..SIDE {
            for j in 0..HEIGHT {
                let p = Vec3::new(i as f32, HALF + 2.0 * HALF * j as f32, k as f32);
                let e = app.world_mut().spawn((
                    RigidBody::Dynamic,
                    Collider::cuboid(HALF, HALF, HALF),
                    Mass(1.0),
                    Transform::from_translation(p),
                ));
                boxes.push(e.id());
            }
        }
    }
    let steps = (minutes * 60.0 * 60.0) as u64;
    let run = |app: &mut App, n: u64| {
        let target = app.world().resource::<PhysicsWorld>().step_count() + n;
        while app.world().resource::<PhysicsWorld>().step_count() < target {
            app.update();
        }
    };
    run(&mut app, 600); // settle for 10 s
    let settled: Vec<Vec3> = boxes.iter().map(|&b| position(&app, b)).collect();
    let e0 = energy(&app, &boxes);
    let rss0 = resident_kib();
    println!(
        "{} boxes, sleeping {}, {minutes} simulated minutes; settled energy {e0:.3} J, RSS {rss0} KiB",
        boxes.len(),
        if awake { "off" } else { "on" }
    );
    let started = std::time::Instant::now();
    let (mut worst_drift, mut worst_gain, mut worst_rss) = (0.0f32, f32::NEG_INFINITY, rss0);
    let chunks = 10u64;
    for c in 1..=chunks {
        run(&mut app, steps / chunks);
        let moved = |i: usize| position(&app, boxes[i]) - settled[i];
        let worst = (0..boxes.len())
            .max_by(|&a, &b| moved(a).length().total_cmp(&moved(b).length()))
            .unwrap_or(0);
        let drift = moved(worst).length();
        let gain = energy(&app, &boxes) - e0;
        let rss = resident_kib();
        worst_drift = worst_drift.max(drift);
        worst_gain = worst_gain.max(gain);
        worst_rss = worst_rss.max(rss);
        println!(
            "{:5.1} min: max drift {:.4} mm (box {worst}: level {} of stack {}, by {:.4} mm), \
             energy {gain:+.4} J, RSS {rss} KiB, {:.1} s wall",
            minutes * c as f64 / chunks as f64,
            drift * 1000.0,
            worst % HEIGHT,
            worst / HEIGHT,
            moved(worst) * 1000.0,
            started.elapsed().as_secs_f64()
        );
    }
    // Energy: f32 round-off of a sum of 1,000 terms of ~25 J: allow 1 mJ a body.
    let checks = [
        (
            worst_drift < 1e-3,
            format!("max drift {:.4} mm < 1 mm", worst_drift * 1e3),
        ),
        (
            worst_gain <= 1e-3 * boxes.len() as f32,
            format!("energy gain {worst_gain:+.4} J ≤ 1 mJ a body"),
        ),
        (
            worst_rss <= rss0 + rss0 / 20 + 1024,
            format!("RSS {worst_rss} KiB ≤ {rss0} KiB + 5 % + 1 MiB"),
        ),
    ];
    let mut ok = true;
    for (pass, what) in &checks {
        println!("{} {what}", if *pass { "pass" } else { "FAIL" });
        ok &= pass;
    }
    std::process::exit(if ok { 0 } else { 1 });
}

fn position(app: &App, e: Entity) -> Vec3 {
    app.world().get::<Transform>(e).unwrap().translation
}

/// Kinetic (translation and rotation) plus potential energy, J.
fn energy(app: &App, boxes: &[Entity]) -> f32 {
    let g = app.world().resource::<Gravity>().0;
    let inertia = Collider::cuboid(HALF, HALF, HALF)
        .shape
        .principal_inertia(1.0);
    boxes
        .iter()
        .map(|&b| {
            let v = app.world().get::<Velocity>(b).unwrap();
            0.5 * v.linear.length_squared() + 0.5 * inertia.x * v.angular.length_squared()
                - g.dot(position(app, b))
        })
        .sum()
}

/// Resident set size of this process, KiB (Linux; 0 elsewhere).
fn resident_kib() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * 4)
}
