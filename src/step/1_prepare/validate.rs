//! Checking a body's input before it enters the simulation: finite poses and velocities,
//! positive masses and sizes, planes only on static or kinematic bodies.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Shape;
use crate::effects::GravityScale;
use crate::limits;

/// What a dynamic or kinematic body brings to be checked each step.
pub(super) struct BodyChecks<'a> {
    pub tf: &'a Transform,
    pub vel: &'a Velocity,
    pub kind: RigidBody,
    pub mass: Option<&'a Mass>,
    pub shape: Option<&'a Shape>,
    pub force: Option<&'a ExternalForce>,
    pub center_of_mass: Option<&'a CenterOfMass>,
    pub friction: Option<&'a Friction>,
    pub restitution: Option<&'a Restitution>,
    /// Linear and angular damping, 1/s.
    pub damping: Vec2,
    pub gravity_scale: Option<&'a GravityScale>,
}

/// Checks a body's whole input: [`validate`], then its force, centre of mass and
/// scalars. Returns the first offending field and why.
///
/// Every awake body passes through here every step, so the rules are first applied as
/// one test that builds no message ([`plainly_valid`]); only a body it doubts goes
/// through the detailed checks, which name the field (and have the last word).
#[inline]
pub(super) fn check_body(b: &BodyChecks) -> Result<(), (&'static str, String)> {
    if plainly_valid(b) {
        debug_assert!(
            detailed(b).is_ok(),
            "the quick test passed a body the rules refuse"
        );
        return Ok(());
    }
    detailed(b)
}

#[cold]
#[inline(never)]
fn detailed(b: &BodyChecks) -> Result<(), (&'static str, String)> {
    validate(b.tf, b.vel, b.kind, b.mass, b.shape)
        .and_then(|()| validate_force(b.force))
        .and_then(|()| validate_center_of_mass(b.center_of_mass))
        .and_then(|()| validate_scalars(b.friction, b.restitution, b.damping, b.gravity_scale))
}

/// The rules of [`detailed`] as plain comparisons: true only if it would pass (it may
/// doubt a body the detailed checks then accept, never the other way round; tests hold
/// every refused field to that through the detailed path).
#[inline(always)]
fn plainly_valid(b: &BodyChecks) -> bool {
    use limits::{MAX_COEFFICIENT, MAX_FORCE, MAX_MASS, MAX_RATE, MAX_SIZE, MAX_SPEED};
    // `x <= max` is false for NaN, so each bound also rules NaN out.
    let within = |v: Vec3, max: f32| v.abs().cmple(Vec3::splat(max)).all();
    let len2 = b.tf.rotation.length_squared();
    let dynamic = b.kind == RigidBody::Dynamic;
    let size = |x: f32| x > 0.0 && x <= MAX_SIZE;
    let shape = match b.shape {
        None => true,
        Some(Shape::Sphere { radius }) => size(*radius),
        Some(Shape::Cuboid { half_extents: h }) => size(h.x) & size(h.y) & size(h.z),
        // Rarer shapes: the shape's own check, and what only a static body may be.
        Some(s) => {
            s.validate().is_ok()
                && !(dynamic
                    && matches!(
                        s,
                        Shape::Plane { .. } | Shape::TriMesh(_) | Shape::HeightField(_)
                    ))
        }
    };
    let mass = match b.mass {
        Some(m) if dynamic => m.0 > 0.0 && m.0 <= MAX_MASS,
        _ => true,
    };
    let in_range = |x: f32, lo: f32, hi: f32| x >= lo && x <= hi;
    let coefficients = b
        .friction
        .is_none_or(|f| in_range(f.0, 0.0, MAX_COEFFICIENT))
        & b.restitution.is_none_or(|r| in_range(r.0, 0.0, 1.0))
        & b.gravity_scale
            .is_none_or(|g| in_range(g.0, -MAX_COEFFICIENT, MAX_COEFFICIENT))
        & in_range(b.damping.x, 0.0, MAX_RATE)
        & in_range(b.damping.y, 0.0, MAX_RATE);
    let force = b
        .force
        .is_none_or(|f| within(f.force, MAX_FORCE) & within(f.torque, MAX_FORCE));
    let com = b.center_of_mass.is_none_or(|c| within(c.0, MAX_SIZE));
    within(b.tf.translation, f32::MAX)
        & b.tf.rotation.is_finite()
        & (1e-12..=f32::MAX).contains(&len2)
        & within(b.vel.linear, MAX_SPEED)
        & within(b.vel.angular, MAX_RATE)
        & mass
        & coefficients
        & force
        & com
        & shape
}

