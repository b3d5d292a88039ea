//! Where a scene's step spends its time: loads a scene file, runs it headless (one step
//! per update, sleeping off as in `peers/`), and prints each stage's median wall time
//! over the timed steps (and the whole update's, as `peers/` times it) with the step's
//! counts (substeps, manifolds) and how far the bodies moved (the largest displacement of
//! any body since it was spawned) and how many still move at the end.
//!
//! ```sh
//! cargo run --release --example stage_times -- peers/scenes/large_pyramid.scene.ron 30 100 [threads]
//! ```
//! `threads`: the compute pool's threads (default: Bevy's choice for this machine).

use bevy::prelude::*;
use tumble::prelude::*;
use tumble::scene::SceneDesc;
use tumble::timings::STAGES;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(file) = args.next() else {
        eprintln!("usage: stage_times <scene file> [warm-up steps] [timed steps]");
        std::process::exit(2);
    };
    let warm: u64 = args
        .next()
        .map_or(30, |s| s.parse().expect("warm-up steps"));
    let timed: usize = args.next().map_or(100, |s| s.parse().expect("timed steps"));
    if let Some(threads) = args.next() {
        let n: usize = threads.parse().expect("threads");
        let pool = || bevy::tasks::TaskPoolBuilder::new().num_threads(n).build();
        bevy::tasks::ComputeTaskPool::get_or_init(pool);
    }
    let scene = SceneDesc::load(&file).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1);
    });
    let (mut app, bodies) = scene.headless_app();
    let position = |app: &App, e: Entity| app.world().get::<Transform>(e).map(|t| t.translation);
    let start: Vec<_> = bodies.iter().map(|&e| position(&app, e)).collect();
    app.world_mut().resource_mut::<Effects>().sleeping = false;
    for _ in 0..warm {
        app.update();
    }
    let mut stages = vec![Vec::with_capacity(timed); STAGES.len()];
    let (mut total, mut counts) = (Vec::new(), (0, 0, 0, 0));
    let mut sweeps = Vec::with_capacity(timed);
    let mut reused = 0;
    let mut passes = (0u64, 0u64);
    let mut wall = Vec::with_capacity(timed);
    for _ in 0..timed {
        let started = std::time::Instant::now();
        app.update();
        wall.push(started.elapsed().as_secs_f64() * 1e3);
        let t = app.world().resource::<StepTimings>();
        for (s, ms) in stages.iter_mut().zip(t.stage_ms) {
            s.push(ms);
        }
        total.push(t.total_ms());
        let w = app.world().resource::<PhysicsWorld>();
        sweeps.push(f64::from(w.normal_sweeps_per_batch()));
        reused += w.reused_manifolds();
        passes.0 += u64::from(w.iterations());
        passes.1 += u64::from(w.relax_iterations());
        counts = (
            counts.0.max(w.substeps()),
            counts.1.max(w.iterations()),
            w.contact_manifolds(),
            w.contact_points(),
        );
    }
    let (substeps, iterations, manifolds, points) = counts;
    println!("{file}: {timed} steps after {warm}");
    println!("  substeps {substeps}, passes {iterations}, manifolds {manifolds}, points {points}");
    let per_step = |n: u64| n as f64 / timed.max(1) as f64;
    println!(
        "  passes a substep (mean): solve {:.2}, relax {:.2}",
        per_step(passes.0),
        per_step(passes.1)
    );
    // Work, not time: the same on any machine, however busy.
    let mean_sweeps = sweeps.iter().sum::<f64>() / sweeps.len().max(1) as f64;
    println!("  normal sweeps per batch and pass {mean_sweeps:.3} (mean over the timed steps)");
    let reused = reused as f64 / timed.max(1) as f64;
    println!("  manifolds reused, moved from the step before: {reused:.0} a step (mean)");
    for (name, s) in STAGES.iter().zip(&mut stages) {
        println!("  {name:<14} {:8.3} ms", median(s));
    }
    println!(
        "  {:<14} {:8.3} ms (median step)",
        "total",
        median(&mut total)
    );
    println!(
        "  {:<14} {:8.3} ms (median app.update(), the stages and all else)",
        "update",
        median(&mut wall)
    );
    let moved = bodies.iter().zip(&start);
    let moved = moved.filter_map(|(&e, &s)| Some((position(&app, e)? - s?, s?)));
    let (d, from) = moved.fold((Vec3::ZERO, Vec3::ZERO), |a, b| {
        if b.0.length() > a.0.length() { b } else { a }
    });
    println!(
        "  largest displacement {:.3} m (by {d}, from {from})",
        d.length()
    );
    let speeds: Vec<f32> = bodies
        .iter()
        .filter_map(|&e| app.world().get::<Velocity>(e).map(|v| v.linear.length()))
        .collect();
    let fast = speeds.iter().filter(|&&s| s > 0.1).count();
    let fastest = speeds.iter().copied().fold(0.0, f32::max);
    println!(
        "  at the end: {fast} of {} bodies faster than 0.1 m/s, the fastest {fastest:.3} m/s",
        speeds.len()
    );
}
