//! One-shot impulses ([`ExternalImpulse`]): added to the solver body when prepare gathers
//! it (so a compound body's summed mass and inertia take them) and zeroed there. The fixed-set sync before it wakes a sleeper that got one, so it is gathered
//! in the same step. Only entities whose impulse changed are visited by the clear, so
//! bodies without one cost nothing.

use bevy::prelude::*;

use crate::body::*;
use crate::limits;
use crate::world::{BodyState, SolverBody};

/// Adds `j` to a gathered dynamic body: Δv = J/m, Δω = I⁻¹·L (world inverse inertia as
/// gathered). A non-finite impulse, or one that would take the body past the speed
/// limits, is logged and dropped.
pub fn apply_impulse(
    entity: Entity,
    j: &ExternalImpulse,
    state: &mut BodyState,
    body: &mut SolverBody,
) {
    let v = body.v + j.impulse * body.inv_mass;
    let w = body.w + body.inv_inertia * j.torque_impulse;
    let fine = |x: Vec3, max: f32| x.is_finite() && x.abs().max_element() <= max;
    if !(fine(v, limits::MAX_SPEED) && fine(w, limits::MAX_RATE)) {
        error!(
            "tumble: body {entity}: ExternalImpulse {:?} dropped (non-finite, or past the \
             speed limits of ±{} m/s, ±{} rad/s)",
            j,
            limits::MAX_SPEED,
            limits::MAX_RATE
        );
        return;
    }
    (body.v, body.w) = (v, w);
    (state.v0, state.w0) = (v, w);
}

/// What is left of a changed [`ExternalImpulse`] after the gather (which zeroes what it
/// applies): a sleeping body's is kept and the body woken, so the next gather applies
/// it; a static, kinematic or rejected body's is dropped. Runs after the gather.
pub fn clear_impulses(
    mut commands: Commands,
    mut impulses: Query<(Entity, &mut ExternalImpulse, Has<Sleeping>), Changed<ExternalImpulse>>,
) {
    for (entity, mut impulse, asleep) in &mut impulses {
        if impulse.is_zero() {
            continue;
        }
        if asleep {
            commands.entity(entity).remove::<Sleeping>();
        } else {
            *impulse.bypass_change_detection() = ExternalImpulse::default();
        }
    }
}