/// Checks one body's input. Returns the offending field and why.
#[inline]
pub fn validate(
    tf: &Transform,
    vel: &Velocity,
    kind: RigidBody,
    mass: Option<&Mass>,
    shape: Option<&Shape>,
) -> Result<(), (&'static str, String)> {
    if !tf.translation.is_finite() {
        return Err(("Transform.translation", format!("{}", tf.translation)));
    }
    // Normalisable: finite components whose squared length neither overflows nor
    // vanishes (a (1e30, 0, 0, 1) quaternion overflows to a length of ∞ and would
    // normalise to zero).
    let len2 = tf.rotation.length_squared();
    if !tf.rotation.is_finite() || !len2.is_finite() || len2 < 1e-12 {
        return Err(("Transform.rotation", format!("{:?}", tf.rotation)));
    }
    if !vel.linear.is_finite() {
        return Err(("Velocity.linear", format!("{}", vel.linear)));
    }
    if !vel.angular.is_finite() {
        return Err(("Velocity.angular", format!("{}", vel.angular)));
    }
    if !vel.linear.is_finite() || vel.linear.abs().max_element() > limits::MAX_SPEED {
        return Err((
            "Velocity.linear",
            format!("{}: beyond ±{}", vel.linear, limits::MAX_SPEED),
        ));
    }
    if vel.angular.abs().max_element() > limits::MAX_RATE {
        return Err((
            "Velocity.angular",
            format!("{}: beyond ±{}", vel.angular, limits::MAX_RATE),
        ));
    }
    if let Some(m) = mass.filter(|_| kind == RigidBody::Dynamic) {
        limits::positive("Mass", m.0, limits::MAX_MASS).map_err(|e| (e.field, e.reason))?;
    }
    if let Some(shape) = shape {
        shape
            .validate()
            .map_err(|r| ("Collider", format!("{r}: sizes must be finite and > 0")))?;
        if kind == RigidBody::Dynamic && matches!(shape, Shape::Plane { .. }) {
            return Err(("Collider", "a plane can only be static or kinematic".into()));
        }
        if kind == RigidBody::Dynamic && matches!(shape, Shape::TriMesh(_) | Shape::HeightField(_))
        {
            let why = "a triangle mesh or heightfield has no inside to weigh: it can only be \
                       static or kinematic (use a convex hull for a moving body)";
            return Err(("Collider", why.into()));
        }
    }
    Ok(())
}

#[inline]
pub(super) fn validate_force(force: Option<&ExternalForce>) -> Result<(), (&'static str, String)> {
    let Some(f) = force else { return Ok(()) };
    let max = limits::MAX_FORCE;
    let ok = |v: Vec3| v.is_finite() && v.abs().max_element() <= max;
    if ok(f.force) && ok(f.torque) {
        Ok(())
    } else {
        Err((
            "ExternalForce",
            format!(
                "force {} torque {}: must be finite and within ±{max}",
                f.force, f.torque
            ),
        ))
    }
}

/// A body's material and per-body scalars: friction and gravity scale finite, restitution
/// within 0..=1, damping finite and ≥ 0.
#[inline]
pub(super) fn validate_scalars(
    friction: Option<&Friction>,
    restitution: Option<&Restitution>,
    damping: Vec2,
    gravity_scale: Option<&GravityScale>,
) -> Result<(), (&'static str, String)> {
    use limits::{MAX_COEFFICIENT, MAX_RATE, scalar};
    let named = |e: limits::Invalid| (e.field, e.reason);
    if let Some(f) = friction {
        scalar("Friction", f.0, 0.0..=MAX_COEFFICIENT).map_err(named)?;
    }
    if let Some(r) = restitution {
        scalar("Restitution", r.0, 0.0..=1.0).map_err(named)?;
    }
    scalar("LinearDamping", damping.x, 0.0..=MAX_RATE).map_err(named)?;
    scalar("AngularDamping", damping.y, 0.0..=MAX_RATE).map_err(named)?;
    if let Some(g) = gravity_scale {
        g.check().map_err(named)?;
    }
    Ok(())
}

