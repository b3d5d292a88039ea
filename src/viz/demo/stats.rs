//! What the panel shows about the running scene: counts, and the total energy and momentum
//! over time for the live plot.

use std::collections::VecDeque;

use bevy::prelude::*;

use crate::PhysicsSystems;
use crate::body::{Mass, RigidBody, Sleeping, Velocity};
use crate::settings::Gravity;
use crate::world::PhysicsWorld;

pub fn plugin(app: &mut App) {
    app.init_resource::<SceneStats>()
        .init_resource::<EnergyHistory>()
        .add_systems(FixedUpdate, measure_scene.after(PhysicsSystems::Sleep));
}

/// What the panel shows of the running scene, measured after each step.
#[derive(Resource, Default, Clone, Copy, Debug)]
pub struct SceneStats {
    /// Dynamic bodies in the scene.
    pub bodies: usize,
    /// Of those, awake.
    pub awake: usize,
    /// Collider pairs that touch.
    pub touching_pairs: usize,
    /// Their contact points.
    pub contact_points: usize,
    /// Kinetic + potential energy, J.
    pub energy: f32,
    /// |Σ m·v|, kg·m/s.
    pub momentum: f32,
}

/// (simulated time, energy, momentum), the last 600 steps.
#[derive(Resource, Default)]
pub struct EnergyHistory {
    /// (s, J, kg·m/s), oldest first.
    pub samples: VecDeque<(f64, f64, f64)>,
}

fn measure_scene(
    world: Res<PhysicsWorld>,
    gravity: Res<Gravity>,
    time: Res<Time>,
    bodies: Query<(&Transform, &Velocity, &Mass, &RigidBody, Has<Sleeping>)>,
    mut stats: ResMut<SceneStats>,
    mut history: ResMut<EnergyHistory>,
) {
    let mut s = SceneStats::default();
    let mut p = Vec3::ZERO;
    for (tf, v, m, kind, asleep) in &bodies {
        if *kind != RigidBody::Dynamic {
            continue;
        }
        s.bodies += 1;
        s.awake += usize::from(!asleep);
        s.energy += 0.5 * m.0 * v.linear.length_squared() - m.0 * gravity.0.dot(tf.translation);
        p += m.0 * v.linear;
    }
    // Rotational energy of the awake bodies, from the solver's own inertia.
    s.energy += world
        .bodies
        .iter()
        .zip(&world.solver_bodies)
        .filter(|(b, _)| b.is_dynamic())
        .map(|(b, sb)| {
            let wb = (sb.dq * b.q0).inverse() * sb.w;
            0.5 * wb.dot(b.inertia * wb)
        })
        .sum::<f32>();
    s.momentum = p.length();
    let touching = world
        .manifolds
        .iter()
        .filter(|m| PhysicsWorld::is_touching(m));
    (s.touching_pairs, s.contact_points) = touching.fold((0, 0), |(n, k), m| (n + 1, k + m.len));
    *stats = s;
    history
        .samples
        .push_back((time.elapsed_secs_f64(), s.energy as f64, s.momentum as f64));
    if history.samples.len() > 600 {
        history.samples.pop_front();
    }
}
