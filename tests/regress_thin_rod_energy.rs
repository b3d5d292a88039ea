//! Regression (found by `tests/random_scenes.rs`, seed 7, shrunk): a thin rod, 2.5 m long
//! and 2 cm thick (1 kg, restitution 0.81), spawned overlapping a 39 kg ball in a closed
//! room, gained energy without bound: 160 kJ after 194 steps from −164 J. A flat landing
//! spun it up about its long axis (its inertia there is tiny), to 400 rad/s; contact
//! anchors and Jacobians are prepared once per step at the start pose, and a body
//! turning over a radian per substep made them push the wrong way. Fixed by limiting
//! a non-round body's spin in contact to an eighth of a turn per step
//! (`MAX_ROTATION_PER_STEP`, Box2D's limit too). `TRACE=1` prints each step.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn thin_rod_hit_by_a_ball_gains_no_energy() {
    let mut app = app();
    closed_room(&mut app, 10.0);
    let r = 1.429_129_1;
    let ball_pos = Vec3::new(0.976_518_4, -0.202_311_72, -0.573_187_1) * (10.0 - r * 3f32.sqrt());
    let b = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(r),
            Mass(38.763_214),
            Transform::from_translation(ball_pos),
            Velocity::linear(Vec3::new(-1.163_345_2, 0.306_369_66, -4.467_870_7)),
            Restitution(0.0),
            Friction(0.0),
        ))
        .id();
    let rod = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(1.268_202_3, 0.01, 0.01),
            Mass(1.0),
            Transform::default(),
            Restitution(0.814_753_9),
            Friction(0.0),
        ))
        .id();
    let energy = |app: &App| {
        let (vb, vr, qr) = (vel(app, b), vel(app, rod), rot(app, rod));
        let i_rod = Collider::cuboid(1.268_202_3, 0.01, 0.01)
            .shape
            .principal_inertia(1.0);
        let w = qr.inverse() * vr.angular;
        0.5 * 38.763_214 * vb.linear.length_squared()
            + 0.5 * 0.4 * 38.763_214 * r * r * vb.angular.length_squared()
            + 0.5 * vr.linear.length_squared()
            + 0.5 * (i_rod * w * w).element_sum()
            + G * (38.763_214 * pos(app, b).y + pos(app, rod).y)
    };
    let e0 = energy(&app);
    for k in 0..300 {
        step(&mut app, 1);
        let e = energy(&app);
        if std::env::var("TRACE").is_ok() {
            eprintln!(
                "{k}: E {e:.2} rod {:.3} v {:.2} w {:.1} ball {:.3}",
                pos(&app, rod),
                vel(&app, rod).linear,
                vel(&app, rod).angular,
                pos(&app, b)
            );
        }
        // Overlap at spawn may add ½·m·v_push² + m·g·d to the rod (d ≤ the ball's
        // diameter): 4.5 + 28 J.
        assert!(e <= e0 + 33.0, "step {k}: energy {e} J from {e0} J");
    }
}
