//! The scaling curve: the ball pit (balls r 0.5 m on a grid 1.2 m apart, dropped into a
//! walled box sized to the grid) at 1,000 to 16,000 balls (10,000 among them), each engine's ms a step, and
//! the exponent k of a least-squares fit ms ∝ Nᵏ.

use tumble::scene::SceneDesc;

/// The grids: 1,000, 2,000, 4,096, 8,000, 10,000 (the real-time target at 60 Hz) and
/// 16,000 balls.
const GRIDS: [(u32, u32, u32); 6] = [
    (10, 10, 10),
    (20, 10, 10),
    (16, 16, 16),
    (20, 20, 20),
    (25, 20, 20),
    (40, 20, 20),
];

fn ball_pit(nx: u32, ny: u32, nz: u32) -> SceneDesc {
    let (hx, hz) = (nx as f32 * 0.6 + 0.5, nz as f32 * 0.6 + 0.5);
    let ron = format!(
        "(name: \"Ball pit {n}\", settings: (effects: (sleeping: false)), planes: [
            (normal: (0.0, 1.0, 0.0)),
            (normal: (1.0, 0.0, 0.0), position: ({mx}, 0.0, 0.0)),
            (normal: (-1.0, 0.0, 0.0), position: ({hx}, 0.0, 0.0)),
            (normal: (0.0, 0.0, 1.0), position: (0.0, 0.0, {mz})),
            (normal: (0.0, 0.0, -1.0), position: (0.0, 0.0, {hz})),
        ], bodies: [
            Grid(body: (shape: Sphere(0.5), position: ({x0}, 1.0, {z0}), mass: Some(1.0)),
                count: ({nx}, {ny}, {nz}), spacing: (1.2, 1.2, 1.2)),
        ])",
        n = nx * ny * nz,
        mx = -hx,
        mz = -hz,
        x0 = -(nx as f32 - 1.0) * 0.6,
        z0 = -(nz as f32 - 1.0) * 0.6,
    );
    SceneDesc::from_ron(&ron, "ball pit").expect("the generated scene parses")
}

/// Least-squares slope of ln(ms) against ln(N).
fn exponent(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points.iter().map(|&(n, t)| (n.ln(), t.ln())).collect();
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    sxy / sxx
}

pub fn run() {
    let mut rows = Vec::new();
    for (nx, ny, nz) in GRIDS {
        let n = (nx * ny * nz) as f64;
        rows.push((n, crate::compare_scene(&ball_pit(nx, ny, nz))));
    }
    println!(
        "\n### Scaling: the ball pit, ms a step\n\n| balls | tumble | avian3d | bevy_rapier3d |\n|---:|---:|---:|---:|"
    );
    for (n, [t, a, r]) in &rows {
        println!("| {n} | {t:.2} | {a:.2} | {r:.2} |");
    }
    let fit = |k: usize| exponent(&rows.iter().map(|(n, m)| (*n, m[k])).collect::<Vec<_>>());
    println!(
        "| fitted exponent | {:.2} | {:.2} | {:.2} |",
        fit(0),
        fit(1),
        fit(2)
    );
}
