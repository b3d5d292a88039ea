//! Waking, before the step, the sleepers an awake body is about to reach.
//!
//! A sleeping body stands in the fixed set as a static collider. Were it woken only when
//! the narrow phase finds an awake body touching it, the step that finds the contact
//! would solve it as a wall: the arriving body would bounce off it and the sleeper would
//! wake at rest, the impact's momentum lost. So before the gather, each awake body that
//! moves faster than the sleep thresholds is placed where the last step left it and
//! tested against the sleepers within one step's reach, with the same contact test and
//! the same speculative distance the narrow phase will use. A sleeper it reaches wakes
//! now, with every sleeper touching it (its island, as the fixed set's wake search finds
//! it), so the gather that follows takes them and the step solves them as the dynamic
//! bodies they are. Box2D wakes a sleeping island the same way when a contact with it
//! begins, before the solve.
//!
//! An edited [`Joint`] (a motor turned on, a new target, limits, anchors) wakes the
//! sleepers at its ends here too, so the edit acts in the step after it.
//!
//! What this cannot see is a body that was not in the last step (spawned this frame)
//! or that the game moved since: the narrow phase still wakes a sleeper such a body
//! touches, a step later. A scene with no sleepers skips all of it.

use bevy::prelude::*;

use super::fixed::wake_neighbours;
use crate::body::{Sleeping, Velocity};
use crate::effects::Effects;
use crate::joint::Joint;
use crate::settings::{SleepSettings, SolverSettings};
use crate::world::{ColliderEntry, PhysicsWorld, STATIC, collide};

/// Scratch kept between steps.
#[derive(Default)]
pub struct ReachScratch {
    /// Fixed entries found near one awake collider.
    near: Vec<u32>,
    /// The boxes of the sleepers reached: their islands wake.
    reached: Vec<(Vec3, Vec3)>,
    /// Per fixed entry: woken already (the island search's).
    woken: Vec<bool>,
    wake_list: Vec<Entity>,
}

/// Wakes the sleeping islands that an awake body reaches in the coming step (see the
/// module docs). Runs after the fixed set is synced and before the gather, with a command
/// flush in between.
#[allow(clippy::too_many_arguments)]
pub fn wake_reached_sleepers(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    effects: Res<Effects>,
    sleep: Res<SleepSettings>,
    settings: Res<SolverSettings>,
    velocities: Query<&Velocity, Without<Sleeping>>,
    edited: Query<&Joint, Changed<Joint>>,
    mut scratch: Local<ReachScratch>,
) {
    let world = &mut *world;
    if !effects.sleeping || !world.fixed.has_sleepers() {
        return;
    }
    world.fixed.update_search();
    let ReachScratch {
        near,
        reached,
        woken,
        wake_list,
    } = &mut *scratch;
    reached.clear();
    for joint in &edited {
        for end in [joint.body1, Some(joint.body2)].into_iter().flatten() {
            world
                .fixed
                .sleeping_bounds(end, |lo, hi| reached.push((lo, hi)));
        }
    }
    let dt = world.dt;
    let moving = if effects.collisions {
        &world.colliders[..]
    } else {
        &[]
    };
    for c in moving {
        if c.body == STATIC {
            continue;
        }
        let (b, s) = (
            &world.bodies[c.body as usize],
            &world.solver_bodies[c.body as usize],
        );
        // The velocity the coming step starts from: the game may have set it since.
        let Ok(v) = velocities.get(b.entity) else {
            continue; // Fell asleep at the end of the last step, or gone.
        };
        let (v, w) = if b.is_dynamic() {
            (v.linear, v.angular)
        } else {
            (s.v, s.w) // A kinematic body's velocity is the one the step derived.
        };
        if v.length() < sleep.linear_threshold && w.length() < sleep.angular_threshold {
            continue; // Still: the narrow phase's wake is early enough.
        }
        // Where the coming step starts it, and how far any of its points may go in it
        // (as the narrow phase's closing speed, with one step of acceleration).
        let (pos, rot) = world.collider_pose(c);
        let (lo, hi) = c.shape.aabb(Vec3::ZERO, Quat::IDENTITY);
        let radius = lo.abs().max(hi.abs()).length();
        let radius = if radius.is_finite() { radius } else { 0.0 };
        let speed = v.length() + b.forces.accel.length() * dt + w.length() * radius;
        let reach = speed * dt;
        let (lo, hi) = c.shape.aabb(pos, rot);
        near.clear();
        let pad = reach + settings.speculative_margin;
        world.fixed.touching(lo, hi, pad, |f| near.push(f));
        // The collider where the coming step starts it: copied only once a sleeper is near.
        let mut moved: Option<ColliderEntry> = None;
        for &f in near.iter() {
            let sleeper = &world.fixed.entries()[f as usize];
            let allowed = sleeper.asleep
                && !sleeper.filter.sensor
                && !c.filter.sensor
                && c.filter.allows(&sleeper.filter)
                && !world.jointed(c.owner, sleeper.owner);
            if !allowed {
                continue;
            }
            let cutoff = settings.margin_for(c.shape.pair_thickness(&sleeper.shape)) + reach;
            let moved = moved.get_or_insert_with(|| ColliderEntry {
                pos,
                rot,
                ..c.clone()
            });
            if collide(moved, 0, sleeper, 1, cutoff).is_some() {
                reached.push((sleeper.aabb_min, sleeper.aabb_max));
            }
        }
    }
    let margin = settings.speculative_margin;
    wake_neighbours(&mut commands, world, reached, (woken, wake_list), margin);
}
