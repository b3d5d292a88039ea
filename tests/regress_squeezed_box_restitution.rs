//! Regression (found by `tests/random_scenes.rs` at 50 m/s and 1:1000, seed 1): a
//! 682 kg ball (e = 0.73) came down on a 6.5 kg box lying on the floor, and the box
//! left at 458 m/s with 920 kJ.
//!
//! Restitution reverses the normal velocity a point had when it first pushed. That
//! velocity was read in the middle of the solve, where the box-floor point saw the box
//! being driven into the floor by the ball's contact, not by any approach of its own,
//! and reversed it. Fixed: the approach speed is the start-of-step one, made faster by
//! at most what gravity adds in a step (`ContactConstraint::approach_gain`).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn a_heavy_ball_landing_on_a_light_box_does_not_launch_it() {
    for sleeping in [false, true] {
        let mut app = if sleeping { app_with_sleeping() } else { app() };
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let h = Vec3::new(1.547_613_7, 0.543_048_74, 0.942_578_1);
        let (m_box, m_ball, r) = (6.535_845, 682.743_5, 1.769_580_4);
        let bx = cuboid(&mut app, h, m_box, Vec3::Y * h.y);
        app.world_mut()
            .entity_mut(bx)
            .insert((Restitution(0.430_638_5), Friction(0.668)));
        // Let the box settle (and fall asleep when sleeping is on).
        step(&mut app, 120);
        let top = 2.0 * h.y;
        let ball = ball(
            &mut app,
            r,
            m_ball,
            Vec3::new(0.3, top + r + 0.5, 0.2),
            Vec3::new(2.0, -8.0, -1.5),
        );
        app.world_mut()
            .entity_mut(ball)
            .insert((Restitution(0.727_215_1), Friction(0.159)));
        // Energy of the ball above the floor, with the box's potential energy: nothing
        // may end up with more (push-out can add ½·m·v_push² to the box: 29 J).
        let push = app.world().resource::<SolverSettings>().max_push_out;
        let i_box = Collider::cuboid(h.x, h.y, h.z)
            .shape
            .principal_inertia(m_box);
        let total = |app: &App| {
            let (vb, vx) = (vel(app, ball), vel(app, bx));
            let wx = rot(app, bx).inverse() * vx.angular;
            0.5 * m_ball * vb.linear.length_squared()
                + 0.2 * m_ball * r * r * vb.angular.length_squared()
                + m_ball * G * pos(app, ball).y
                + 0.5 * m_box * vx.linear.length_squared()
                + 0.5 * (i_box * wx * wx).element_sum()
                + m_box * G * pos(app, bx).y
        };
        let e0 = total(&app) + 0.5 * m_box * push * push;
        for k in 0..180 {
            step(&mut app, 1);
            let v = vel(&app, bx).linear.length();
            assert!(
                v < 20.0,
                "sleeping {sleeping}, step {k}: the box left at {v} m/s"
            );
            let e = total(&app);
            assert!(
                e <= e0 * (1.0 + 1e-4),
                "sleeping {sleeping}, step {k}: {e} J from {e0} J"
            );
        }
    }
}
