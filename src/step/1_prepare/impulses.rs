//! One-shot impulses ([`ExternalImpulse`]): applied to `Velocity` at the start of the
//! step that follows them, then zeroed. Runs after the fixed set is synced (an impulse
//! wakes a sleeper there) and before the bodies are gathered. Only entities whose
//! impulse changed are visited, so bodies without one cost nothing.

use bevy::prelude::*;

use super::{MassInput, mass_properties};
use crate::body::*;
use crate::collider::Collider;
use crate::effects::LockRotation;
use crate::limits;
use crate::world::world_inv_inertia;

/// The components an impulse needs.
type ImpulseItem<'a> = (
    Entity,
    &'a mut ExternalImpulse,
    &'a mut Velocity,
    &'a RigidBody,
    &'a Transform,
    Option<&'a Mass>,
    Option<&'a ColliderDensity>,
    Option<&'a AngularInertia>,
    Option<&'a Collider>,
    Has<LockRotation>,
);

/// Applies and clears every pending [`ExternalImpulse`] of a dynamic body.
pub fn apply_impulses(
    mut bodies: Query<ImpulseItem, (Changed<ExternalImpulse>, Without<PhysicsRejected>)>,
) {
    for (entity, mut impulse, mut vel, kind, tf, mass, density, inertia, collider, locked) in
        &mut bodies
    {
        if impulse.is_zero() {
            continue;
        }
        let j = *impulse;
        // Zeroed without counting as a change: it is ours, not the user's.
        *impulse.bypass_change_detection() = ExternalImpulse::default();
        if *kind != RigidBody::Dynamic {
            continue;
        }
        let given = MassInput {
            mass,
            density,
            inertia,
        };
        let shape = collider.map(|c| c.shape.scaled(tf.scale));
        let (m, inertia) = mass_properties(shape.as_ref(), &given);
        let dv = j.impulse / m;
        let dw = if locked {
            Vec3::ZERO
        } else {
            world_inv_inertia(tf.rotation.normalize(), inertia.recip()) * j.torque_impulse
        };
        let (v, w) = (vel.linear + dv, vel.angular + dw);
        let fine = |x: Vec3, max: f32| x.is_finite() && x.abs().max_element() <= max;
        if !(fine(v, limits::MAX_SPEED) && fine(w, limits::MAX_RATE)) {
            error!(
                "tumble: body {entity}: ExternalImpulse {:?} dropped (non-finite, or past the \
                 speed limits of ±{} m/s, ±{} rad/s)",
                j,
                limits::MAX_SPEED,
                limits::MAX_RATE
            );
            continue;
        }
        vel.linear = v;
        vel.angular = w;
    }
}
