//! Our hand-written pairs (sphere–sphere, sphere–box, box–box, sphere–plane, box–plane)
//! against parry3d's convex manifolds on the same random poses: the same touching
//! verdict, normals within 1°, the deepest point's depth within 1e-4 m, the same point
//! count. What disagrees is counted and printed, then held to those criteria.

use bevy::prelude::*;

use super::Manifold;
use super::{DISPATCH, Posed, parry};
use crate::collider::Shape;
use crate::rng::Rnd;

/// Random shapes of the three hand-written kinds.
trait RandomShape {
    fn shape(&mut self, kind: u32) -> Shape;
}

impl RandomShape for Rnd {
    fn shape(&mut self, kind: u32) -> Shape {
        match kind {
            0 => Shape::Sphere {
                radius: self.range(0.1, 1.0),
            },
            1 => Shape::Cuboid {
                half_extents: Vec3::new(
                    self.range(0.1, 1.0),
                    self.range(0.1, 1.0),
                    self.range(0.1, 1.0),
                ),
            },
            _ => Shape::Plane { half_extents: None },
        }
    }
}

/// What one pair gave: whether it touches, the deepest depth, its normal, its points.
#[derive(Debug, Clone, Copy)]
struct Outcome {
    touching: bool,
    depth: f32,
    normal: Vec3,
    points: usize,
}

fn outcome(m: &Manifold) -> Outcome {
    let deepest = m
        .points()
        .iter()
        .map(|p| p.separation)
        .fold(f32::INFINITY, f32::min);
    Outcome {
        touching: deepest <= 0.0,
        depth: -deepest,
        normal: m.normal,
        points: m.len,
    }
}

/// Disagreements over `n` random poses of the pair (`ka` ≤ `kb`): verdicts, normals
/// beyond 1°, depths beyond 1e-4 m, point counts; and how many touched.
fn compare(ka: u32, kb: u32, n: usize, seed: u64) -> ([usize; 5], f32) {
    let mut rnd = Rnd(seed);
    let mut counts = [0usize; 5];
    let mut worst_depth = 0.0f32;
    let margin = 0.02;
    for _ in 0..n {
        let (sa, sb) = (rnd.shape(ka), rnd.shape(kb));
        let rb = rnd.rot();
        // B at the origin; A along a random direction, about as far as the two reach
        // (their bounding spheres), pushed in or pulled out a little.
        let reach = |s: &Shape| match *s {
            Shape::Sphere { radius } => radius,
            Shape::Cuboid { half_extents } => half_extents.length(),
            _ => 0.0,
        };
        let dir = if kb == 2 { rb * Vec3::Y } else { rnd.dir() };
        let d = reach(&sa) * rnd.range(0.3, 1.1)
            + if kb == 2 {
                0.0
            } else {
                reach(&sb) * rnd.range(0.3, 1.0)
            };
        let a = Posed {
            shape: &sa,
            pos: dir * d,
            rot: rnd.rot(),
        };
        let b = Posed {
            shape: &sb,
            pos: Vec3::ZERO,
            rot: rb,
        };
        let f = DISPATCH[ka as usize][sb.kind() as usize].unwrap();
        let (mut ours, mut theirs) = (Manifold::default(), Manifold::default());
        f(a, b, margin, &mut ours);
        parry::collide(a, b, margin, &mut theirs);
        let (o, t) = (outcome(&ours), outcome(&theirs));
        // Within rounding of touching: either verdict is right.
        let borderline =
            (o.depth.abs() < 1e-4 && ours.len > 0) || (t.depth.abs() < 1e-4 && theirs.len > 0);
        if o.touching != t.touching && !borderline {
            counts[0] += 1;
        }
        if o.touching && t.touching {
            counts[4] += 1;
            if o.normal.angle_between(t.normal) > 1f32.to_radians() {
                counts[1] += 1;
            }
            if (o.depth - t.depth).abs() > 1e-4 {
                counts[2] += 1;
            }
            worst_depth = worst_depth.max((o.depth - t.depth).abs());
            if o.points != t.points {
                counts[3] += 1;
            }
        }
    }
    (counts, worst_depth)
}

/// Sphere–sphere, sphere–box, sphere–plane and box–plane agree with parry on every
/// pose. Box–box agrees on every verdict; on 3 % of touching poses it picks another
/// axis than parry, by design: a face is kept over an edge unless the edge separates by
/// [`EDGE_TOLERANCE`](super::box_box) (5 mm) more, and A's face over B's within 1 mm, so
/// resting boxes keep one manifold step after step (their warm start holds). The depth
/// then differs by less than that tolerance, and the clipped point count often differs
/// (parry keeps the points of its own reference face).
#[test]
fn our_pairs_agree_with_parry() {
    let n = 4000;
    let pairs = [
        (0, 0, "sphere–sphere"),
        (0, 1, "sphere–box"),
        (1, 1, "box–box"),
        (0, 2, "sphere–plane"),
        (1, 2, "box–plane"),
    ];
    let mut report = String::new();
    let mut results = vec![];
    for (i, &(ka, kb, name)) in pairs.iter().enumerate() {
        let (c, worst) = compare(ka, kb, n, 0x9E37_79B9 + i as u64);
        report += &format!(
            "{name}: of {n} poses {} touched; verdicts differ {}, normals > 1° {}, depths > 1e-4 m {} (worst {worst:.1e} m), point counts {}\n",
            c[4], c[0], c[1], c[2], c[3]
        );
        results.push((name, c, worst));
    }
    println!("{report}");
    for (name, c, worst) in results {
        assert!(
            c[4] > n / 3,
            "{name}: too few touching poses to compare\n{report}"
        );
        assert_eq!(c[0], 0, "{name}: touching verdicts differ\n{report}");
        if name == "box–box" {
            assert!(
                c[1] * 20 < c[4],
                "box–box: more than 5 % of normals differ\n{report}"
            );
            assert!(
                worst <= 0.005 + 1e-4,
                "box–box: depth beyond the edge tolerance\n{report}"
            );
        } else {
            assert_eq!(
                c[1] + c[2] + c[3],
                0,
                "{name}: disagrees with parry\n{report}"
            );
        }
    }
}
