//! The step's broad phase tree (parry3d's BVH over boxes enlarged past the swept ones,
//! with the pairs of overlapping enlarged boxes kept from step to step: see
//! `world/awake_tree.rs`) against the sweep and prune it replaced (insertion-sorted from
//! last step's order) and parry3d's BVH as rapier uses it (leaves updated and the tree
//! refitted each step, then a self-traversal), on boxes like the peers' scenes' over 60
//! steps of motion: µs per step, median of interleaved rounds (release, one thread). All
//! three must find the same pairs.
//!
//! `cargo bench --features bench-internals --bench broad_phase`

use std::time::Instant;

use bevy::prelude::*;
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use tumble::bench_api::{BroadPhaseTree, Rnd, SweepAndPrune};

const STEPS: usize = 60;
const ROUNDS: usize = 9;

/// Box centres for each step and the boxes' half size (fattened by the 2 cm margin).
struct Scene {
    name: &'static str,
    frames: Vec<Vec<Vec3>>,
    half: Vec3,
}

fn boxes(s: &Scene, k: usize) -> Vec<(Vec3, Vec3)> {
    s.frames[k]
        .iter()
        .map(|&c| (c - s.half, c + s.half))
        .collect()
}

/// 2000 bodies of 0.5 m falling at 5 m/s through a 18 × 28 × 18 m column (rain).
fn rain() -> Scene {
    let mut rnd = Rnd(21);
    let start: Vec<Vec3> = (0..2000)
        .map(|_| {
            Vec3::new(
                rnd.range(-9.0, 9.0),
                rnd.range(2.0, 30.0),
                rnd.range(-9.0, 9.0),
            )
        })
        .collect();
    let frames = (0..STEPS)
        .map(|k| {
            start
                .iter()
                .map(|&p| p - Vec3::Y * (5.0 / 60.0) * k as f32)
                .collect()
        })
        .collect();
    Scene {
        name: "rain (2000)",
        frames,
        half: Vec3::splat(0.27),
    }
}

/// The 385-cube pyramid at rest, every cube trembling by 0.1 mm.
fn pyramid() -> Scene {
    let mut start = vec![];
    for layer in 0..10 {
        let n = 10 - layer;
        for i in 0..n {
            for j in 0..n {
                let off = (n as f32 - 1.0) * 0.5;
                start.push(Vec3::new(
                    i as f32 - off,
                    0.5 + layer as f32,
                    j as f32 - off,
                ));
            }
        }
    }
    let mut rnd = Rnd(7);
    let frames = (0..STEPS)
        .map(|_| start.iter().map(|&p| p + rnd.vec(-1e-4, 1e-4)).collect())
        .collect();
    Scene {
        name: "pyramid (385)",
        frames,
        half: Vec3::splat(0.52),
    }
}

/// 10,000 balls of 1 m touching on a 1 m grid (22 × 22 × 21) at rest, every one
/// trembling by 0.1 mm (the ball pit scaled up, settled).
fn ball_pile() -> Scene {
    let start: Vec<Vec3> = (0..10_000)
        .map(|i| {
            let (x, y, z) = (i % 22, (i / 22) % 22, i / 484);
            Vec3::new(x as f32, y as f32, z as f32)
        })
        .collect();
    let mut rnd = Rnd(9);
    let frames = (0..STEPS)
        .map(|_| start.iter().map(|&p| p + rnd.vec(-1e-4, 1e-4)).collect())
        .collect();
    Scene {
        name: "ball pile (10,000)",
        frames,
        half: Vec3::splat(0.52),
    }
}

/// µs a step and pairs found over the scene's steps, by `pairs` (the boxes of each step
/// made beforehand).
fn timed(s: &Scene, mut pairs: impl FnMut(&[(Vec3, Vec3)]) -> usize) -> (f64, usize) {
    let all: Vec<_> = (0..STEPS).map(|k| boxes(s, k)).collect();
    let t = Instant::now();
    let found = all.iter().map(|b| pairs(b)).sum();
    (t.elapsed().as_secs_f64() * 1e6 / STEPS as f64, found)
}

fn tree(s: &Scene) -> (f64, usize) {
    let mut tree = BroadPhaseTree::default();
    timed(s, |b| tree.pairs(b).len())
}

fn sap(s: &Scene) -> (f64, usize) {
    let mut sap = SweepAndPrune::default();
    timed(s, |b| sap.pairs(b).len())
}

fn parry(s: &Scene) -> (f64, usize) {
    let all: Vec<Vec<Aabb>> = (0..STEPS)
        .map(|k| {
            boxes(s, k)
                .into_iter()
                .map(|(lo, hi)| Aabb::new(lo, hi))
                .collect()
        })
        .collect();
    let mut bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &all[0]);
    let mut ws = BvhWorkspace::default();
    let t = Instant::now();
    let mut pairs = 0;
    for b in &all {
        for (i, aabb) in b.iter().enumerate() {
            bvh.insert_or_update_partially(*aabb, i as u32, 0.0);
        }
        bvh.refit(&mut ws);
        bvh.traverse_bvtt_single_tree::<false>(&mut ws, &mut |_, _| pairs += 1);
    }
    (t.elapsed().as_secs_f64() * 1e6 / STEPS as f64, pairs)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    println!(
        "| scene | step's tree µs/step | sweep and prune | parry BVH | SAP / tree | parry / tree | pairs |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for s in [rain(), pyramid(), ball_pile()] {
        let (mut t, mut a, mut b) = (vec![], vec![], vec![]);
        let mut found = [0; 3];
        for _ in 0..ROUNDS {
            for (k, (run, times)) in [
                (tree as fn(&Scene) -> (f64, usize), &mut t),
                (sap, &mut a),
                (parry, &mut b),
            ]
            .into_iter()
            .enumerate()
            {
                let (ms, p) = run(&s);
                times.push(ms);
                found[k] = p;
            }
        }
        assert!(
            found.iter().all(|&p| p == found[0]),
            "{}: {found:?} pairs",
            s.name
        );
        let (t, o, p) = (median(t), median(a), median(b));
        println!(
            "| {} | {t:.1} | {o:.1} | {p:.1} | {:.2} | {:.2} | {} |",
            s.name,
            o / t,
            p / t,
            found[0]
        );
    }
}
