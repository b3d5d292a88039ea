//! Impulses and forces at a point, with analytic answers: Δv = J/m and Δω = I⁻¹(r × J),
//! v = F·t/m and ω = I⁻¹(r × F)·t; an impulse applies exactly once under every frame
//! pacing, wakes a sleeper, and a bad one is dropped.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// A cube, so its inertia is the same about every axis and ω stays put between impulses:
/// I = m·(2a)²/6 for half size a.
const HALF: f32 = 0.25;
const M: f32 = 3.0;
fn cube_inertia() -> f32 {
    M * (2.0 * HALF) * (2.0 * HALF) / 6.0
}

#[test]
fn an_impulse_at_a_point_moves_and_turns_the_body_as_theory_says() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.insert_resource(Gravity(Vec3::ZERO));
        let c = Vec3::new(1.0, 2.0, 3.0);
        let b = cuboid(app, Vec3::splat(HALF), M, c);
        let (j, point) = (Vec3::new(0.0, 0.0, 6.0), c + Vec3::new(HALF, 0.1, 0.0));
        app.world_mut()
            .entity_mut(b)
            .insert(ExternalImpulse::at_point(j, point, c));
        step(app, 30);
        let v = vel(app, b);
        assert_near_vec(v.linear, j / M, 1e-6, &format!("{what}: Δv = J/m"));
        let expected = (point - c).cross(j) / cube_inertia();
        // ω is constant for a cube, but each substep takes it into the body frame and
        // back: f32 round-off of a few ε per substep, over 120 substeps.
        let tol = 4.0 * f32::EPSILON * 120.0 * expected.length();
        assert_near_vec(
            v.angular,
            expected,
            tol,
            &format!("{what}: Δω = I⁻¹(r × J)"),
        );
        // Applied once: after 30 steps (0.5 s) the centre moved v·t.
        assert_near_vec(
            pos(app, b),
            c + j / M * 0.5,
            1e-5,
            &format!("{what}: x = v·t"),
        );
        let left = *app.world().get::<ExternalImpulse>(b).unwrap();
        assert!(left.is_zero(), "{what}: consumed");
    });
}

#[test]
fn impulses_of_several_frames_add_up_and_apply_once() {
    for pacing in Pacing::GAME {
        let what = format!("{pacing:?}");
        let mut app = paced_app(pacing, false);
        app.insert_resource(Gravity(Vec3::ZERO));
        let b = cuboid(&mut app, Vec3::splat(HALF), M, Vec3::ZERO);
        // Three frames, each adding an impulse, whether or not they step.
        for _ in 0..3 {
            app.world_mut()
                .get_mut::<ExternalImpulse>(b)
                .map(|mut i| {
                    i.apply(Vec3::X);
                })
                .unwrap_or_else(|| {
                    app.world_mut()
                        .entity_mut(b)
                        .insert(ExternalImpulse::new(Vec3::X));
                });
            frames(&mut app, 1);
        }
        step(&mut app, 2);
        assert_near_vec(vel(&app, b).linear, Vec3::X * 3.0 / M, 1e-6, &what);
    }
}

#[test]
fn a_jump_wakes_the_body_and_reaches_the_height_its_impulse_implies() {
    for pacing in Pacing::GAME {
        let what = format!("{pacing:?}");
        let mut app = paced_app(pacing, true);
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let (r, m) = (0.3, 2.0);
        let b = ball(&mut app, r, m, Vec3::Y * r, Vec3::ZERO);
        step(&mut app, 120);
        assert!(asleep(&app, b), "{what}: asleep before the jump");
        let v0 = 4.0;
        app.world_mut()
            .entity_mut(b)
            .insert(ExternalImpulse::new(Vec3::Y * m * v0));
        let mut top = 0.0f32;
        for _ in 0..60 {
            step(&mut app, 1);
            top = top.max(pos(&app, b).y - r);
        }
        // Apex v0²/2g; semi-implicit Euler at substep hs = h/4 peaks lower by at most
        // v0·hs/2 (half a substep of rise), plus the contact's resting sag (< 1 mm).
        let apex = v0 * v0 / (2.0 * G);
        assert_near(top, apex, v0 * H / 8.0 + 1e-3, &format!("{what}: apex"));
    }
}

#[test]
fn a_bad_impulse_is_dropped_and_the_body_carries_on() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.3, 1.0, Vec3::Y * 0.3, Vec3::ZERO);
    step(&mut app, 30);
    for bad in [Vec3::NAN, Vec3::INFINITY, Vec3::X * 1e30] {
        app.world_mut()
            .entity_mut(b)
            .insert(ExternalImpulse::new(bad));
        step(&mut app, 1);
        assert!(rejected_field(&app, b).is_none(), "{bad}: not rejected");
        assert!(
            vel(&app, b).linear.length() < 1e-3,
            "{bad}: velocity unchanged"
        );
        assert_near(pos(&app, b).y, 0.3, 1e-3, &format!("{bad}: still resting"));
        assert!(app.world().get::<ExternalImpulse>(b).unwrap().is_zero());
    }
}

#[test]
fn a_force_at_a_point_pushes_and_turns() {
    let mut app = app_without_gravity();
    let c = Vec3::ZERO;
    let b = cuboid(&mut app, Vec3::splat(HALF), M, c);
    let (f, point) = (Vec3::Y * 3.0, Vec3::new(HALF, 0.0, 0.0));
    app.world_mut()
        .entity_mut(b)
        .insert(ExternalForce::at_point(f, point, c));
    step(&mut app, 60);
    let t = 1.0;
    assert_near_vec(vel(&app, b).linear, f * t / M, 1e-5, "v = F·t/m");
    let tau = (point - c).cross(f);
    assert_near_vec(
        vel(&app, b).angular,
        tau * t / cube_inertia(),
        1e-4,
        "ω = τ·t/I",
    );
}