/// The mass properties a dynamic body ends up with: mass, inverse mass, inertia and its
/// inverse all finite and positive. A shape too small for its density to give a usable
/// mass (a 1e-12 m sphere without `Mass`) is refused here rather than handed to the
/// solver as an infinite inverse mass.
/// A [`CenterOfMass`] is finite and within [`limits::MAX_SIZE`] of the origin.
#[inline]
pub(super) fn validate_center_of_mass(
    com: Option<&CenterOfMass>,
) -> Result<(), (&'static str, String)> {
    match com {
        Some(c) if !(c.0.is_finite() && c.0.abs().max_element() <= limits::MAX_SIZE) => Err((
            "CenterOfMass",
            format!("{}: must be finite and within ±{} m", c.0, limits::MAX_SIZE),
        )),
        _ => Ok(()),
    }
}

/// A mass or principal inertia the solver can invert: finite, positive, with a finite
/// reciprocal.
#[inline(always)]
fn invertible(x: f32) -> bool {
    x.is_finite() && x > 0.0 && x.recip().is_finite()
}

/// Every dynamic body's mass properties, every step: one test, and the message only
/// for a body that fails it (out of line, as [`check_body`] does).
#[inline]
pub(super) fn validate_mass_properties(
    mass: f32,
    inertia: Vec3,
    given: (bool, bool),
) -> Result<(), (&'static str, String)> {
    if invertible(mass) & invertible(inertia.x) & invertible(inertia.y) & invertible(inertia.z) {
        return Ok(());
    }
    mass_properties_error(mass, inertia, given)
}

