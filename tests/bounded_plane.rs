//! Bounded planes are walls and ledges of finite size: a ball resting on one stays, a ball
//! just beyond its edge falls past it, and a ball rolling over the edge tips off.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::TAU;
use tumble::prelude::*;

fn ledge(app: &mut App) {
    app.world_mut()
        .spawn((Collider::plane_rect(1.0, 1.0), Transform::default()));
}

/// A static contact at the default 4 substeps runs at a quarter of the substep rate, 60 Hz
/// (src/step/5_solve/stiffness.rs).
const OMEGA: f32 = TAU * 60.0;

/// A ball resting on the ledge sinks by the soft contact's sag s = g/ω² = 0.069 mm (its
/// contact row passes through the centre, so its effective mass is its own mass).
fn sag() -> f32 {
    G / (OMEGA * OMEGA)
}

#[test]
fn ball_rests_on_a_ledge_and_misses_beyond_it() {
    let mut app = app();
    ledge(&mut app);
    let on = ball(&mut app, 0.25, 1.0, Vec3::new(0.5, 0.25, 0.0), Vec3::ZERO);
    let off = ball(&mut app, 0.25, 1.0, Vec3::new(1.5, 1.0, 0.0), Vec3::ZERO);
    step(&mut app, 60);
    // 1 s on an over-damped contact (ζ = 10, slow mode ω/2ζ ≈ 19/s): the transient is
    // e^-19 of the sag; what is left is f32 round-off (3e-8 m at 0.25 m), inside 0.1·s.
    assert_near(
        pos(&app, on).y,
        0.25 - sag(),
        0.1 * sag(),
        "rests on the ledge",
    );
    assert_near_vec(
        pos(&app, on) * Vec3::new(1.0, 0.0, 1.0),
        Vec3::X * 0.5,
        1e-6,
        "stays put",
    );
    // Free fall from 1.0 m for 1 s (semi-implicit, hs = 1/240): y = 1 − ½g(1 + 1/240).
    let expected = 1.0 - 0.5 * G * (1.0 + 1.0 / 240.0);
    assert_near(
        pos(&app, off).y,
        expected,
        1e-4,
        "falls freely past the edge",
    );
}

#[test]
fn ball_rolling_off_the_edge_tips_over_it() {
    let (r, v) = (0.25, 2.0);
    let mut app = app();
    ledge(&mut app);
    let b = ball(&mut app, r, 1.0, Vec3::new(0.0, r, 0.0), Vec3::X * v);
    // Rolling without slip from the start: ω = v/r.
    app.world_mut().entity_mut(b).insert(Velocity {
        linear: Vec3::X * v,
        angular: Vec3::Z * (-v / r),
    });
    let mut track = Vec::new();
    for k in 1..=120 {
        step(&mut app, 1);
        track.push((k, pos(&app, b), vel(&app, b).linear));
    }
    // The first step in free fall: one in which gravity went unanswered for at least half
    // the step.
    let left = track
        .iter()
        .find(|(_, _, u)| u.y < -0.5 * G * H)
        .map(|&(k, _, _)| k)
        .expect("never left the ledge");
    // The centre reaches the edge x = 1 at t = 1 m / 2 m/s = 0.5 s, the end of step 30. A
    // contact is made from the pose at the start of a step, so the step that starts with the
    // centre over the face still carries it, and at 2 m/s (v²/r = 16 m/s² > g) it then
    // leaves the edge at once: free fall starts in step 31, or in step 32 when round-off
    // leaves the centre a hair short of the edge after step 30. A ball that fell through
    // leaves in step 1; one held beyond the edge never leaves.
    assert!(
        (31..=32).contains(&left),
        "free fall began in step {left}, not when the centre passed the edge (31 or 32)"
    );
    // Horizontally nothing acts: rolling at v = ωr needs no friction, and in flight there is
    // none. Allow at most one substep of the largest friction, μ·g·hs = 0.5·g/240 = 0.02 m/s.
    let dv = 0.5 * G * H / 4.0;
    let y_rest = track[left - 2].1.y;
    for &(k, p, u) in &track {
        let t = k as f32 * H;
        assert_near(u.x, v, dv, &format!("step {k}: rolling speed"));
        assert_near(p.x, v * t, dv * t, &format!("step {k}: x"));
        if k < left {
            // On the ledge, settling into its sag: r − 2s ≤ y ≤ r, and no faster vertically
            // than a spring of amplitude s moves, ω·s = g/ω = 0.026 m/s.
            assert_near(p.y, r - sag(), sag(), &format!("step {k}: on the ledge"));
            assert_near(
                u.y,
                0.0,
                OMEGA * sag(),
                &format!("step {k}: vertical speed"),
            );
        } else {
            // Free fall from rest at y_rest since the end of step `left − 1`: after n
            // substeps of hs (semi-implicit), v = −g·n·hs and the drop is ½g·t·(t + hs).
            // Tolerance: f32 round-off of ≤ 360 substep additions at y ~ 10 m (ulp 1e-6 m).
            let t = (k - left + 1) as f32 * H;
            let hs = H / 4.0;
            assert_near(u.y, -G * t, 1e-3, &format!("step {k}: falling speed"));
            assert_near(
                p.y,
                y_rest - 0.5 * G * t * (t + hs),
                1e-3,
                &format!("step {k}: falling over the edge"),
            );
        }
    }
}
