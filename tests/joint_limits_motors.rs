//! Joint limits, motors, ropes, welds and breaking, against their analytic answers: a
//! hinge limit holds a bar under ten times the torque that would turn it, a slider's
//! motor reaches its speed at the rate its force allows, a rope never outgrows its
//! length, a weld keeps its bodies' relative pose, a joint reports the load it carries
//! and breaks at its break force.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn spawn(app: &mut App, bundle: impl Bundle) -> Entity {
    app.world_mut().spawn(bundle).id()
}

fn forces(app: &App, joint: Entity) -> JointForces {
    *app.world().get::<JointForces>(joint).expect("joint forces")
}

#[test]
fn a_hinge_limit_holds_ten_times_the_torque_it_resists() {
    // A 1 kg, 1 m bar hinged to the world at its end about z, limits ±0.3 rad, gravity
    // pulling its far end down (torque m·g·L/2 about the hinge), and a torque of ten
    // times that pushing the same way.
    let mut app = app();
    let (m, l) = (1.0, 1.0);
    let hinge = Vec3::new(0.0, 3.0, 0.0);
    let bar = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::cuboid(l / 2.0, 0.05, 0.05),
            Mass(m),
            Transform::from_translation(hinge + Vec3::X * l / 2.0),
        ),
    );
    let joint = spawn(
        &mut app,
        Joint::revolute(None, bar, Vec3::Z)
            .with_local_anchors(hinge, Vec3::new(-l / 2.0, 0.0, 0.0))
            .with_limits(-0.3, 0.3),
    );
    let gravity_torque = m * G * l / 2.0;
    app.world_mut().entity_mut(bar).insert(ExternalForce {
        force: Vec3::ZERO,
        torque: Vec3::Z * -10.0 * gravity_torque,
    });
    step(&mut app, 180);
    let angle = rot(&app, bar).to_euler(EulerRot::ZYX).0;
    assert_near(angle, -0.3, 0.01, "bar angle at the lower limit, rad");
    // Balance about the bar's centre: the hinge's force carries m·g (up) at the hinge,
    // L/2·cos θ to the side, and the limit's torque takes the rest, (10 + cos θ)·m·g·L/2.
    let f = forces(&app, joint);
    assert_near(f.force.y, m * G, 0.01 * m * G, "hinge force, N");
    let expected = (10.0 + angle.cos()) * gravity_torque;
    assert_near(f.torque.z, expected, 0.01 * expected, "limit torque, N·m");
}

#[test]
fn a_slider_motor_reaches_its_speed_at_the_rate_its_force_allows() {
    // A 2 kg box on a slider along x (no gravity), motor 3 m/s with at most 4 N: it
    // accelerates at F/m = 2 m/s² until 3 m/s (1.5 s), then holds it.
    let mut app = app_without_gravity();
    let (m, f, target) = (2.0, 4.0, 3.0);
    let cart = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::cuboid(0.2, 0.2, 0.2),
            Mass(m),
            Transform::default(),
        ),
    );
    spawn(
        &mut app,
        Joint::prismatic(None, cart, Vec3::X).with_motor(target, f),
    );
    step(&mut app, 30);
    assert_near(
        vel(&app, cart).linear.x,
        f / m * 0.5,
        0.01,
        "speed after 0.5 s, m/s",
    );
    step(&mut app, 90);
    assert_near(
        vel(&app, cart).linear.x,
        target,
        1e-3,
        "speed after 2 s, m/s",
    );
    // Across the axis it has not moved, nor turned.
    let p = pos(&app, cart);
    assert!(p.y.abs() < 1e-4 && p.z.abs() < 1e-4, "off the axis: {p}");
}

#[test]
fn a_slider_stops_at_its_limit() {
    let mut app = app();
    let block = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::cuboid(0.2, 0.2, 0.2),
            Mass(1.0),
            Transform::from_xyz(0.0, 2.0, 0.0),
        ),
    );
    // A vertical slider, the block free to fall 0.5 m below where it starts.
    spawn(
        &mut app,
        Joint::prismatic(None, block, Vec3::Y)
            .with_local_anchors(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO)
            .with_limits(-0.5, 0.5),
    );
    step(&mut app, 120);
    assert_near(
        pos(&app, block).y,
        1.5,
        0.01,
        "height at the lower limit, m",
    );
}

