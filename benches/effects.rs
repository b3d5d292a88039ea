//! What each effect costs: the same scenes stepped with only the effects they need, with
//! everything on, and with each other effect added alone. Prints a table (median step
//! time of interleaved rounds, single-threaded release build).
//!
//! Also the gather and writeback of 10,000 bodies (free flight, where they are nearly
//! the whole step).
//!
//! `cargo bench --bench effects [-- <title filter>]`

use std::time::Instant;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::prelude::*;
use tumble::scene::SceneDesc;
use tumble::settings::GlobalForce;
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

impl Case {
    /// A headless app with `effects`, set up by `setup` and warmed up for 20 steps.
    fn new(label: impl Into<String>, effects: Effects, setup: impl FnOnce(&mut World)) -> Self {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
            .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
        app.update();
        setup(app.world_mut());
        app.insert_resource(effects);
        app.insert_resource(GlobalForce(Vec3::new(0.5, 0.0, 0.0)));
        for _ in 0..20 {
            app.update();
        }
        Self {
            label: label.into(),
            app,
            samples: vec![],
            stages: vec![],
        }
    }
}

/// The scene with only what it needs, with everything, with each other effect added
/// alone, and with each needed effect taken away alone.
fn effect_cases(scene: &SceneDesc, needed: Effects) -> Vec<Case> {
    let spawn = |w: &mut World| {
        scene.spawn_into(w);
    };
    let mut out = vec![
        Case::new("only what it needs", needed, spawn),
        Case::new("all effects", Effects::ALL, spawn),
    ];
    let count = needed.clone().toggles().len();
    for i in 0..count {
        let mut changed = needed;
        let mut toggles = changed.toggles();
        let (name, on) = &mut toggles[i];
        let label = format!("{} {name}", if **on { "−" } else { "+" });
        **on = !**on;
        out.push(Case::new(label, changed, spawn));
    }
    out
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Whether a table was asked for: `cargo bench --bench effects -- pyramid` runs only the
/// tables whose title contains "pyramid".
fn wanted(title: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    filters.is_empty() || filters.iter().any(|f| title.contains(f.as_str()))
}

fn run(title: &str, cases: impl FnOnce() -> Vec<Case>) {
    if !wanted(title) {
        return;
    }
    let mut cases = cases();
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
    run("1000 balls in free flight", || {
        effect_cases(&free, Effects::FREE_FLIGHT)
    });

    // Gather and writeback at 10,000 bodies: in free flight prepare and writeback are
    // nearly the whole step, so this times their per-body cost at scale.
    let mut many = free.clone();
    if let tumble::scene::BodyGroup::Pile { count, .. } = &mut many.bodies[0] {
        *count = 10_000;
    }
    run("10000 balls in free flight (gather and writeback)", || {
        let spawn = |w: &mut World| {
            many.spawn_into(w);
        };
        vec![Case::new("only what it needs", Effects::FREE_FLIGHT, spawn)]
    });

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
    run("385-cube pyramid", || effect_cases(&pyramid, needed));

    run("a bouncing ball among 1000 boxes", still_bodies_cases);

    // Game features a scene does not use cost nothing: collision events are opt-in per
    // collider. The pyramid (about 1,100 touching contacts) with events on every cube
    // and with none.
    run("collision events on the 385-cube pyramid", || {
        let with_events = |w: &mut World| {
            pyramid.spawn_into(w);
            let cubes: Vec<Entity> = w
                .query_filtered::<Entity, With<RigidBody>>()
                .iter(w)
                .collect();
            for e in cubes {
                w.entity_mut(e).insert(CollisionEventsEnabled);
            }
        };
        vec![
            Case::new("no events (the default)", needed, |w| {
                pyramid.spawn_into(w);
            }),
            Case::new("events on every cube", needed, with_events),
        ]
    });
}

/// A ball bouncing on the ground, alone and among 1000 boxes that are static, asleep or
/// awake: static and sleeping bodies should cost only their fixed-set entry.
fn still_bodies_cases() -> Vec<Case> {
    let effects = Effects {
        damping: false,
        wind: false,
        global_force: false,
        ..Effects::ALL
    };
    let ball = |w: &mut World| {
        w.spawn((Collider::plane(), Transform::default()));
        w.spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.5),
            Restitution(0.9),
            Transform::from_xyz(1.0, 3.0, 0.0),
        ));
    };
    // A 40 × 25 field of 0.6 m cubes resting on the ground 2 m apart; the ball bounces in a
    // gap between four of them (x = 1, z = 0), so it never touches them.
    let boxes = |kind: RigidBody, asleep: bool| {
        move |w: &mut World| {
            ball(w);
            for i in 0..1000 {
                let (x, z) = ((i % 40) as f32 * 2.0 - 40.0, (i / 40) as f32 * 2.0 - 25.0);
                let mut e = w.spawn((
                    kind,
                    Collider::cuboid(0.3, 0.3, 0.3),
                    Transform::from_xyz(x, 0.3, z),
                ));
                if asleep {
                    e.insert(Sleeping);
                }
            }
        }
    };
    let awake = Effects {
        sleeping: false,
        ..effects
    };
    vec![
        Case::new("the ball alone", effects, ball),
        Case::new(
            "+ 1000 static boxes",
            effects,
            boxes(RigidBody::Static, false),
        ),
        Case::new(
            "+ 1000 sleeping boxes",
            effects,
            boxes(RigidBody::Dynamic, true),
        ),
        Case::new(
            "+ 1000 awake boxes (sleeping off)",
            awake,
            boxes(RigidBody::Dynamic, false),
        ),
    ]
}
