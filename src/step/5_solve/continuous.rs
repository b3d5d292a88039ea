//! Continuous collision against the fixed set, after the solve.
//!
//! Contacts are found once per step, at the start poses, as far ahead as each pair could
//! close at its speeds of that moment. A body that an impact speeds up *during* the step
//! (a 1 kg box hit by a 1000 kg one at 50 m/s) can then cross a wall it had no contact
//! with, and next step it starts deep inside it while the heavy body keeps pushing.
//! Box2D v3 answers this with a time-of-impact sweep of fast bodies against static
//! shapes after the solve; so do we, for the bodies the solver moved away from their
//! free path by more than the speculative margin covers: the body's pose is moved back
//! along its path, by bisection, to where it is no deeper into any fixed collider than it
//! started (plus [`CONTINUOUS_SLOP`] of the margin), and its velocity into that collider
//! is removed. A body that a heavier one touches is swept too, when it moved more than
//! the slop: a light box already flying at a wall, its contact with the wall found,
//! and a 1000 times heavier box behind it, is driven through that contact — Gauss–Seidel
//! passes, each of which hands the light box the heavy one's speed again, converge in
//! about M/m of them — and it kept to its free path while doing so (at 16 substeps it
//! ended 0.22 m inside the wall; swept past the margin only, it still crept 12–14 mm a
//! step). Everything else (bodies that kept to their free path and have no heavier
//! neighbour, sleepers, static scenes) costs one subtraction per contact body, and one
//! pass over the manifolds marks the pushed bodies.

use bevy::prelude::*;

use crate::settings::{CONTINUOUS_SLOP, SLOP_OF_THICKNESS, SolverSettings};
use crate::world::collide;
use crate::world::{ColliderEntry, PhysicsWorld, STATIC};

/// Bisection steps on the path: the pose is found to 1/2^10 of the step's motion.
const BISECTIONS: u32 = 10;

/// Moves bodies that an impact drove into the fixed set back to where they met it.
pub fn sweep_against_fixed(
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SolverSettings>,
    mut found: Local<Vec<u32>>,
    mut pushed: Local<Vec<bool>>,
) {
    let world = &mut *world;
    // Only a contact can move a body off its free path.
    if world.manifolds.is_empty() {
        return;
    }
    let dt = world.dt;
    mark_pushed(world, &mut pushed);
    for ci in 0..world.colliders.len() {
        let c = &world.colliders[ci];
        let fixed_or_asleep = c.body == STATIC || c.asleep;
        if fixed_or_asleep || c.filter.sensor || !world.bodies[c.body as usize].is_dynamic() {
            continue;
        }
        let i = c.body as usize;
        let (b, s) = (&world.bodies[i], &world.solver_bodies[i]);
        // The body's own margin (smaller for bodies under 4 cm) sets both the trigger
        // and the tolerance, which for small bodies is a tenth of the thinnest side.
        let thickness = c.shape.thickness();
        let margin = settings.margin_for(thickness);
        let slop = (CONTINUOUS_SLOP * margin).min(SLOP_OF_THICKNESS * thickness);
        let off_path = (s.dp - b.v0 * dt).length() > margin;
        if !b.in_contact || !(off_path || pushed[i] && s.dp.length() > slop) {
            continue;
        }
        let (dp, dq) = (s.dp, s.dq);
        let c = c.clone();
        let at = |t: f32| {
            let rot = (Quat::IDENTITY.slerp(dq, t) * b.q0).normalize();
            ColliderEntry {
                pos: b.x0 + dp * t + rot * c.offset,
                rot: if c.local_rot == Quat::IDENTITY {
                    rot
                } else {
                    (rot * c.local_rot).normalize()
                },
                ..c.clone()
            }
        };
        let (lo0, hi0) = c.shape.aabb(c.pos, c.rot);
        let end = at(1.0);
        let (lo1, hi1) = c.shape.aabb(end.pos, end.rot);
        found.clear();
        world
            .fixed
            .overlapping(lo0.min(lo1), hi0.max(hi1), 0.0, |k| found.push(k));
        let mut hit: Option<(f32, Vec3)> = None;
        for &k in found.iter() {
            let f = &world.fixed.entries()[k as usize];
            if !c.filter.allows(&f.filter) || c.filter.sensor || f.filter.sensor {
                continue;
            }
            let depth = |t: f32| depth_into(&at(t), f);
            let limit = depth(0.0).0.max(0.0) + slop;
            let (d1, n) = depth(1.0);
            if d1 <= limit {
                continue;
            }
            // depth(0) ≤ limit < depth(1): bisect for the last pose within the limit.
            let (mut lo, mut hi) = (0.0f32, 1.0f32);
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                if depth(mid).0 <= limit {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            if hit.is_none_or(|(t, _)| lo < t) {
                hit = Some((lo, n));
            }
        }
        let Some((t, n)) = hit else { continue };
        let s = &mut world.solver_bodies[i];
        s.dp = dp * t;
        s.dq = Quat::IDENTITY.slerp(dq, t).normalize();
        // `n` points from the body into the fixed collider: stop moving into it.
        s.v -= s.v.dot(n).max(0.0) * n;
    }
}

/// Marks, per body, whether a heavier dynamic body has a manifold with it.
fn mark_pushed(world: &PhysicsWorld, pushed: &mut Vec<bool>) {
    pushed.clear();
    pushed.resize(world.bodies.len(), false);
    let inv_mass = |c: u32| {
        let body = world.colliders[c as usize].body;
        let dynamic = body != STATIC && world.bodies[body as usize].is_dynamic();
        dynamic.then(|| (body, world.solver_bodies[body as usize].inv_mass))
    };
    for m in &world.manifolds {
        if let (Some((a, ima)), Some((b, imb))) = (inv_mass(m.a), inv_mass(m.b)) {
            if ima > imb {
                pushed[a as usize] = true;
            } else if imb > ima {
                pushed[b as usize] = true;
            }
        }
    }
}

/// How deep `a` is into `b` (the largest overlap of any contact point, ≤ 0 when apart)
/// and the contact normal from `a` to `b`.
fn depth_into(a: &ColliderEntry, b: &ColliderEntry) -> (f32, Vec3) {
    match collide(a, 0, b, 1, 0.0) {
        Some(m) => {
            let deepest = m
                .points()
                .iter()
                .map(|p| -p.separation)
                .fold(f32::MIN, f32::max);
            (deepest, m.normal)
        }
        None => (f32::MIN, Vec3::ZERO),
    }
}
