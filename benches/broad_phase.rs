//! Our broad phase (sweep and prune, insertion-sorted from last step's order) against
//! parry3d's BVH (leaves updated and the tree refitted each step, as rapier does, then a
//! self-traversal) on the peers' scenes' boxes over 60 steps of motion: µs per step,
//! median of interleaved rounds (release, one thread). Both must find the same pairs.
//!
//! `cargo bench --features bench-internals --bench broad_phase`

use std::time::Instant;

use bevy::prelude::*;
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use tumble::bench_api::{Rnd, SweepAndPrune};

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

fn ours(s: &Scene) -> (f64, usize) {
    let mut sap = SweepAndPrune::default();
    let all: Vec<_> = (0..STEPS).map(|k| boxes(s, k)).collect();
    let t = Instant::now();
    let mut pairs = 0;
    for b in &all {
        pairs += sap.pairs(b).len();
    }
    (t.elapsed().as_secs_f64() * 1e6 / STEPS as f64, pairs)
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
    println!("| scene | ours µs/step | parry BVH µs/step | parry / ours | pairs (ours, parry) |");
    println!("|---|---:|---:|---:|---|");
    for s in [rain(), pyramid()] {
        let (mut a, mut b) = (vec![], vec![]);
        let (mut pa, mut pb) = (0, 0);
        for _ in 0..ROUNDS {
            let (t, p) = ours(&s);
            a.push(t);
            pa = p;
            let (t, p) = parry(&s);
            b.push(t);
            pb = p;
        }
        let (o, p) = (median(a), median(b));
        println!(
            "| {} | {o:.1} | {p:.1} | {:.2} | {pa}, {pb} |",
            s.name,
            p / o
        );
    }
}
