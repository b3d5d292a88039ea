//! Side by side: the same scene files stepped by tumble, avian3d 0.7 and bevy_rapier3d
//! 0.36, each in its own headless Bevy app (MinimalPlugins + TransformPlugin + the physics
//! plugin, one 60 Hz physics step per `update()`), in the same run, interleaved round by
//! round. Prints the median time of one `update()` per engine and the ratios to tumble,
//! and a behaviour check (how far the bodies sank and how fast they still move at the
//! end) so that a fast engine is not fast because it did less.
//!
//! Each engine runs at its own defaults (tumble 4 substeps; avian 6 substeps; rapier 4
//! solver iterations = substeps, one step) with sleeping off everywhere. Threads: Bevy's
//! compute pool pinned to `--threads N` threads (default 1); avian (with its default
//! `parallel` feature) and tumble split work across it, and bevy_rapier3d's `parallel`
//! feature is off by default.
//! The scenes: the demo's spheres, tower, pyramid and rain, and the three big ones in
//! `peers/scenes/` (a 5,050-cube flat pyramid, 100 small pyramids, a 4,096-ball pit).
//!
//! `cargo run --release -p tumble-peers [-- <scene filter>] [--threads N] [--stages]`;
//! with `--scaling`, the ball pit at 1k … 16k balls and each engine's fitted exponent;
//! with `--stages`, tumble's median time in each stage of its step too.

mod avian;
mod rapier;
mod scaling;

use std::time::Instant;

use bevy::app::{TaskPoolOptions, TaskPoolThreadAssignmentPolicy};
use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::scene::SceneDesc;
use tumble::timings::{STAGES, StepTimings};

const ROUNDS: usize = 9;
const STEPS: usize = 20;
const WARM_UP: usize = 30;

/// One engine's app on one scene.
struct Run {
    engine: &'static str,
    app: App,
    bodies: Vec<Entity>,
    start_y: Vec<f32>,
    samples: Vec<f64>,
}

/// Runs plugins' `finish` and `cleanup` (which `App::run` would) and the first update,
/// which only starts the clock.
pub fn start(app: &mut App) {
    app.finish();
    app.cleanup();
    // Systems run one after another on the caller, as in a headless test; the engines'
    // own work is what uses the pool's threads (Bevy's multi-threaded executor costs
    // about 0.7 ms an update here with one pool thread, more than a small scene's step).
    let mut schedules = app.world_mut().resource_mut::<Schedules>();
    for (_, schedule) in schedules.iter_mut() {
        schedule.set_executor(SingleThreadedExecutor::new());
    }
    app.update();
}

/// Threads of the compute pool (`--threads N`; default 1). Bevy is built here with
/// `multi_threaded` (avian's default `parallel` feature turns it on), which needs at
/// least one pool thread; at one, avian and tumble solve serially, and the caller only
/// waits on it.
static THREADS: std::sync::OnceLock<usize> = std::sync::OnceLock::new();

/// `--stages`: also print tumble's median time in each stage of its step.
static STAGE_TIMES: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// A headless app that runs exactly one 60 Hz fixed step per update, its compute pool
/// pinned to [`THREADS`] (the pools are global: the first app sets them for the run).
pub fn headless_app() -> App {
    let threads = *THREADS.get().unwrap_or(&1);
    let compute = TaskPoolThreadAssignmentPolicy {
        min_threads: threads,
        max_threads: threads,
        percent: 1.0,
        on_thread_spawn: None,
        on_thread_destroy: None,
    };
    let pools = TaskPoolPlugin {
        task_pool_options: TaskPoolOptions {
            compute,
            ..default()
        },
    };
    let mut app = App::new();
    app.add_plugins((MinimalPlugins.set(pools), TransformPlugin))
        .insert_resource(Time::<Fixed>::from_hz(60.0))
        .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
    app
}

fn tumble_app(scene: &SceneDesc) -> (App, Vec<Entity>) {
    let mut app = headless_app();
    app.add_plugins(tumble::TumblePlugin::default());
    start(&mut app);
    let bodies = scene.spawn_into(app.world_mut());
    app.world_mut()
        .resource_mut::<tumble::prelude::Effects>()
        .sleeping = false;
    (app, bodies)
}

impl Run {
    fn new(engine: &'static str, (app, bodies): (App, Vec<Entity>)) -> Self {
        let start_y = bodies.iter().map(|&e| y_of(&app, e)).collect();
        Self {
            engine,
            app,
            bodies,
            start_y,
            samples: vec![],
        }
    }

