//! Compound bodies: colliders on child entities of a `RigidBody` are parts of it. Mass,
//! centre of mass and inertia are summed from the parts (parallel-axis theorem); the body
//! tips, turns and rests as that sum says, sleeps with its parts, and wakes when one of
//! them changes.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// An L: a post (0.2 × 1 × 0.2 m, the body's own collider) standing on the ground, and an
/// arm of length `arm` (0.2 × 0.2 cross-section, a child) sticking out sideways from its
/// top, both water-dense. The post's footprint reaches 0.1 m to +x.
fn l_shape(app: &mut App, arm: f32) -> Entity {
    ground(app, Vec3::ZERO, Quat::IDENTITY);
    let body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.1, 0.5, 0.1),
            Transform::from_xyz(0.0, 0.5, 0.0),
        ))
        .id();
    app.world_mut().spawn((
        Collider::cuboid(arm / 2.0, 0.1, 0.1),
        Transform::from_xyz(0.1 + arm / 2.0, 0.4, 0.0),
        ChildOf(body),
    ));
    body
}

/// The centre of mass's x: arm mass ∝ arm, post ∝ 1, so x = arm·(0.1 + arm/2)/(1 + arm):
/// over the footprint (≤ 0.1 m) for an arm shorter than √0.2 = 0.447 m.
#[test]
fn an_l_stands_or_tips_where_its_centre_of_mass_says() {
    for (arm, tips) in [(0.40, false), (0.50, true)] {
        let com_x = arm * (0.1 + arm / 2.0) / (1.0 + arm);
        assert_eq!(com_x > 0.1, tips, "the case is on the side it claims");
        let mut app = app();
        let body = l_shape(&mut app, arm);
        step(&mut app, 180);
        let up = rot(&app, body) * Vec3::Y;
        if tips {
            assert!(
                up.x > 0.5,
                "arm {arm} (centre of mass at x = {com_x:.3}) tips toward the arm: up {up}"
            );
        } else {
            assert!(
                tilt(&app, body) < 1e-3,
                "arm {arm} (centre of mass at x = {com_x:.3}) stands: tilt {}",
                tilt(&app, body)
            );
            assert_near_vec(
                pos(&app, body),
                Vec3::new(0.0, 0.5, 0.0),
                1e-3,
                "it stays put",
            );
        }
    }
}

/// Two 1 kg balls of radius 0.1 m at x = ±0.5 m under a body with no collider of its own:
/// mass 2 kg, centre between them, I = 2·(2/5·m·r²) about x and 2·(2/5·m·r² + m·0.5²)
/// about y and z. Impulses give Δv = J/M and Δω = I⁻¹·L. Each dumbbell is spun about one
/// principal axis, which it then keeps (about two, it would precess within the step).
#[test]
fn a_dumbbells_mass_and_inertia_are_summed_from_its_parts() {
    let own = 2.0 * 0.4 * 1.0 * 0.01;
    let across = own + 2.0 * 0.25;
    let j = Vec3::new(0.4, 0.0, 0.2);
    for (l, expected) in [
        (Vec3::X * 0.016, Vec3::X * 0.016 / own),
        (Vec3::Y * 0.508, Vec3::Y * 0.508 / across),
        (Vec3::Z * 0.254, Vec3::Z * 0.254 / across),
    ] {
        let mut app = app_without_gravity();
        let body = app
            .world_mut()
            .spawn((RigidBody::Dynamic, Transform::from_xyz(0.0, 3.0, 0.0)))
            .id();
        for x in [-0.5, 0.5] {
            app.world_mut().spawn((
                Collider::sphere(0.1),
                Mass(1.0),
                Transform::from_xyz(x, 0.0, 0.0),
                ChildOf(body),
            ));
        }
        step(&mut app, 1);
        app.world_mut().entity_mut(body).insert(ExternalImpulse {
            impulse: j,
            torque_impulse: l,
        });
        step(&mut app, 1);
        let v = vel(&app, body);
        assert_near_vec(v.linear, j / 2.0, 1e-6, "Δv = J / 2 kg");
        assert_near_vec(
            v.angular,
            expected,
            1e-5,
            &format!("Δω = I⁻¹·L for L = {l}, I = (0.008, 0.508, 0.508) kg·m²"),
        );
    }
}

/// A table: the top slab is the body's collider, four legs are children. It stands on
/// its legs (the top at 0.9 m), falls asleep with them, and holds a ball dropped on it;
/// its Transform stays where it was put and its legs' stay local.
#[test]
fn a_table_of_five_boxes_stands_sleeps_and_holds_a_ball() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let table = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Collider::cuboid(1.0, 0.05, 0.5),
                Transform::from_xyz(0.0, 0.85, 0.0),
            ))
            .id();
        let mut legs = Vec::new();
        for (x, z) in [(-0.9, -0.4), (-0.9, 0.4), (0.9, -0.4), (0.9, 0.4)] {
            let leg = (
                Collider::cuboid(0.05, 0.4, 0.05),
                Transform::from_xyz(x, -0.45, z),
                ChildOf(table),
            );
            legs.push(app.world_mut().spawn(leg).id());
        }
        step(app, 120);
        if sleeping {
            assert!(asleep(app, table), "{what}: the table sleeps");
        }
        let b = ball(app, 0.1, 1.0, Vec3::new(0.2, 2.0, 0.1), Vec3::ZERO);
        step(app, 120);
        assert_near(
            pos(app, b).y,
            1.0,
            2e-3,
            &format!("{what}: the ball rests on the top"),
        );
        assert_near_vec(
            pos(app, table),
            Vec3::new(0.0, 0.85, 0.0),
            2e-3,
            &format!("{what}: the table stands"),
        );
        assert!(tilt(app, table) < 2e-3, "{what}: level");
        let leg = app.world().get::<Transform>(legs[0]).unwrap().translation;
        assert_eq!(leg, Vec3::new(-0.9, -0.45, -0.4), "{what}: legs stay local");
    });
}

/// A slab asleep on its one leg (a child collider): removing the leg's collider wakes it,
/// and it falls the metre to the ground.
#[test]
fn a_sleeping_compound_wakes_when_a_part_leaves() {
    let mut app = app_with_sleeping();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.1, 0.5),
            Transform::from_xyz(0.0, 1.1, 0.0),
        ))
        .id();
    // One leg in the middle holds it up.
    let leg = app
        .world_mut()
        .spawn((
            Collider::cuboid(0.1, 0.5, 0.1),
            Transform::from_xyz(0.0, -0.6, 0.0),
            ChildOf(body),
        ))
        .id();
    step(&mut app, 120);
    assert!(asleep(&app, body), "asleep on its leg");
    assert_near(pos(&app, body).y, 1.1, 2e-3, "standing on its leg");
    app.world_mut().entity_mut(leg).remove::<Collider>();
    step(&mut app, 60);
    assert!(
        !asleep(&app, body) || pos(&app, body).y < 0.2,
        "woke and fell"
    );
    assert_near(pos(&app, body).y, 0.1, 2e-3, "the slab lies on the ground");
}
