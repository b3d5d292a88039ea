//! The contact pass, batched in SIMD lanes against one contact at a time, on the
//! contacts the solver had after a second of each scene (warm start, one solve pass and
//! the fixed contacts again), and the packing into batches (once a step in the solver,
//! which makes 8–20 passes a step): µs, medians of interleaved rounds (release, one
//! thread). Both passes must leave the same bits.
//!
//! `cargo bench --features bench-internals --bench contact_pass`

use std::time::Instant;

use tumble::bench_api::ContactPass;
use tumble::scene::SceneDesc;

const ROUNDS: usize = 15;
const PASSES: usize = 10;

fn main() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    println!(
        "| scene | contacts | scalar pass µs | batched pass µs | × scalar | packing µs \
         | batches | lanes filled | scalar contacts | levels | sweeps a batch |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for file in [
        "assets/scenes/3_pyramid.scene.ron",
        "assets/scenes/9_rain.scene.ron",
        "peers/scenes/large_pyramid.scene.ron",
        "peers/scenes/ball_pit.scene.ron",
    ] {
        let scene = SceneDesc::load(root.join(file)).expect("scene file");
        let mut pass = ContactPass::from_scene(&scene, 60);
        pass.run(true);
        let batched = pass.velocity_bits();
        pass.reset();
        pass.run(false);
        assert!(batched == pass.velocity_bits(), "{file}: the passes differ");
        pass.reset();
        let mut times = [Vec::new(), Vec::new()];
        let mut packing = Vec::new();
        for _ in 0..ROUNDS {
            let start = Instant::now();
            for _ in 0..PASSES {
                pass.pack();
            }
            packing.push(start.elapsed().as_secs_f64() * 1e6 / PASSES as f64);
            for (batched, t) in [false, true].into_iter().zip(&mut times) {
                let start = Instant::now();
                for _ in 0..PASSES {
                    pass.run(batched);
                    std::hint::black_box(&pass);
                }
                t.push(start.elapsed().as_secs_f64() * 1e6 / PASSES as f64);
            }
        }
        let median = |mut t: Vec<f64>| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        };
        let [scalar, batched] = times.map(median);
        let packing = median(packing);
        let name = file
            .rsplit('/')
            .next()
            .unwrap()
            .trim_end_matches(".scene.ron");
        let n = pass.contacts();
        let ratio = batched / scalar;
        let (batches, filled, lone, levels) = pass.packing();
        let sweeps = pass.sweeps_per_batch();
        let fill = 100.0 * filled as f64 / (batches * 4).max(1) as f64;
        println!(
            "| {name} | {n} | {scalar:.0} | {batched:.0} | {ratio:.2} | {packing:.0} \
             | {batches} | {fill:.0} % | {lone} | {levels} | {sweeps:.2} |"
        );
    }
}
