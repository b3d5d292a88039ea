//! Stage 7, sleep: bodies that have been still for a while fall asleep together with
//! everything they touch (an island), and sleeping bodies that were touched wake up.
//! A sleeping body moves to the fixed set (see prepare): it costs a wake check, nothing more.

use bevy::prelude::*;

use crate::body::{RigidBody, SleepTimer, Sleeping, Velocity};
use crate::settings::{GlobalForce, SleepSettings};
use crate::world::{PhysicsWorld, STATIC};

/// Advances sleep timers, puts still islands to sleep and wakes touched sleepers.
pub fn update_sleep(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SleepSettings>,
    global: Res<GlobalForce>,
    mut bodies: Query<(&mut SleepTimer, &mut Velocity)>,
    mut scratch: Local<(Vec<u32>, Vec<f32>)>,
) {
    let world = &mut *world;
    for &e in &world.wake {
        commands.entity(e).remove::<Sleeping>();
    }

    let n = world.bodies.len();
    for (b, s) in world.bodies.iter_mut().zip(&world.solver_bodies) {
        let still =
            s.v.length() < settings.linear_threshold && s.w.length() < settings.angular_threshold;
        b.sleep_time = if still { b.sleep_time + world.dt } else { 0.0 };
    }
    // Islands: bodies joined by contacts (static colliders don't join islands).
    // Union-find parents and each island's least still time, kept between steps.
    let (parent, least) = &mut *scratch;
    parent.clear();
    parent.extend(0..n as u32);
    for m in &world.manifolds {
        let (a, b) = (
            world.colliders[m.a as usize].body,
            world.colliders[m.b as usize].body,
        );
        if a != STATIC && b != STATIC {
            let (ra, rb) = (find(parent, a), find(parent, b));
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
    // An island sleeps when its least-still body has been still long enough; a woken
    // sleeper in the island keeps it awake.
    least.clear();
    least.resize(n, f32::INFINITY);
    for i in 0..n {
        let root = find(parent, i as u32) as usize;
        least[root] = least[root].min(world.bodies[i].sleep_time);
    }
    for i in 0..n {
        let body = &world.bodies[i];
        let root = find(parent, i as u32) as usize;
        let Ok((mut timer, mut vel)) = bodies.get_mut(body.entity) else {
            continue;
        };
        timer.0 = body.sleep_time;
        let pushed = global.0 != Vec3::ZERO;
        if body.kind == RigidBody::Dynamic && !pushed && least[root] >= settings.time_to_sleep {
            *vel = Velocity::ZERO;
            commands.entity(body.entity).insert(Sleeping);
        }
    }
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        parent[i as usize] = parent[parent[i as usize] as usize];
        i = parent[i as usize];
    }
    i
}