#[cold]
#[inline(never)]
fn mass_properties_error(
    mass: f32,
    inertia: Vec3,
    (explicit, explicit_inertia): (bool, bool),
) -> Result<(), (&'static str, String)> {
    let ok = invertible;
    let field = if explicit {
        "Mass"
    } else {
        "Collider or ColliderDensity"
    };
    if !ok(mass) {
        return Err((
            field,
            format!("mass {mass} kg from the collider's volume is unusable; give the body a Mass"),
        ));
    }
    if !(ok(inertia.x) && ok(inertia.y) && ok(inertia.z)) {
        // With a usable mass, only the shape's size (or a given inertia) can make the
        // inertia unusable.
        return Err((
            if explicit_inertia {
                "AngularInertia"
            } else {
                "Collider"
            },
            format!("inertia {inertia} kg·m² is not finite and positive (mass {mass} kg)"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Collider;
    use crate::rng::Rnd;

    /// A value that is often fine and sometimes hostile: NaN, ±∞, huge, zero, negative,
    /// just past a limit.
    fn value(rnd: &mut Rnd, fine: f32) -> f32 {
        let edge = [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            0.0,
            -fine,
            limits::MAX_SIZE * 1.01,
            limits::MAX_RATE * 1.01,
            1e-40,
        ];
        if rnd.unit() < 0.85 {
            fine * rnd.range(0.5, 1.5)
        } else {
            edge[(rnd.unit() * edge.len() as f32) as usize % edge.len()]
        }
    }

    /// The quick test is the fast path of the detailed rules, kept honest by them (the
    /// reference): on random bodies with hostile fields it answers what they answer, and
    /// so does `check_body`.
    #[test]
    fn the_quick_test_never_passes_what_the_rules_refuse() {
        let mut rnd = Rnd(0x5eed_1234_abcd_0001);
        let (mut passed, mut refused) = (0, 0);
        for _ in 0..20_000 {
            let v3 = |rnd: &mut Rnd, fine: f32| {
                Vec3::new(value(rnd, fine), value(rnd, fine), value(rnd, fine))
            };
            let tf = Transform {
                translation: v3(&mut rnd, 3.0),
                rotation: Quat::from_xyzw(
                    value(&mut rnd, 0.5),
                    value(&mut rnd, 0.5),
                    value(&mut rnd, 0.5),
                    value(&mut rnd, 0.5),
                ),
                scale: Vec3::ONE,
            };
            let vel = Velocity {
                linear: v3(&mut rnd, 2.0),
                angular: v3(&mut rnd, 2.0),
            };
            let shape = match (rnd.unit() * 4.0) as u32 {
                0 => Collider::sphere(value(&mut rnd, 0.5)).shape,
                1 => Collider::cuboid(value(&mut rnd, 0.5), 0.4, value(&mut rnd, 0.3)).shape,
                2 => Collider::capsule(value(&mut rnd, 0.5), value(&mut rnd, 0.5)).shape,
                _ => Collider::plane().shape,
            };
            let kind = [RigidBody::Dynamic, RigidBody::Kinematic][(rnd.unit() * 2.0) as usize];
            let some = |rnd: &mut Rnd| rnd.unit() < 0.5;
            let mass = some(&mut rnd).then(|| Mass(value(&mut rnd, 2.0)));
            let force = some(&mut rnd).then(|| ExternalForce {
                force: v3(&mut rnd, 10.0),
                torque: v3(&mut rnd, 1.0),
            });
            let com = some(&mut rnd).then(|| CenterOfMass(v3(&mut rnd, 0.1)));
            let friction = some(&mut rnd).then(|| Friction(value(&mut rnd, 0.5)));
            let restitution = some(&mut rnd).then(|| Restitution(value(&mut rnd, 0.5)));
            let gravity = some(&mut rnd).then(|| GravityScale(value(&mut rnd, 1.0)));
            let damping = Vec2::new(value(&mut rnd, 0.1), value(&mut rnd, 0.1));
            let b = BodyChecks {
                tf: &tf,
                vel: &vel,
                kind,
                mass: mass.as_ref(),
                shape: Some(&shape),
                force: force.as_ref(),
                center_of_mass: com.as_ref(),
                friction: friction.as_ref(),
                restitution: restitution.as_ref(),
                damping,
                gravity_scale: gravity.as_ref(),
            };
            let rules = detailed(&b).is_ok();
            // The same rules: it neither passes what they refuse nor doubts what they
            // accept (a doubt would only cost time, but there is no reason for one).
            assert_eq!(plainly_valid(&b), rules, "{:?}", detailed(&b));
            assert_eq!(check_body(&b).is_ok(), rules);
            if rules {
                passed += 1;
            } else {
                refused += 1;
            }
        }
        // Both answers were exercised.
        assert!(
            passed > 1000 && refused > 1000,
            "{passed} passed, {refused} refused"
        );
    }

    fn check(
        tf: Transform,
        vel: Velocity,
        mass: Option<f32>,
        shape: &Shape,
    ) -> Option<&'static str> {
        let mass = mass.map(Mass);
        validate(&tf, &vel, RigidBody::Dynamic, mass.as_ref(), Some(shape))
            .err()
            .map(|e| e.0)
    }

    #[test]
    fn each_bad_field_is_named() {
        let s = Collider::sphere(1.0).shape;
        let v = Velocity::ZERO;
        assert_eq!(
            check(Transform::from_xyz(f32::NAN, 0., 0.), v, None, &s),
            Some("Transform.translation")
        );
        let bad_rot = Transform {
            rotation: Quat::from_xyzw(0., f32::INFINITY, 0., 1.),
            ..default()
        };
        assert_eq!(check(bad_rot, v, None, &s), Some("Transform.rotation"));
        let fast = Velocity::linear(Vec3::new(0., f32::INFINITY, 0.));
        assert_eq!(
            check(Transform::IDENTITY, fast, None, &s),
            Some("Velocity.linear")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(0.0), &s), Some("Mass"));
        assert_eq!(check(Transform::IDENTITY, v, Some(-2.0), &s), Some("Mass"));
        assert_eq!(
            check(Transform::IDENTITY, v, Some(f32::NAN), &s),
            Some("Mass")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, &Collider::sphere(-1.0).shape),
            Some("Collider")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, &Collider::plane().shape),
            Some("Collider")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(1.0), &s), None);
    }
}
