//! What each effect costs: the same scenes stepped with only the effects they need, with
//! everything on, and with each other effect added alone. Prints a table (median step
//! time of interleaved rounds, single-threaded release build).
//!
//! `cargo bench --bench effects`

use std::time::Instant;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::prelude::*;
use tumble::scene::SceneDesc;
use tumble::timings::{STAGES, StepTimings};

const ROUNDS: usize = 9;
const STEPS: usize = 30;

struct Case {
    label: String,
    app: App,
    samples: Vec<f64>,
    /// Per-stage ms of each step, summed over a round.
    stages: Vec<[f64; STAGES.len()]>,
}

fn app_for(scene: &SceneDesc, effects: Effects) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
        .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
    app.update();
    scene.spawn_into(app.world_mut());
    app.insert_resource(effects);
    app.insert_resource(GlobalForce(Vec3::new(0.5, 0.0, 0.0)));
    for _ in 0..20 {
        app.update();
    }
    app
}

fn cases(scene: &SceneDesc, needed: Effects) -> Vec<Case> {
    let mut out = vec![
        Case {
            label: "only what it needs".into(),
            app: app_for(scene, needed),
            samples: vec![],
            stages: vec![],
        },
        Case {
            label: "all effects".into(),
            app: app_for(scene, Effects::ALL),
            samples: vec![],
            stages: vec![],
        },
    ];
    let names: Vec<&str> = needed.clone().toggles().iter().map(|(n, _)| *n).collect();
    for (i, name) in names.into_iter().enumerate() {
        let mut with = needed;
        let toggles = with.toggles();
        let (_, on) = toggles.into_iter().nth(i).unwrap();
        if *on {
            continue;
        }
        *on = true;
        out.push(Case {
            label: format!("+ {name}"),
            app: app_for(scene, with),
            samples: vec![],
            stages: vec![],
        });
    }
    out
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn run(title: &str, scene: &SceneDesc, needed: Effects) {
    let mut cases = cases(scene, needed);
    for _ in 0..ROUNDS {
        for case in cases.iter_mut() {
            let started = Instant::now();
            let mut stages = [0.0; STAGES.len()];
            for _ in 0..STEPS {
                case.app.update();
                let t = case.app.world().resource::<StepTimings>();
                for (sum, ms) in stages.iter_mut().zip(t.stage_ms) {
                    *sum += ms / STEPS as f64;
                }
            }
            case.stages.push(stages);
            case.samples
                .push(started.elapsed().as_secs_f64() * 1e3 / STEPS as f64);
        }
    }
    let step = |c: &Case| {
        let mut totals: Vec<f64> = c.stages.iter().map(|s| s.iter().sum()).collect();
        median(&mut totals)
    };
    let base = step(&cases[0]);
    println!(
        "\n### {title}\n\n| effects | step ms | × needed | marginal ms | app update ms | {} |\n|---|---:|---:|---:|---:|{}",
        STAGES.join(" | "),
        "---:|".repeat(STAGES.len())
    );
    for case in cases.iter_mut() {
        let m = step(case);
        let per_stage: Vec<String> = (0..STAGES.len())
            .map(|i| {
                let mut v: Vec<f64> = case.stages.iter().map(|s| s[i]).collect();
                format!("{:.3}", median(&mut v))
            })
            .collect();
        println!(
            "| {} | {m:.3} | {:.2} | {:+.3} | {:.3} | {} |",
            case.label,
            m / base,
            m - base,
            median(&mut case.samples),
            per_stage.join(" | ")
        );
    }
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let load = |name: &str| SceneDesc::load(dir.join(name)).expect("scene file");

    // 1000 balls in free flight: gravity is all they need.
    let mut free = load("9_rain.scene.ron");
    free.planes.clear();
    free.bodies.truncate(1);
    if let tumble::scene::BodyGroup::Pile {
        count, min, max, ..
    } = &mut free.bodies[0]
    {
        *count = 1000;
        (*min, *max) = (Vec3::new(-30.0, 0.0, -30.0), Vec3::new(30.0, 60.0, 30.0));
    }
    run("1000 balls in free flight", &free, Effects::FREE_FLIGHT);

    // The 385-cube pyramid: gravity, collisions, friction, rotation.
    let pyramid = load("3_pyramid.scene.ron");
    let needed = Effects {
        damping: false,
        wind: false,
        global_force: false,
        restitution: false,
        sleeping: false,
        ..Effects::ALL
    };
    run("385-cube pyramid", &pyramid, needed);
}