#[test]
fn a_rope_never_outgrows_its_length() {
    // A 1 kg ball on a 2 m rope, let go 0.5 m from the pivot: it falls slack, jerks the
    // rope taut and swings.
    let mut app = app();
    let pivot = Vec3::new(0.0, 5.0, 0.0);
    let ball = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::sphere(0.1),
            Mass(1.0),
            Transform::from_translation(pivot + Vec3::new(0.5, 0.0, 0.0)),
        ),
    );
    spawn(
        &mut app,
        Joint::rope(None, ball, 2.0).with_local_anchors(pivot, Vec3::ZERO),
    );
    let mut longest = 0.0f32;
    for _ in 0..300 {
        step(&mut app, 1);
        longest = longest.max(pos(&app, ball).distance(pivot));
    }
    assert!(longest > 1.9, "the rope went taut: {longest}");
    assert!(longest <= 2.0 * 1.01, "the rope stretched to {longest} m");
}

#[test]
fn a_weld_keeps_its_bodies_relative_pose() {
    // Two boxes welded side by side, one turned 30°, dropped onto the ground: they land,
    // tip and settle as one.
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let a = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::new(0.0, 1.0, 0.0));
    let b = cuboid(
        &mut app,
        Vec3::new(0.5, 0.1, 0.1),
        0.5,
        Vec3::new(0.75, 1.2, 0.0),
    );
    app.world_mut()
        .entity_mut(b)
        .get_mut::<Transform>()
        .unwrap()
        .rotation = Quat::from_rotation_z(0.5);
    let relative = |app: &App| {
        let (ra, rb) = (rot(app, a), rot(app, b));
        (
            ra.inverse() * (pos(app, b) - pos(app, a)),
            ra.inverse() * rb,
        )
    };
    let (p0, q0) = relative(&app);
    // The weld point: b's origin, 0.75 m right and 0.2 m up in a's frame.
    let at = Vec3::new(0.75, 0.2, 0.0);
    spawn(
        &mut app,
        Joint::fixed(a, b).with_local_anchors(at, Vec3::ZERO),
    );
    step(&mut app, 240);
    let (p, q) = relative(&app);
    assert!(p.distance(p0) < 2e-3, "offset moved {} m", p.distance(p0));
    assert!(
        q.angle_between(q0) < 5e-3,
        "turned {} rad",
        q.angle_between(q0)
    );
}

#[test]
fn a_joint_reports_its_load_and_breaks_at_its_break_force() {
    // A 2 kg ball hanging on a ball joint carries m·g; a downward pull growing 10 N/s
    // breaks the joint when the total passes 50 N.
    let mut app = app();
    let pivot = Vec3::new(0.0, 5.0, 0.0);
    let m = 2.0;
    let ball = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::sphere(0.1),
            Mass(m),
            Transform::from_translation(pivot - Vec3::Y),
        ),
    );
    let joint = spawn(
        &mut app,
        Joint::spherical(None, ball)
            .with_local_anchors(pivot, Vec3::Y)
            .with_break_force(50.0),
    );
    step(&mut app, 60);
    assert_near(forces(&app, joint).force.y, m * G, 0.01 * m * G, "load, N");
    let mut broke_at = None;
    for k in 1..600 {
        let pull = 10.0 * k as f32 * H;
        app.world_mut()
            .entity_mut(ball)
            .insert(ExternalForce::new(Vec3::NEG_Y * pull));
        step(&mut app, 1);
        if app.world().get::<Joint>(joint).is_none() {
            broke_at = Some(m * G + pull);
            break;
        }
    }
    let total = broke_at.expect("the joint never broke");
    assert_near(total, 50.0, 0.05 * 50.0, "load at the break, N");
    // Free now: it falls.
    let y = pos(&app, ball).y;
    step(&mut app, 30);
    assert!(pos(&app, ball).y < y - 0.5, "the ball fell after the break");
}

