//! Our hand-written shape pairs against parry3d's on the same poses: ns per manifold,
//! median of interleaved rounds (release, one thread). The poses are the parity test's
//! kind: B at the origin, A about as far as the two reach, half of them touching.
//!
//! `cargo bench --features bench-internals --bench pairs`

use std::hint::black_box;
use std::time::Instant;

use bevy::prelude::*;
use tumble::bench_api::{Implementation, Rnd, collide};
use tumble::collider::Shape;

const POSES: usize = 2000;
const ROUNDS: usize = 15;

type Pose = (Shape, Vec3, Quat);

fn poses(
    a: impl Fn(&mut Rnd) -> Shape,
    b: impl Fn(&mut Rnd) -> Shape,
    plane: bool,
) -> Vec<(Pose, Pose)> {
    let mut rnd = Rnd(0x2545_F491);
    (0..POSES)
        .map(|_| {
            let (sa, sb) = (a(&mut rnd), b(&mut rnd));
            let rb = rnd.rot();
            let reach = |s: &Shape| match *s {
                Shape::Sphere { radius } => radius,
                Shape::Cuboid { half_extents } => half_extents.length(),
                _ => 0.0,
            };
            let dir = if plane { rb * Vec3::Y } else { rnd.dir() };
            let d = reach(&sa) * rnd.range(0.3, 1.1) + reach(&sb) * rnd.range(0.3, 1.0);
            ((sa, dir * d, rnd.rot()), (sb, Vec3::ZERO, rb))
        })
        .collect()
}

/// ns per manifold for one implementation over the poses.
fn time(with: Implementation, cases: &[(Pose, Pose)]) -> f64 {
    let start = Instant::now();
    let mut points = 0;
    for (a, b) in cases {
        points += collide(with, (&a.0, a.1, a.2), (&b.0, b.1, b.2), 0.02);
    }
    black_box(points);
    start.elapsed().as_nanos() as f64 / cases.len() as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let sphere = |r: &mut Rnd| Shape::Sphere {
        radius: r.range(0.1, 1.0),
    };
    let cuboid = |r: &mut Rnd| Shape::Cuboid {
        half_extents: Vec3::new(r.range(0.1, 1.0), r.range(0.1, 1.0), r.range(0.1, 1.0)),
    };
    let plane = |_: &mut Rnd| Shape::Plane { half_extents: None };
    let pairs: Vec<(&str, Vec<(Pose, Pose)>)> = vec![
        ("sphere–sphere", poses(sphere, sphere, false)),
        ("sphere–box", poses(sphere, cuboid, false)),
        ("box–box", poses(cuboid, cuboid, false)),
        ("sphere–plane", poses(sphere, plane, true)),
        ("box–plane", poses(cuboid, plane, true)),
    ];
    println!("| pair | ours ns | parry ns | parry / ours |");
    println!("|---|---:|---:|---:|");
    for (name, cases) in &pairs {
        let (mut ours, mut parry) = (vec![], vec![]);
        for _ in 0..ROUNDS {
            ours.push(time(Implementation::Ours, cases));
            parry.push(time(Implementation::Parry, cases));
        }
        let (o, p) = (median(ours), median(parry));
        println!("| {name} | {o:.1} | {p:.1} | {:.2} |", p / o);
    }
}
