//! Regression (found by `tests/random_scenes.rs`, seed 11, shrunk): a frictionless rod,
//! 4.5 m long and 2 cm thick (1 kg, restitution 0.9), dropped on its end in a closed
//! room, bounced, tipped, and on its third landing gained 270 J (energy from −23 J to
//! +250 J in one step, step 230), spinning across its length at 18 rad/s.
//!
//! The contact rows carried the world inverse inertia of the start of the step. The rod
//! turns a tenth of a radian in a step, and its inertia about its long axis is 25,000
//! times smaller than across it: an impulse spun it about where its long axis had been,
//! which was now mostly across the rod, at the cheap axis's rate. Fixed by turning the
//! world inertia of anisotropic bodies with them every substep and refreshing the rows
//! that use it (`refresh_rows`); impulses along any row with the true mass matrix and
//! e ≤ 1 cannot add energy. `TRACE=1` prints each step.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_thin_rod_landing_while_turning_gains_no_energy() {
    let mut app = app();
    closed_room(&mut app, 10.0);
    let h = Vec3::new(0.01, 2.244_702, 0.01);
    let rod = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(h.x, h.y, h.z),
            Mass(1.0),
            Transform::default(),
            Restitution(0.896_650_4),
            Friction(0.0),
        ))
        .id();
    let inertia = Collider::cuboid(h.x, h.y, h.z).shape.principal_inertia(1.0);
    let energy = |app: &App| {
        let (v, q) = (vel(app, rod), rot(app, rod));
        let w = q.inverse() * v.angular;
        0.5 * v.linear.length_squared()
            + 0.5 * (inertia * w * w).element_sum()
            + G * pos(app, rod).y
    };
    // Nothing overlaps at spawn and e < 1: the only energy a step may add is a push-out
    // lifting the rod out of at most the speculative margin, m·g·margin (0.2 J).
    let margin = app.world().resource::<SolverSettings>().speculative_margin;
    let e0 = energy(&app);
    let mut landings = 0;
    let mut falling = false;
    for k in 0..400 {
        step(&mut app, 1);
        let e = energy(&app);
        if std::env::var("TRACE").is_ok() {
            eprintln!(
                "{k}: E {e:.2} v {:.2} w {:.1}",
                vel(&app, rod).linear,
                vel(&app, rod).angular
            );
        }
        assert!(e <= e0 + G * margin, "step {k}: energy {e} J from {e0} J");
        let vy = vel(&app, rod).linear.y;
        landings += (falling && vy > 0.0) as u32;
        falling = vy < 0.0;
    }
    // The case is the third landing: make sure it happened.
    assert!(landings >= 3, "only {landings} landings");
}
