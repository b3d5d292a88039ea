//! Stage 1b, forces: each effect that pushes bodies is its own system, run only when its
//! effect is on ([`Effects`](crate::effects::Effects)); prepare has already put each
//! body's own `ExternalForce` in.

use bevy::prelude::*;

use crate::effects::Wind;
use crate::settings::{GlobalForce, Gravity};
use crate::world::PhysicsWorld;

/// a += g · gravity scale.
pub fn apply_gravity(mut world: ResMut<PhysicsWorld>, gravity: Res<Gravity>) {
    for b in world.bodies.iter_mut().filter(|b| b.is_dynamic()) {
        b.forces.accel += gravity.0 * b.gravity_scale;
    }
}

/// a += F/m for the global push.
pub fn apply_global_force(mut world: ResMut<PhysicsWorld>, force: Res<GlobalForce>) {
    if force.0 == Vec3::ZERO {
        return;
    }
    let world = &mut *world;
    for (b, s) in world
        .bodies
        .iter_mut()
        .zip(&world.solver_bodies)
        .filter(|(b, _)| b.is_dynamic())
    {
        b.forces.accel += force.0 * s.inv_mass;
    }
}

/// The bodies' own drag coefficients.
pub fn apply_damping(mut world: ResMut<PhysicsWorld>) {
    for b in world.bodies.iter_mut() {
        b.forces.linear_damping += b.damping.x;
        b.forces.angular_damping += b.damping.y;
    }
}

/// a += k·(wind − v): adds k to the linear drag and k·wind to the constant acceleration,
/// so every integrator treats it like drag.
pub fn apply_wind(mut world: ResMut<PhysicsWorld>, wind: Res<Wind>, time: Res<Time<Fixed>>) {
    let w = wind.at(time.elapsed_secs());
    for b in world.bodies.iter_mut().filter(|b| b.is_dynamic()) {
        b.forces.linear_damping += wind.drag;
        b.forces.accel += wind.drag * w;
    }
}