#[test]
fn a_ball_joints_cone_and_twist_limits_hold() {
    // A 1 kg, 1 m bar hanging from a ball joint at its top, its cone 0.3 rad about the
    // vertical: a sideways pull of 2·m·g at its centre would lean it to atan 2 = 63°
    // free; a 5 N·m twist about the vertical would spin it, and its twist limits ±0.5 rad
    // hold it.
    let mut app = app();
    let (m, l) = (1.0, 1.0);
    let pivot = Vec3::new(0.0, 4.0, 0.0);
    let bar = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::cuboid(0.05, l / 2.0, 0.05),
            Mass(m),
            Transform::from_translation(pivot - Vec3::Y * l / 2.0),
        ),
    );
    spawn(
        &mut app,
        Joint::spherical(None, bar)
            .with_local_anchors(pivot, Vec3::Y * l / 2.0)
            .with_cone_limit(Vec3::NEG_Y, 0.3)
            .with_twist_limits(-0.5, 0.5),
    );
    app.world_mut().entity_mut(bar).insert(ExternalForce {
        force: Vec3::X * 2.0 * m * G,
        torque: Vec3::Y * 5.0,
    });
    let (mut lean, mut twist) = (0.0f32, 0.0f32);
    for _ in 0..180 {
        step(&mut app, 1);
        let q = rot(&app, bar);
        lean = lean.max((q * Vec3::NEG_Y).angle_between(Vec3::NEG_Y));
        // The twist: q = swing · twist, the twist about the bar's axis at rest (y).
        let along = q.y;
        twist = twist.max((2.0 * along.atan2(q.w)).abs());
    }
    assert!(lean > 0.25, "it leaned against the cone: {lean}");
    assert!(
        lean < 0.3 + 0.01,
        "it leaned {lean} rad past the 0.3 rad cone"
    );
    assert!(twist > 0.4, "it twisted against the limit: {twist}");
    assert!(
        twist < 0.5 + 0.01,
        "it twisted {twist} rad past the 0.5 rad limit"
    );
}

#[test]
fn a_hinge_motor_spins_up_at_its_torque_and_holds_its_speed() {
    // A 2 kg disc (cylinder r 0.5 m, I = m·r²/2 = 0.25 kg·m² about its axis) on a hinge
    // to the world, no gravity; motor 3 rad/s with at most 0.5 N·m: it spins up at
    // τ/I = 2 rad/s² for 1.5 s, then holds 3 rad/s.
    let mut app = app_without_gravity();
    let wheel = spawn(
        &mut app,
        (
            RigidBody::Dynamic,
            Collider::cylinder(0.5, 0.05),
            Mass(2.0),
            Transform::default(),
        ),
    );
    spawn(
        &mut app,
        Joint::revolute(None, wheel, Vec3::Y).with_motor(3.0, 0.5),
    );
    step(&mut app, 30);
    assert_near(
        vel(&app, wheel).angular.y,
        1.0,
        0.01,
        "spin after 0.5 s, rad/s",
    );
    step(&mut app, 90);
    assert_near(
        vel(&app, wheel).angular.y,
        3.0,
        1e-3,
        "spin after 2 s, rad/s",
    );
    let w = vel(&app, wheel).angular;
    assert!(
        w.x.abs() < 1e-4 && w.z.abs() < 1e-4,
        "off the hinge axis: {w}"
    );
}

#[test]
fn a_spring_joint_has_its_stiffness_and_frequency() {
    // A 1 kg ball on a 2 Hz spring of rest length 1 m below a world anchor. Undamped and
    // let go at the rest length, it bobs with the spring's period, 0.5 s; damped
    // (ζ = 0.7) it settles g/ω² = 6.2 cm below the rest length (k = m·ω²). (The soft
    // step integrates the spring implicitly, which damps it: undamped, its first swing
    // fell 14 % short of 2·g/ω².)
    let omega = std::f32::consts::TAU * 2.0;
    let anchor = Vec3::new(0.0, 5.0, 0.0);
    let setup = |zeta: f32| {
        let mut app = app();
        let ball = spawn(
            &mut app,
            (
                RigidBody::Dynamic,
                Collider::sphere(0.1),
                Mass(1.0),
                Transform::from_translation(anchor - Vec3::Y),
            ),
        );
        spawn(
            &mut app,
            Joint::spring(None, ball, 1.0, 2.0, zeta).with_local_anchors(anchor, Vec3::ZERO),
        );
        (app, ball)
    };
    let (mut app, ball) = setup(0.0);
    let mut lows = Vec::new();
    let (mut before, mut last) = (pos(&app, ball).y, pos(&app, ball).y);
    for k in 1..=150 {
        step(&mut app, 1);
        let y = pos(&app, ball).y;
        if k > 1 && last < before && last <= y {
            // A lowest point at step k − 1, refined by the parabola through three steps.
            let (a, b, c) = (before, last, y);
            let shift = 0.5 * (a - c) / (a - 2.0 * b + c);
            lows.push((k as f32 - 1.0 + shift) * H);
        }
        (before, last) = (last, y);
    }
    assert!(lows.len() >= 4, "{lows:?}");
    let period = (lows[lows.len() - 1] - lows[0]) / (lows.len() - 1) as f32;
    assert_near(period, 0.5, 0.01 * 0.5, "period, s");

    let (mut app, ball) = setup(0.7);
    step(&mut app, 300);
    let sag = anchor.y - 1.0 - pos(&app, ball).y;
    assert_near(
        sag,
        G / (omega * omega),
        0.01 * G / (omega * omega),
        "static stretch, m",
    );
}
