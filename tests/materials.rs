//! Mass properties and material combine rules: a density sets the mass of a body without
//! `Mass`, an `AngularInertia` replaces the shape's, and each combine rule gives the
//! friction a sliding box feels (its stopping distance v²/2μg) and the bounce of a ball.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn density_sets_the_mass_and_angular_inertia_replaces_the_shapes() {
    let mut app = app_without_gravity();
    let h = Vec3::new(0.5, 0.25, 0.1);
    let density = 500.0;
    let b = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(h.x, h.y, h.z),
            ColliderDensity(density),
            AngularInertia(Vec3::splat(2.0)),
            Transform::default(),
            ExternalImpulse {
                impulse: Vec3::X * 10.0,
                torque_impulse: Vec3::Y * 3.0,
            },
        ))
        .id();
    step(&mut app, 1);
    let m = 8.0 * h.x * h.y * h.z * density;
    assert_near_vec(vel(&app, b).linear, Vec3::X * 10.0 / m, 1e-6, "Δv = J/(ρV)");
    // Isotropic override: ω = L/I exactly, whatever the box's own shape.
    assert_near_vec(vel(&app, b).angular, Vec3::Y * 1.5, 1e-6, "Δω = L/I");
}

#[test]
fn a_bad_density_or_inertia_is_refused_with_its_field() {
    for (density, inertia, field) in [
        (Some(0.0), None, "Collider or ColliderDensity"),
        (Some(f32::NAN), None, "Collider or ColliderDensity"),
        (None, Some(Vec3::new(1.0, -1.0, 1.0)), "AngularInertia"),
        (None, Some(Vec3::INFINITY), "AngularInertia"),
    ] {
        let mut app = app();
        let e = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y);
        let mut entity = app.world_mut().entity_mut(e);
        entity.remove::<Mass>();
        if let Some(d) = density {
            entity.insert(ColliderDensity(d));
        }
        if let Some(i) = inertia {
            entity.insert((Mass(1.0), AngularInertia(i)));
        }
        step(&mut app, 1);
        assert_eq!(
            rejected_field(&app, e),
            Some(field),
            "{density:?} {inertia:?}"
        );
    }
}

/// Stopping distance of a box sent sliding at `v0` over a floor, with friction `mu_box`
/// and `mu_floor` and the rules each asks for.
fn slide(
    mu_box: f32,
    mu_floor: f32,
    rules: (CoefficientCombine, CoefficientCombine),
    v0: f32,
) -> f32 {
    let mut app = app();
    let floor = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    app.world_mut()
        .entity_mut(floor)
        .insert((Friction(mu_floor), FrictionCombine(rules.1)));
    let b = cuboid(&mut app, Vec3::splat(0.25), 1.0, Vec3::Y * 0.25);
    step(&mut app, 10);
    app.world_mut().entity_mut(b).insert((
        Friction(mu_box),
        FrictionCombine(rules.0),
        Velocity::linear(Vec3::X * v0),
    ));
    let x0 = pos(&app, b).x;
    step(&mut app, 120);
    assert!(vel(&app, b).linear.length() < 1e-3, "stopped");
    pos(&app, b).x - x0
}

#[test]
fn each_combine_rule_gives_its_friction() {
    use CoefficientCombine::*;
    let (a, b, v0) = (0.2, 0.8, 3.0);
    for (rules, mu) in [
        ((Average, Average), 0.5),
        ((GeometricMean, GeometricMean), 0.4),
        ((Min, Min), 0.2),
        ((Multiply, Multiply), 0.16),
        ((Max, Max), 0.8),
        // Different rules: the later one in the enum wins.
        ((Average, Max), 0.8),
        ((Min, GeometricMean), 0.2),
    ] {
        let d = slide(a, b, rules, v0);
        // v0²/2μg, within one step's travel (the stop falls inside a step).
        assert_near(
            d,
            v0 * v0 / (2.0 * mu * G),
            v0 * H,
            &format!("{rules:?}: μ = {mu}"),
        );
    }
}

#[test]
fn restitution_combines_too() {
    use CoefficientCombine::*;
    for (rule, e) in [(Max, 0.9f32), (Min, 0.5), (Average, 0.7)] {
        let mut app = app();
        let floor = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        app.world_mut()
            .entity_mut(floor)
            .insert((Restitution(0.5), RestitutionCombine(rule)));
        let (r, h) = (0.25, 2.0);
        let b = ball(&mut app, r, 1.0, Vec3::Y * (r + h), Vec3::ZERO);
        // Both ask for the rule (the ball's default, Max, would win over Min).
        app.world_mut()
            .entity_mut(b)
            .insert((Restitution(0.9), RestitutionCombine(rule)));
        let (mut top, mut bounced) = (0.0f32, false);
        for _ in 0..90 {
            step(&mut app, 1);
            let vy = vel(&app, b).linear.y;
            bounced |= vy > 0.0;
            if bounced {
                top = top.max(pos(&app, b).y - r);
            }
        }
        // First apex e²·h, within the bounce test's error budget (6·g·hs/v of h).
        let v = (2.0 * G * h).sqrt();
        let tol = 6.0 * G * (H / 4.0) / v * h;
        assert_near(top, e * e * h, tol, &format!("{rule:?}: e = {e}"));
    }
}
