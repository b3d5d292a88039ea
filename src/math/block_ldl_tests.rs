//! The block LDLᵀ against a dense reference: random systems shaped like the joints',
//! dependent rows, and the fill of a chain and a tree.

use super::block_ldl::*;
use crate::rng::Rnd;

/// A random system shaped like the joints': `bodies` bodies, each node a joint of
/// random size between two of them (or one and the world), A = J M⁻¹ Jᵀ (+ `soft`
/// on the diagonal). Returns the sizes, edges and the dense matrix.
fn system(
    rng: &mut Rnd,
    nodes: usize,
    bodies: usize,
    soft: f64,
) -> (Vec<usize>, Vec<(u32, u32)>, Vec<Vec<f64>>) {
    let sizes: Vec<usize> = (0..nodes)
        .map(|_| 1 + (rng.unit() * 6.0) as usize % 6)
        .collect();
    let ends: Vec<(usize, Option<usize>)> = (0..nodes)
        .map(|_| {
            let a = (rng.unit() * bodies as f32) as usize % bodies;
            let b = (rng.unit() * bodies as f32) as usize % bodies;
            (a, (b != a).then_some(b))
        })
        .collect();
    let rows: usize = sizes.iter().sum();
    // J: rows × 6·bodies, dense; M⁻¹ diagonal.
    let inv_mass: Vec<f64> = (0..6 * bodies)
        .map(|_| rng.range(0.01, 10.0) as f64)
        .collect();
    let mut j = vec![vec![0.0f64; 6 * bodies]; rows];
    let mut r = 0;
    for (k, &(a, b)) in ends.iter().enumerate() {
        for _ in 0..sizes[k] {
            for body in [Some(a), b].into_iter().flatten() {
                for d in 0..6 {
                    j[r][6 * body + d] = rng.range(-1.0, 1.0) as f64;
                }
            }
            r += 1;
        }
    }
    let mut dense = vec![vec![0.0; rows]; rows];
    for (r, row) in dense.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = (0..6 * bodies)
                .map(|d| j[r][d] * inv_mass[d] * j[c][d])
                .sum();
        }
        row[r] += soft;
    }
    let mut edges = Vec::new();
    for (x, &(a, b)) in ends.iter().enumerate() {
        for (y, &(c, d)) in ends.iter().enumerate().skip(x + 1) {
            let shares = [Some(a), b]
                .into_iter()
                .flatten()
                .any(|e| e == c || Some(e) == d);
            if shares {
                edges.push((x as u32, y as u32));
            }
        }
    }
    (sizes, edges, dense)
}

fn load(p: &BlockPattern, sizes: &[usize], dense: &[Vec<f64>]) -> BlockMatrix {
    let mut m = BlockMatrix::default();
    m.reset(p);
    let node_of: Vec<(u32, usize)> = sizes
        .iter()
        .enumerate()
        .flat_map(|(k, &s)| (0..s).map(move |r| (k as u32, r)))
        .collect();
    for (r, &(a, ra)) in node_of.iter().enumerate() {
        for (c, &(b, rb)) in node_of.iter().enumerate().skip(r) {
            if a == b {
                m.add_diag(a, ra, rb, dense[r][c]);
            } else if p.coupling(a, b).is_some() {
                m.add_coupling(p, (a, ra), (b, rb), dense[r][c]);
            } else {
                assert_eq!(dense[r][c], 0.0, "an uncoupled pair has no entry");
            }
        }
    }
    m
}

fn residual(dense: &[Vec<f64>], x: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    dense
        .iter()
        .zip(b)
        .map(|(row, b)| (row.iter().zip(x).map(|(a, x)| a * x).sum::<f64>() - b).abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn the_block_solve_solves_random_joint_systems() {
    let mut rng = Rnd(7);
    for round in 0..40 {
        let (nodes, bodies) = (2 + round % 25, 2 + round % 13);
        let (sizes, edges, dense) = system(&mut rng, nodes, bodies, 1e-3);
        let p = BlockPattern::new(&sizes, &edges);
        let mut m = load(&p, &sizes, &dense);
        m.factor(&p);
        let b: Vec<f64> = (0..m.rows()).map(|_| rng.range(-1.0, 1.0) as f64).collect();
        let mut x = b.clone();
        m.solve(&p, &mut x);
        let res = residual(&dense, &x, &b);
        assert!(res < 1e-8, "round {round}: residual {res}");
    }
}

#[test]
fn dependent_rows_are_dropped_and_the_rest_still_hold() {
    // Rigid (no softness) with more rows than the bodies' freedoms: many rows depend
    // on others. A consistent right-hand side (A·y) must still be met.
    let mut rng = Rnd(11);
    for round in 0..20 {
        let (sizes, edges, dense) = system(&mut rng, 6 + round % 5, 2, 0.0);
        let p = BlockPattern::new(&sizes, &edges);
        let mut m = load(&p, &sizes, &dense);
        m.factor(&p);
        let y: Vec<f64> = (0..m.rows()).map(|_| rng.range(-1.0, 1.0) as f64).collect();
        let b: Vec<f64> = dense
            .iter()
            .map(|row| row.iter().zip(&y).map(|(a, y)| a * y).sum())
            .collect();
        let mut x = b.clone();
        m.solve(&p, &mut x);
        assert!(x.iter().all(|v| v.is_finite()));
        let res = residual(&dense, &x, &b);
        assert!(res < 1e-6, "round {round}: residual {res}");
    }
}

#[test]
fn a_chain_and_a_tree_fill_nothing() {
    // A chain of 30 joints: 29 couplings. A star of 3 arms of 4 joints around a hub
    // body: the hub's 3 joints couple pairwise (3), each arm's in a row (3 × 3).
    let chain: Vec<(u32, u32)> = (0..29).map(|i| (i, i + 1)).collect();
    assert_eq!(BlockPattern::new(&[3; 30], &chain).fill(), 29);
    let mut star = vec![(0, 4), (0, 8), (4, 8)];
    for arm in [0u32, 4, 8] {
        star.extend((arm..arm + 3).map(|i| (i, i + 1)));
    }
    assert_eq!(BlockPattern::new(&[5; 12], &star).fill(), 12);
}
