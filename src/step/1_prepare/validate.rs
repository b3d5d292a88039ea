//! Checking a body's input before it enters the simulation: finite poses and velocities,
//! positive masses and sizes, planes only on static or kinematic bodies.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Shape;

/// Checks one body's input. Returns the offending field and why.
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
    if !tf.rotation.is_finite() || tf.rotation.length_squared() < 1e-12 {
        return Err(("Transform.rotation", format!("{:?}", tf.rotation)));
    }
    if !vel.linear.is_finite() {
        return Err(("Velocity.linear", format!("{}", vel.linear)));
    }
    if !vel.angular.is_finite() {
        return Err(("Velocity.angular", format!("{}", vel.angular)));
    }
    if let Some(m) = mass.filter(|m| kind == RigidBody::Dynamic && !(m.0.is_finite() && m.0 > 0.0))
    {
        return Err(("Mass", format!("{} kg: mass must be finite and > 0", m.0)));
    }
    if let Some(shape) = shape {
        shape
            .validate()
            .map_err(|r| ("Collider", format!("{r}: sizes must be finite and > 0")))?;
        if kind == RigidBody::Dynamic && matches!(shape, Shape::Plane { .. }) {
            return Err(("Collider", "a plane can only be static or kinematic".into()));
        }
    }
    Ok(())
}

pub(super) fn validate_force(force: Option<&ExternalForce>) -> Result<(), (&'static str, String)> {
    match force {
        Some(f) if !(f.force.is_finite() && f.torque.is_finite()) => Err((
            "ExternalForce",
            format!("force {} torque {}", f.force, f.torque),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Collider;

    fn check(
        tf: Transform,
        vel: Velocity,
        mass: Option<f32>,
        shape: Shape,
    ) -> Option<&'static str> {
        let mass = mass.map(Mass);
        validate(&tf, &vel, RigidBody::Dynamic, mass.as_ref(), Some(&shape))
            .err()
            .map(|e| e.0)
    }

    #[test]
    fn each_bad_field_is_named() {
        let s = Collider::sphere(1.0).shape;
        let v = Velocity::ZERO;
        assert_eq!(
            check(Transform::from_xyz(f32::NAN, 0., 0.), v, None, s),
            Some("Transform.translation")
        );
        let bad_rot = Transform {
            rotation: Quat::from_xyzw(0., f32::INFINITY, 0., 1.),
            ..default()
        };
        assert_eq!(check(bad_rot, v, None, s), Some("Transform.rotation"));
        let fast = Velocity::linear(Vec3::new(0., f32::INFINITY, 0.));
        assert_eq!(
            check(Transform::IDENTITY, fast, None, s),
            Some("Velocity.linear")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(0.0), s), Some("Mass"));
        assert_eq!(check(Transform::IDENTITY, v, Some(-2.0), s), Some("Mass"));
        assert_eq!(
            check(Transform::IDENTITY, v, Some(f32::NAN), s),
            Some("Mass")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, Collider::sphere(-1.0).shape),
            Some("Collider")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, Collider::plane().shape),
            Some("Collider")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(1.0), s), None);
    }
}
