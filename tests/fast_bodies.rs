//! Fast bodies don't tunnel: contacts are created speculatively as far ahead as the pair
//! can close in one step, so a 200 m/s ball stops at a 10 cm wall.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::TAU;
use tumble::prelude::*;

/// A static contact at the default 4 substeps: 60 Hz (a quarter of the substep rate),
/// damping ratio ζ = 10 (src/step/5_solve/stiffness.rs, softness.rs).
const OMEGA: f32 = TAU * 60.0;
const ZETA: f32 = 10.0;

/// The lowest point of a body, how far its lowest corner is above y = 0.
fn lowest(app: &App, e: Entity, h: Vec3) -> f32 {
    let q = rot(app, e);
    pos(app, e).y
        - (0..3)
            .map(|i| h[i] * (q * Vec3::AXES[i]).y.abs())
            .sum::<f32>()
}

#[test]
fn ball_at_200_mps_never_passes_a_thin_wall() {
    let mut app = app_without_gravity();
    // A static wall 0.1 m thick, its near face at x = 10.
    app.world_mut().spawn((
        Collider::cuboid(0.05, 2.0, 2.0),
        Transform::from_xyz(10.05, 0.0, 0.0),
    ));
    let (r, v0) = (0.1, 200.0);
    let b = ball(&mut app, r, 1.0, Vec3::ZERO, Vec3::X * v0);
    let touching = 10.0 - r;
    // The speculative contact lets the ball close its gap and no more, so it stops touching
    // the face: x = 9.9 up to f32 round-off of 10 m positions (ulp 1e-6 m; 1e-4 m is 100 of
    // them). Restitution is 0 (the default): no rebound. What an overlap of up to 1e-4 m
    // could give back is the soft contact's push-out, at its bias rate
    // ω/(2ζ + hs·ω) = 17.5/s: 1.75e-3 m/s.
    let x_tol = 1e-4;
    let hs = H / 4.0;
    let v_tol = OMEGA / (2.0 * ZETA + hs * OMEGA) * x_tol;
    let mut hit = None;
    for k in 1..=60 {
        step(&mut app, 1);
        let (x, u) = (pos(&app, b).x, vel(&app, b).linear);
        assert!(
            x <= touching + x_tol,
            "step {k}: ball at x = {x}, inside or past the wall"
        );
        match hit {
            None if x < touching - x_tol => {
                // Still in flight, no gravity: untouched.
                assert_near_vec(u, Vec3::X * v0, 1e-3, &format!("step {k}: in flight"));
                assert_near(
                    x,
                    v0 * k as f32 * H,
                    1e-3,
                    &format!("step {k}: x in flight"),
                );
            }
            _ => {
                hit.get_or_insert(k);
                assert_near(
                    x,
                    touching,
                    x_tol,
                    &format!("step {k}: stopped at the face"),
                );
                assert!(
                    u.length() <= v_tol,
                    "step {k}: moving at {u} after the impact (e = 0: no rebound, bound {v_tol})"
                );
            }
        }
    }
    // 9.9 m at 200 m/s: it reaches the wall in the third step's flight (9.9/3.33 = 2.97).
    assert_eq!(hit, Some(3), "reached the wall in step {hit:?}");
}

#[test]
fn fast_box_lands_on_the_ground_instead_of_falling_through() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let h = Vec3::splat(0.25);
    let b = cuboid(&mut app, h, 1.0, Vec3::new(0.0, 3.0, 0.0));
    app.world_mut()
        .entity_mut(b)
        .insert(Velocity::linear(Vec3::NEG_Y * 150.0));
    // A speculative point closes its gap and no more; below the floor a point only sinks by
    // the soft contact's give under the load it carries. The most one point can give: the
    // whole weight on one corner, whose row has inverse mass 1/m + r⊥²/I = 4/m for a cube
    // (r⊥² = 2·0.25², I = m·0.5²/6), so 4·g/ω² = 0.28 mm.
    let give = 4.0 * G / (OMEGA * OMEGA);
    for k in 1..=60 {
        step(&mut app, 1);
        let low = lowest(&app, b, h);
        assert!(
            low >= -give,
            "step {k}: lowest corner at y = {low}, deeper than {give} below the floor"
        );
    }
    // On the floor at the end, on whichever face: centre between 0.25 − give and 0.25.
    let y = pos(&app, b).y;
    assert!((0.25 - give..=0.25).contains(&y), "box at y = {y}");
}

/// With restitution 0 a box that lands flat stops where it lands. One Gauss–Seidel sweep
/// over the four corner rows of an impact leaves their impulses lopsided (the rows are
/// coupled through the box), and the warm-started excess throws it back up (at 2.6 m/s,
/// tumbling, to slide off at 4 m/s). So the solver sweeps a manifold's normal rows again
/// until they settle (at most 4 times).
#[test]
fn fast_box_landing_flat_stops_dead() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let h = Vec3::splat(0.25);
    let b = cuboid(&mut app, h, 1.0, Vec3::new(0.0, 3.0, 0.0));
    app.world_mut()
        .entity_mut(b)
        .insert(Velocity::linear(Vec3::NEG_Y * 150.0));
    // Resting sag of a full face: s = g/ω² (a cube's corner rows cancel the four-way split).
    let s = G / (OMEGA * OMEGA);
    for k in 1..=60 {
        step(&mut app, 1);
        let u = vel(&app, b).linear;
        // It covers 2.5 m a step from 2.75 m up: it touches down in step 2.
        if k >= 2 {
            // After touching down: held within one sag by a spring of angular frequency ω,
            // it can move up at no more than ω·s = g/ω = 0.026 m/s.
            assert!(
                u.y <= OMEGA * s,
                "step {k}: rebounding at {u} (e = 0; bound {})",
                OMEGA * s
            );
        }
    }
    // Where it landed, flat: the impact is vertical, so it stays within the drift a flat
    // drop is allowed (box_stacking: 2 cm), at the full-face sag (settled as in
    // box_stacking: a tenth of it), leaning at most (s + 0.1·s) across its 0.5 m base.
    let p = pos(&app, b);
    assert_near(p.y, 0.25 - s, 0.1 * s, "resting height");
    assert!(p.xz().length() < 0.02, "slid to {p}");
    let lean = (rot(&app, b) * Vec3::Y).xz().length();
    assert!(lean <= 1.1 * s / 0.5, "lean {lean}");
}
