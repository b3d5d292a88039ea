//! Effects that are off have no influence, effects switched at run time act from the next
//! step, and per-body opt-outs (GravityScale, LockRotation) hold through collisions.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::TAU;
use tumble::prelude::*;

fn set(app: &mut App, f: impl FnOnce(&mut Effects)) {
    f(&mut app.world_mut().resource_mut::<Effects>());
}

#[test]
fn without_gravity_a_body_at_rest_stays_exactly_at_rest() {
    let mut app = app();
    set(&mut app, |e| e.gravity = false);
    let b = ball(&mut app, 0.5, 1.0, Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO);
    step(&mut app, 120);
    assert_eq!(pos(&app, b), Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(vel(&app, b), Velocity::ZERO);
}

#[test]
fn switching_gravity_off_acts_from_the_next_step() {
    let mut app = app();
    let b = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 10);
    let v10 = vel(&app, b).linear;
    set(&mut app, |e| e.gravity = false);
    step(&mut app, 1);
    assert_eq!(vel(&app, b).linear, v10, "no gravity in the very next step");
    set(&mut app, |e| e.gravity = true);
    step(&mut app, 1);
    assert!((vel(&app, b).linear.y - (v10.y - G * H)).abs() < 1e-5);
}

#[test]
fn locked_rotation_keeps_orientation_through_a_corner_landing() {
    let tilted = Quat::from_euler(EulerRot::XYZ, 0.4, 0.3, 0.2);
    // The lowest corner lies `ext` below the centre: the box's support along −Y.
    let ext: f32 = (0..3).map(|i| 0.5 * (tilted * Vec3::AXES[i]).y.abs()).sum();
    // Resting on that one corner it sinks by the soft contact's sag s = g/ω²: a static contact
    // at the default 4 substeps runs at a quarter of the substep rate, 60 Hz, and a corner
    // of a body that cannot turn has the body's own mass as its effective mass
    // (src/step/5_solve/stiffness.rs). s = 0.069 mm.
    let omega = TAU * 60.0;
    let sag = G / (omega * omega);
    // It lands when the corner has fallen 2 − ext (t = √(2(2 − ext)/g) = 0.50 s). The landing
    // impulse m·√(2g(2 − ext)) = 4.9 N·s allows μ·4.9 = 2.45 N·s of friction (μ = 0.5),
    // more than the 1 N·s of its slide, so the slide ends in the landing step: x = 1 m/s · t
    // within one step's travel, 1 m/s · H.
    let t_land = (2.0 * (2.0 - ext) / G).sqrt();
    for scene_wide in [false, true] {
        let mut app = app();
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y * 2.0);
        let mut entity = app.world_mut().entity_mut(b);
        entity.insert((
            Transform::from_xyz(0.0, 2.0, 0.0).with_rotation(tilted),
            Velocity::linear(Vec3::X),
        ));
        if scene_wide {
            set(&mut app, |e| e.rotation = false);
        } else {
            app.world_mut().entity_mut(b).insert(LockRotation);
        }
        step(&mut app, 120);
        assert!(
            rot(&app, b).angle_between(tilted) < 1e-5,
            "turned to {:?}",
            rot(&app, b)
        );
        assert_eq!(vel(&app, b).angular, Vec3::ZERO);
        let p = pos(&app, b);
        // 1.5 s after landing: the over-damped contact (ζ = 10) relaxes at ω/2ζ ≈ 19/s, so
        // the transient is e^-28 of the sag; what is left is f32 round-off (6e-8 m at
        // y ≈ 0.8), far inside a tenth of the sag.
        assert_near(p.y, ext - sag, 0.1 * sag, "resting on its lowest corner");
        assert_near(p.x, t_land, H, "slid until the landing stopped it");
        assert_near(p.z, 0.0, H, "sideways");
        // At rest: a body held within ±0.1·s by a spring of angular frequency ω moves at most
        // ω·0.1·s = 2.6 mm/s.
        let v = vel(&app, b).linear.length();
        assert!(v <= omega * 0.1 * sag, "still moving at {v} m/s");
    }
}

