//! Prints the state hash of a scene file after N physics steps (one step per update,
//! sleeping as the scene says): the determinism fingerprint. Two processes, two
//! machines or two builds that print the same hash simulated every bit alike.
//!
//! ```sh
//! cargo run --release --example state_hash -- assets/scenes/4_mixed_masses.scene.ron 600
//! ```

use tumble::prelude::*;
use tumble::scene::SceneDesc;
use tumble::state_hash::state_hash;

fn main() {
    let mut args = std::env::args().skip(1);
    let (Some(file), Some(steps)) = (args.next(), args.next()) else {
        eprintln!("usage: state_hash <scene file> <steps>");
        std::process::exit(2);
    };
    let steps: u64 = steps.parse().expect("steps must be a whole number");
    let scene = SceneDesc::load(&file).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1);
    });
    let (mut app, _) = scene.headless_app();
    while app.world().resource::<PhysicsWorld>().step_count() < steps {
        app.update();
    }
    println!(
        "{:016x}  {file} after {steps} steps",
        state_hash(app.world_mut())
    );
}
