//! Stage 4, narrow phase: a contact manifold for each candidate pair, by a dispatch table
//! over shape pairs. Contacts are computed at the start-of-step poses and kept up to a
//! speculative distance (the margin plus how far the pair can close in one step), so the
//! solver can stop bodies exactly where they meet, however fast they are.
//!
//! Warm starting: each new point looks up last step's impulses of the same pair and
//! feature id.

use bevy::prelude::*;

use crate::geometry::{collide, collide_each, has_mesh};
use crate::limits::MAX_MANIFOLDS_PER_STEP;
use crate::settings::SolverSettings;
use crate::world::{ColliderEntry, Manifold, PhysicsWorld, STATIC};

/// Computes the manifolds of all candidate pairs and warm-starts them from the cache.
pub fn collide_pairs(
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SolverSettings>,
    mut capped: Local<bool>,
) {
    let world = &mut *world;
    world.manifolds.clear();
    let dt = world.dt;
    let mut full = false;
    for &(ia, ib) in &world.pairs {
        if world.manifolds.len() == MAX_MANIFOLDS_PER_STEP {
            full = true;
            break;
        }
        let (a, b) = (&world.colliders[ia as usize], &world.colliders[ib as usize]);
        // Filtered out by layers, or two sensors, or held by a joint: not even a manifold.
        if !a.filter.allows(&b.filter) || world.jointed(a.owner, b.owner) {
            continue;
        }
        if a.filter.sensor || b.filter.sensor {
            // Only overlap counts, and nobody wakes: no margin, no contact response.
            if let Some(m) = collide(a, ia, b, ib, 0.0) {
                world.sensor_overlaps.push(m);
            }
            continue;
        }
        let (da, db) = (is_dynamic(world, a.body), is_dynamic(world, b.body));
        if !da && !db {
            // A moving kinematic body reaching a sleeper wakes it (a platform carrying a
            // crate that fell asleep on it); next step they collide.
            let sleeper = match (a.asleep, b.asleep) {
                (true, false) if moving(world, b.body) => Some((a, ia, b, ib)),
                (false, true) if moving(world, a.body) => Some((b, ib, a, ia)),
                _ => None,
            };
            if let Some((s, is, k, ik)) = sleeper {
                let reach = dt * closing_speed(world, k);
                let margin = settings.margin_for(k.shape.pair_thickness(&s.shape));
                if collide(k, ik, s, is, margin + reach).is_some() {
                    world.wake.push(s.owner);
                }
            }
            continue;
        }
        // Something awake reaches a sleeping body: it wakes next step; this step it
        // stands still like a static one.
        let wake = if a.asleep {
            Some(a.owner)
        } else if b.asleep {
            Some(b.owner)
        } else {
            None
        };
        let reach = dt * (closing_speed(world, a) + closing_speed(world, b));
        let margin = settings.margin_for(a.shape.pair_thickness(&b.shape));
        let (colliders, cache) = (&world.colliders, &world.impulse_cache);
        let manifolds = &mut world.manifolds;
        let mut found = false;
        let mut take = |mut m: Manifold| {
            found = true;
            let (fa, ra) = a.filter.combine;
            let (fb, rb) = b.filter.combine;
            m.friction = fa.pair(fb).apply(a.friction, b.friction).max(0.0);
            m.restitution = ra.pair(rb).apply(a.restitution, b.restitution);
            let key = (
                colliders[m.a as usize].entity,
                colliders[m.b as usize].entity,
                m.sub,
            );
            if let Some(cached) = cache.get(&key) {
                warm_start_from(&mut m, cached, margin);
            }
            if manifolds.len() < MAX_MANIFOLDS_PER_STEP {
                manifolds.push(m);
            }
        };
        // Convex pairs (nearly all) without the indirect call a mesh's several manifolds
        // need.
        if has_mesh(&a.shape, &b.shape) {
            collide_each(a, ia, b, ib, margin + reach, &mut take);
        } else if let Some(m) = collide(a, ia, b, ib, margin + reach) {
            take(m);
        }
        if found && let Some(e) = wake {
            world.wake.push(e);
        }
    }
    if full && !*capped {
        warn!(
            "tumble: more than {MAX_MANIFOLDS_PER_STEP} contact manifolds this step; the \
             rest wait for later steps"
        );
    }
    *capped = full;
}

/// Gives each new point last step's impulses: from the point with the same feature id,
/// or else from the nearest old point within `reach` (the same spot of a resting contact
/// can change its feature id when the reference face flips between the two boxes, and
/// losing a heavy body's warm start makes it sink and bounce).
fn warm_start_from(m: &mut Manifold, cached: &Manifold, reach: f32) {
    for p in m.points_mut() {
        let same_id = cached.points().iter().find(|c| c.id == p.id);
        let nearest = || {
            cached
                .points()
                .iter()
                .map(|c| (c, c.point.distance_squared(p.point)))
                .filter(|(_, d)| *d < reach * reach)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(c, _)| c)
        };
        if let Some(c) = same_id.or_else(nearest) {
            p.normal_impulse = c.normal_impulse;
            p.tangent_impulse = c.tangent_impulse;
        }
    }
}

/// A kinematic (or dynamic) body with any velocity.
fn moving(world: &PhysicsWorld, body: u32) -> bool {
    body != STATIC && {
        let b = &world.bodies[body as usize];
        b.v0 != Vec3::ZERO || b.w0 != Vec3::ZERO
    }
}

fn is_dynamic(world: &PhysicsWorld, body: u32) -> bool {
    body != STATIC && world.bodies[body as usize].is_dynamic()
}

/// An upper bound on how fast any point of the collider moves this step.
fn closing_speed(world: &PhysicsWorld, c: &ColliderEntry) -> f32 {
    if c.body == STATIC {
        return 0.0;
    }
    let (b, s) = (
        &world.bodies[c.body as usize],
        &world.solver_bodies[c.body as usize],
    );
    let (lo, hi) = c.shape.aabb(Vec3::ZERO, Quat::IDENTITY);
    let reach = lo.abs().max(hi.abs()).length();
    let reach = if reach.is_finite() { reach } else { 0.0 };
    b.v0.length().max(s.v.length()) + b.w0.length().max(s.w.length()) * reach
}