#[test]
fn without_collisions_bodies_pass_through_and_no_collision_stage_runs() {
    let mut app = app();
    set(&mut app, |e| e.collisions = false);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.5, 1.0, Vec3::Y, Vec3::ZERO);
    step(&mut app, 60);
    // Free fall from 1 m for 1 s (semi-implicit, hs = 1/240).
    assert!((pos(&app, b).y - (1.0 - 0.5 * G * (1.0 + 1.0 / 240.0))).abs() < 1e-4);
    let world = app.world().resource::<PhysicsWorld>();
    assert!(world.candidate_pairs() == 0 && world.contact_manifolds() == 0);
}

#[test]
fn without_friction_a_box_slides_down_a_ramp_at_g_sin_theta() {
    let theta = 0.25f32;
    let tilt_q = Quat::from_rotation_z(theta);
    let mut app = app();
    set(&mut app, |e| e.friction = false);
    ground(&mut app, Vec3::ZERO, tilt_q);
    let p = tilt_q * Vec3::Y * 0.5;
    let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, p);
    app.world_mut().entity_mut(b).insert((
        Friction(1.0),
        Transform::from_translation(p).with_rotation(tilt_q),
    ));
    step(&mut app, 30);
    let v0 = vel(&app, b).linear.length();
    step(&mut app, 60);
    let a = vel(&app, b).linear.length() - v0;
    assert!(
        (a - G * theta.sin()).abs() < 0.01 * G * theta.sin(),
        "a = {a}"
    );
}

#[test]
fn without_restitution_a_bouncy_ball_does_not_bounce() {
    let mut app = app();
    set(&mut app, |e| e.restitution = false);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.5, 1.0, Vec3::Y * 3.0, Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Restitution(0.9));
    step(&mut app, 60);
    let mut highest = 0.0f32;
    for _ in 0..60 {
        step(&mut app, 1);
        highest = highest.max(pos(&app, b).y);
    }
    assert!(highest < 0.51, "rose to {highest}");
}

#[test]
fn damping_off_ignores_drag_and_wind_drags_bodies_along() {
    let mut app = app_without_gravity();
    set(&mut app, |e| e.damping = false);
    let b = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::X * 2.0);
    app.world_mut().entity_mut(b).insert(LinearDamping(3.0));
    step(&mut app, 30);
    assert_eq!(vel(&app, b).linear, Vec3::X * 2.0);

    // Wind: a = k·(w − v), so v → w with rate k (RK4: exact to f32 rounding).
    let mut app = app_without_gravity();
    app.insert_resource(Integrator::Rk4);
    app.insert_resource(Wind {
        velocity: Vec3::new(4.0, 0.0, 0.0),
        drag: 0.5,
        ..default()
    });
    set(&mut app, |e| e.wind = true);
    let b = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    step(&mut app, 120);
    let expected = 4.0 * (1.0 - (-0.5f32 * 2.0).exp());
    assert!(
        (vel(&app, b).linear.x - expected).abs() < 1e-4,
        "{} vs {expected}",
        vel(&app, b).linear.x
    );
}

#[test]
fn gravity_scale_per_body() {
    let mut app = app();
    let float = ball(&mut app, 0.5, 1.0, Vec3::ZERO, Vec3::ZERO);
    let heavy = ball(&mut app, 0.5, 1.0, Vec3::X * 5.0, Vec3::ZERO);
    app.world_mut().entity_mut(float).insert(GravityScale(0.0));
    app.world_mut().entity_mut(heavy).insert(GravityScale(2.0));
    step(&mut app, 60);
    assert_eq!(pos(&app, float), Vec3::ZERO);
    assert!((vel(&app, heavy).linear.y + 2.0 * G).abs() < 1e-4);
}