    /// Mean drop of the bodies since the start (m) and the fastest body's speed (m/s),
    /// from `Transform` and the finite difference of one more step.
    fn behaviour(&mut self) -> (f32, f32) {
        let before: Vec<Vec3> = self.bodies.iter().map(|&e| pos_of(&self.app, e)).collect();
        self.app.update();
        let mut drop = 0.0;
        let mut fastest = 0.0f32;
        for ((&e, p0), y0) in self.bodies.iter().zip(&before).zip(&self.start_y) {
            let p = pos_of(&self.app, e);
            drop += y0 - p.y;
            fastest = fastest.max((p - *p0).length() * 60.0);
        }
        (drop / self.bodies.len().max(1) as f32, fastest)
    }
}

fn pos_of(app: &App, e: Entity) -> Vec3 {
    app.world()
        .get::<Transform>(e)
        .map_or(Vec3::NAN, |t| t.translation)
}

fn y_of(app: &App, e: Entity) -> f32 {
    pos_of(app, e).y
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn compare(file: &str) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = SceneDesc::load(dir.join(file)).expect("scene file");
    compare_scene(&scene);
}

/// Times the three engines on `scene`, prints the table, and returns each engine's median
/// ms a step (tumble, avian3d, bevy_rapier3d).
pub fn compare_scene(scene: &SceneDesc) -> [f64; 3] {
    let mut runs = [
        Run::new("tumble", tumble_app(&scene)),
        Run::new("avian3d", avian::app(&scene)),
        Run::new("bevy_rapier3d", rapier::app(&scene)),
    ];
    for run in runs.iter_mut() {
        for _ in 0..WARM_UP {
            run.app.update();
        }
    }
    // tumble's own stage times, step by step (read outside the timed spans).
    let mut stages = vec![vec![]; STAGES.len()];
    for _ in 0..ROUNDS {
        for (k, run) in runs.iter_mut().enumerate() {
            let started = Instant::now();
            for _ in 0..STEPS {
                run.app.update();
            }
            run.samples
                .push(started.elapsed().as_secs_f64() * 1e3 / STEPS as f64);
            if k == 0 {
                let t = run.app.world().resource::<StepTimings>();
                stages
                    .iter_mut()
                    .zip(t.stage_ms)
                    .for_each(|(s, ms)| s.push(ms));
            }
        }
    }
    let steps = WARM_UP + ROUNDS * STEPS + 1;
    println!(
        "\n### {} ({} bodies, {} steps, {} thread(s))\n\n| engine | ms / step | × tumble | mean drop m | fastest m/s |\n|---|---:|---:|---:|---:|",
        scene.name,
        runs[0].bodies.len(),
        steps,
        THREADS.get().unwrap_or(&1)
    );
    let base = median(&mut runs[0].samples.clone());
    let mut out = [0.0; 3];
    for (k, run) in runs.iter_mut().enumerate() {
        let m = median(&mut run.samples);
        let (drop, fastest) = run.behaviour();
        println!(
            "| {} | {m:.3} | {:.2} | {drop:.3} | {fastest:.2} |",
            run.engine,
            m / base
        );
        out[k] = m;
    }
    // The same bits at every thread count (the split levels and the narrow phase's runs
    // join in a fixed order): compare this line across `--threads`.
    let hash = tumble::state_hash::state_hash(runs[0].app.world_mut());
    println!("\ntumble's state after the run: {hash:016x}");
    if STAGE_TIMES.get() == Some(&true) {
        // Each round's last step, so the median of ROUNDS steps: where the threads go.
        let line: Vec<String> = STAGES
            .iter()
            .zip(&mut stages)
            .map(|(name, s)| format!("{name} {:.3}", median(s)))
            .collect();
        println!("tumble's stages, median ms: {}", line.join(", "));
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let threads = args
        .iter()
        .position(|a| a == "--threads")
        .and_then(|i| args.get(i + 1))
        .map(|n| n.parse::<usize>().expect("--threads takes a count").max(1))
        .unwrap_or(1);
    THREADS.set(threads).expect("set once");
    STAGE_TIMES
        .set(args.iter().any(|a| a == "--stages"))
        .expect("set once");
    if args.iter().any(|a| a == "--scaling") {
        scaling::run();
        return;
    }
    let filters: Vec<String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| !a.starts_with("--") && !(*i > 0 && args[i - 1] == "--threads"))
        .map(|(_, a)| a.clone())
        .collect();
    for file in [
        "../assets/scenes/1_spheres_in_a_box.scene.ron",
        "../assets/scenes/2_box_tower.scene.ron",
        "../assets/scenes/3_pyramid.scene.ron",
        "../assets/scenes/9_rain.scene.ron",
        "scenes/large_pyramid.scene.ron",
        "scenes/many_pyramids.scene.ron",
        "scenes/ball_pit.scene.ron",
    ] {
        if filters.is_empty() || filters.iter().any(|f| file.contains(f.as_str())) {
            compare(file);
        }
    }
}
