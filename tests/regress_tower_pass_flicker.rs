//! Regression: the solve passes of a resting tower followed the rounding of its impulses.
//!
//! The passes a substep grow with the decades of the largest load ratio (1 up to 10:1).
//! A ten-high tower of equal cubes carries exactly 10:1 on its bottom contact, and read
//! from the impulses, which the passes converge to 1 % (`NORMAL_TOL`), the ratio came out
//! 10 ± 2·10⁻⁵ from step to step: the tower took 1 or 2 solve passes a substep as the
//! rounding fell (1.35 on average), its stiffness changing from step to step for nothing.
//! Fixed: a ratio within `RATIO_BAND` (the passes' own 1 %) above a decade counts as that
//! decade.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_resting_ten_cube_tower_takes_one_pass_every_step() {
    let (n, m) = (10, 1.0);
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        let floor = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let cubes: Vec<Entity> = (0..n)
            .map(|i| {
                // Every other cube 1 cm aside, as in the box tower scene.
                let x = if i % 2 == 1 { 0.01 } else { 0.0 };
                cuboid(
                    &mut app,
                    Vec3::splat(0.5),
                    m,
                    Vec3::new(x, 0.5 + i as f32, 0.0),
                )
            })
            .collect();
        step(&mut app, 120);
        for k in 0..240 {
            step(&mut app, 1);
            let world = app.world().resource::<PhysicsWorld>();
            // The floor carries the whole tower: the load the rule reads is 10:1, to
            // the passes' 1 %.
            let carried: f32 = world
                .contacts_of(cubes[0])
                .filter(|c| c.other == floor)
                .map(|c| c.normal_force)
                .sum();
            assert_near(
                carried,
                n as f32 * m * G,
                0.01 * n as f32 * m * G,
                "floor load",
            );
            assert_eq!(
                world.iterations(),
                1,
                "{pacing:?}, step {k}: {} solve passes at a 10:1 load of {carried} N",
                world.iterations()
            );
        }
    }
}
