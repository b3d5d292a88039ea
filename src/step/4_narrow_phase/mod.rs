//! Stage 4, narrow phase: a contact manifold for each candidate pair, by a dispatch table
//! over shape pairs. Contacts are computed at the start-of-step poses and kept up to a
//! speculative distance (the margin plus how far the pair can close in one step), so the
//! solver can stop bodies exactly where they meet, however fast they are.
//!
//! Warm starting: each new point looks up last step's impulses of the same pair and
//! feature id. A box pair that has barely moved relative to itself since its manifold
//! was found keeps that manifold, moved with the two boxes (see `reuse`).

use bevy::prelude::*;

use crate::geometry::has_mesh;
use crate::limits::MAX_MANIFOLDS_PER_STEP;
use crate::math::lanes::three_operand_copy;
use crate::settings::SolverSettings;
use crate::world::{
    ColliderEntry, Manifold, PhysicsWorld, STATIC, WarmStartCache, collide, collide_each,
};

mod reuse;
#[cfg(test)]
mod reuse_tests;

/// Candidate pairs from which the narrow phase splits them between the compute pool's
/// threads (each run of pairs into its own lists, joined in pair order: the same result
/// on any number of threads). Measured in `peers/` on the 5,050-cube pyramid at two
/// threads: the stage 9.8 ms serial, 4.8–8.0 ms split (the pool thread's half ran 1.5–2.5×
/// slower than the caller's where other work shared the cores). From 2,048 the 385-cube
/// pyramid split too (2,432 manifolds, nearly all moved from the step before, so little
/// work a pair), and its stage took 0.39-0.43 ms at two threads against 0.28-0.29 at
/// one; from 4,096, 0.28-0.29 at two (interleaved runs).
pub const PARALLEL_PAIRS_FROM: usize = 4096;

/// What the narrow phase finds for a run of pairs, in pair order.
#[derive(Default)]
struct Found {
    manifolds: Vec<Manifold>,
    sensor_overlaps: Vec<Manifold>,
    wake: Vec<Entity>,
    /// How many of `manifolds` were last step's, moved.
    reused: usize,
    /// The manifold cap was reached (the rest of the pairs wait).
    full: bool,
}

/// The narrow phase's runs but the first (which fills the world's lists), kept between
/// steps so that their buffers are.
#[derive(Default)]
pub struct RunBuffers(Vec<Found>);

impl Found {
    /// Empty, its buffers kept.
    fn clear(&mut self) {
        self.manifolds.clear();
        self.sensor_overlaps.clear();
        self.wake.clear();
        (self.reused, self.full) = (0, false);
    }
}

/// Computes the manifolds of all candidate pairs and warm-starts them from the cache.
pub fn collide_pairs(
    mut world: ResMut<PhysicsWorld>,
    settings: Res<SolverSettings>,
    mut capped: Local<bool>,
    mut speeds: Local<Vec<f32>>,
    mut runs: Local<RunBuffers>,
) {
    let world = &mut *world;
    world.manifolds.clear();
    // Each collider's closing speed, once (a collider is in several pairs).
    speeds.clear();
    speeds.extend(world.colliders.iter().map(|c| closing_speed(world, c)));
    let speeds = &*speeds;
    // The first run fills the world's own lists (as the serial loop does), the others
    // buffers kept between steps (not allocated and grown afresh every step).
    let mut own = Found {
        manifolds: std::mem::take(&mut world.manifolds),
        sensor_overlaps: std::mem::take(&mut world.sensor_overlaps),
        wake: std::mem::take(&mut world.wake),
        reused: 0,
        full: false,
    };
    let entities = world.colliders.iter().map(|c| c.entity);
    world.impulse_cache.match_pairs(&world.pairs, entities);
    let threads = bevy::tasks::ComputeTaskPool::try_get().map_or(1, |p| p.thread_num());
    let mut split = false;
    let before = (own.sensor_overlaps.len(), own.wake.len());
    if threads >= 2 && world.pairs.len() >= PARALLEL_PAIRS_FROM {
        let shared = &*world;
        let cuts = run_cuts(&world.pairs, &world.impulse_cache, threads);
        let runs = &mut runs.0;
        runs.resize_with(cuts.len(), Found::default);
        runs.iter_mut().for_each(Found::clear);
        let first = &world.pairs[..cuts.first().map_or(world.pairs.len(), |c| c.0)];
        let ends = cuts.iter().map(|c| c.0).skip(1).chain([world.pairs.len()]);
        let settings = &*settings;
        bevy::tasks::ComputeTaskPool::get().scope(|scope| {
            let own = &mut own;
            scope.spawn(async move { collide_run(shared, settings, speeds, (first, 0), 0, own) });
            for ((&(start, next), end), run) in cuts.iter().zip(ends).zip(runs.iter_mut()) {
                let pairs = (&shared.pairs[start..end], start);
                scope.spawn(async move { collide_run(shared, settings, speeds, pairs, next, run) });
            }
        });
        // Past the cap the serial loop decides which pairs wait; so does this.
        let found = own.manifolds.len() + runs.iter().map(|r| r.manifolds.len()).sum::<usize>();
        split = found <= MAX_MANIFOLDS_PER_STEP;
        if split {
            own.reused += runs.iter().map(|r| r.reused).sum::<usize>();
            for run in runs.iter_mut() {
                own.manifolds.append(&mut run.manifolds);
                own.sensor_overlaps.append(&mut run.sensor_overlaps);
                own.wake.append(&mut run.wake);
            }
        } else {
            // Back to what the world held before the runs (the joints may have woken
            // bodies this step).
            own.manifolds.clear();
            own.sensor_overlaps.truncate(before.0);
            own.wake.truncate(before.1);
            (own.reused, own.full) = (0, false);
        }
    }
    if !split {
        collide_run(world, &settings, speeds, (&world.pairs, 0), 0, &mut own);
    }
    world.reused_manifolds = own.reused;
    let full = own.full;
    world.manifolds = own.manifolds;
    world.sensor_overlaps = own.sensor_overlaps;
    world.wake = own.wake;
    if full && !*capped {
        warn!(
            "tumble: more than {MAX_MANIFOLDS_PER_STEP} contact manifolds this step; the \
             rest wait for later steps"
        );
    }
    *capped = full;
}

/// Where the runs after the first begin when `pairs` are split into `runs`: each at the
/// pair of one of last step's manifolds, evenly spaced among them, with that manifold's
/// place, where the run looks its first pair up (see `WarmStartCache::find`). A run that
/// looked first at place 0 missed, and a miss makes the whole index: at two threads the
/// ball pit made it every step, and its narrow phase took as long as on one. A cut whose
/// pair is gone is made at the even split and looked up from 0. (The runs join to the
/// same manifolds wherever they are cut.)
fn run_cuts(pairs: &[(u32, u32)], cache: &WarmStartCache, runs: usize) -> Vec<(usize, usize)> {
    let mut cuts = Vec::with_capacity(runs.saturating_sub(1));
    let mut last = 0;
    for k in 1..runs {
        let place = cache.len() * k / runs;
        let guess = (pairs.len() * k / runs).max(last + 1);
        // Outward from the even split: this step's pairs are nearly last step's.
        let found = cache.pair_at(place).and_then(|pair| {
            (0..pairs.len())
                .flat_map(|d| [guess.checked_add(d), guess.checked_sub(d)])
                .flatten()
                .find(|&p| p > last && p < pairs.len() && pairs[p] == pair)
        });
        let cut = match found {
            Some(p) => (p, place),
            None => (guess, 0),
        };
        if cut.0 >= pairs.len() {
            break;
        }
        last = cut.0;
        cuts.push(cut);
    }
    cuts
}

three_operand_copy! {
    /// The narrow phase of a run of pairs (the first at place `start` of the step's pairs),
    /// into `out`, looking the first pair up in the warm-start cache at place `next`;
    /// `speeds`: each collider's [`closing_speed`], m/s.
    fn collide_run / collide_vex => collide_any(
        world: &PhysicsWorld,
        settings: &SolverSettings,
        speeds: &[f32],
        pairs: (&[(u32, u32)], usize),
        next: usize,
        out: &mut Found,
    )
}

#[inline(always)]
fn collide_any(
    world: &PhysicsWorld,
    settings: &SolverSettings,
    speeds: &[f32],
    (pairs, start): (&[(u32, u32)], usize),
    mut next: usize,
    out: &mut Found,
) {
    let dt = world.dt;
    for (place, &(ia, ib)) in (start as u32..).zip(pairs) {
        if out.manifolds.len() == MAX_MANIFOLDS_PER_STEP {
            out.full = true;
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
                out.sensor_overlaps.push(m);
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
                let reach = dt * speeds[ik as usize];
                let margin = settings.margin_for(k.shape.pair_thickness(&s.shape));
                if collide(k, ik, s, is, margin + reach).is_some() {
                    out.wake.push(s.owner);
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
        let reach = dt * (speeds[ia as usize] + speeds[ib as usize]);
        let margin = settings.margin_for(a.shape.pair_thickness(&b.shape));
        let cutoff = margin + reach;
        let (colliders, cache) = (&world.colliders, &world.impulse_cache);
        let key = |m: &Manifold| {
            let entity = |i: u32| colliders[i as usize].entity;
            (entity(m.a), entity(m.b), m.sub)
        };
        let manifolds = &mut out.manifolds;
        let before = manifolds.len();
        // Whether the pair has a manifold (a cell: `take` sets it, and so does reuse).
        let found = std::cell::Cell::new(false);
        // The pair's material.
        let combine = |m: &mut Manifold| {
            let (fa, ra) = a.filter.combine;
            let (fb, rb) = b.filter.combine;
            m.friction = fa.pair(fb).apply(a.friction, b.friction).max(0.0);
            m.restitution = ra.pair(rb).apply(a.restitution, b.restitution);
        };
        // `warm`: last step's manifold of the pair, whose impulses this one starts from.
        let take = |mut m: Manifold, warm: Option<&Manifold>, manifolds: &mut Vec<_>| {
            found.set(true);
            combine(&mut m);
            if let Some(cached) = warm {
                warm_start_from(&mut m, cached, margin);
            }
            if manifolds.len() < MAX_MANIFOLDS_PER_STEP {
                manifolds.push(m);
            }
        };
        // Convex pairs (nearly all) without the indirect call a mesh's several manifolds
        // need; box pairs that barely moved keep last step's manifold, moved (its
        // impulses with it).
        if has_mesh(&a.shape, &b.shape) {
            collide_each(a, ia, b, ib, cutoff, &mut |m| {
                let warm = cache.find_at(&key(&m), place, &mut next);
                take(m, warm, manifolds);
            });
        } else if reuse::reusable(a, b) {
            let cached = cache.find_at(&(a.entity, b.entity, 0), place, &mut next);
            // (The loop's first check leaves room for one more manifold.)
            let limits = (margin, cutoff);
            let moved =
                cached.is_some_and(|c| reuse::reuse_onto(manifolds, c, (a, ia), (b, ib), limits));
            if moved {
                out.reused += 1;
                found.set(true);
                combine(manifolds.last_mut().expect("just pushed"));
            } else if let Some(mut m) = collide(a, ia, b, ib, cutoff) {
                reuse::anchor(&mut m, a, b, cutoff);
                take(m, cached, manifolds);
            }
        } else if let Some(m) = collide(a, ia, b, ib, cutoff) {
            let warm = cache.find_at(&key(&m), place, &mut next);
            take(m, warm, manifolds);
        }
        for m in &mut manifolds[before..] {
            m.pair = place;
        }
        if found.get()
            && let Some(e) = wake
        {
            out.wake.push(e);
        }
    }
}

/// Gives each new point last step's impulses: from the point with the same feature id,
/// or else from the nearest old point within `reach` (the same spot of a resting contact
/// can change its feature id when the reference face flips between the two boxes, and
/// losing a heavy body's warm start makes it sink and bounce).
fn warm_start_from(m: &mut Manifold, cached: &Manifold, reach: f32) {
    m.previous_load = cached.previous_load;
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
            p.twist_impulse = c.twist_impulse;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneDesc;

    /// The parallel narrow phase joins its runs in pair order: any split of the pairs
    /// into runs must find what one run does, in the same order.
    #[test]
    fn runs_of_pairs_join_to_the_whole() {
        let scene = SceneDesc::load("assets/scenes/9_rain.scene.ron").unwrap();
        let (mut app, _) = scene.headless_app();
        for _ in 0..90 {
            app.update();
        }
        // Hand this step's manifolds to the warm-start cache, as the next step's
        // prepare would, so the runs below warm-start from them.
        let mut world = app.world_mut().resource_mut::<PhysicsWorld>();
        let mut last = world.manifolds.clone();
        let world = &mut *world;
        world.impulse_cache.take_over(&mut last);
        // The pairs are the step's own: the lookups take the repeated pairs' path.
        let entities = world.colliders.iter().map(|c| c.entity);
        world.impulse_cache.match_pairs(&world.pairs, entities);
        assert!(world.impulse_cache.repeats());
        let world = app.world().resource::<PhysicsWorld>();
        let settings = app.world().resource::<SolverSettings>();
        assert!(world.pairs.len() > 500, "{} pairs", world.pairs.len());
        let speeds: Vec<f32> = world
            .colliders
            .iter()
            .map(|c| closing_speed(world, c))
            .collect();
        let mut whole = Found::default();
        collide_run(world, settings, &speeds, (&world.pairs, 0), 0, &mut whole);
        assert!(whole.manifolds.len() > 100);
        let warm = whole.manifolds.iter().flat_map(|m| m.points());
        assert!(
            warm.filter(|p| p.normal_impulse > 0.0).count() > 100,
            "the runs start from last step's impulses"
        );
        for runs in [2, 3, 7] {
            let mut joined = Found::default();
            let size = world.pairs.len().div_ceil(runs);
            for (k, pairs) in world.pairs.chunks(size).enumerate() {
                let mut run = Found::default();
                collide_run(world, settings, &speeds, (pairs, k * size), 0, &mut run);
                joined.manifolds.extend(run.manifolds);
                joined.wake.extend(run.wake);
            }
            assert_eq!(joined.manifolds.len(), whole.manifolds.len());
            for (x, y) in joined.manifolds.iter().zip(&whole.manifolds) {
                assert!((x.a, x.b, x.len, x.normal) == (y.a, y.b, y.len, y.normal));
                for (p, q) in x.points().iter().zip(y.points()) {
                    assert!(
                        (p.point, p.separation, p.normal_impulse)
                            == (q.point, q.separation, q.normal_impulse)
                    );
                }
            }
            assert_eq!(joined.wake, whole.wake);
        }
    }

    /// Regression: the runs after the first looked their first pair up at place 0 of
    /// last step's manifolds, missed, and the miss made the whole pair index (a hash map
    /// of every manifold) every step: 190 of the ball pit's 211 steps at two threads,
    /// against 16 at one. Pairs that are last step's, in last step's order (every third
    /// without a manifold), looked up run by run: cut where `run_cuts` cuts and from its
    /// places, they make no index at any run count; cut evenly and from place 0, they do.
    #[test]
    fn runs_cut_at_last_steps_pairs_make_no_index() {
        let pairs: Vec<(u32, u32)> = (0..3000).map(|i| (i / 7, 500 + i)).collect();
        let touching = |k: usize| !k.is_multiple_of(3);
        let entity = |i: u32| Entity::from_raw_u32(i).unwrap();
        let key = |m: &Manifold| (entity(m.a), entity(m.b), m.sub);
        let mut last: Vec<Manifold> = (pairs.iter().enumerate())
            .filter(|&(k, _)| touching(k))
            .map(|(_, &(a, b))| Manifold { a, b, ..default() })
            .collect();
        let mut cache = WarmStartCache::default();
        cache.index(&last, key);
        cache.take_over(&mut last);
        // Looks each touching pair of `run` up from place `next`; whether all were found.
        let look_up = |cache: &WarmStartCache, run: std::ops::Range<usize>, mut next| {
            run.filter(|&k| touching(k)).all(|k| {
                let (a, b) = pairs[k];
                cache.find(&(entity(a), entity(b), 0), &mut next).is_some()
            })
        };
        assert!(look_up(&cache, 0..pairs.len(), 0));
        assert!(!cache.has_index(), "one run finds every pair in order");
        for runs in [2, 3, 7] {
            let cuts = run_cuts(&pairs, &cache, runs);
            assert_eq!(cuts.len(), runs - 1);
            for &(p, place) in &cuts {
                assert_eq!(cache.pair_at(place), Some(pairs[p]), "cut at a kept pair");
            }
            let starts = [(0, 0)].into_iter().chain(cuts.iter().copied());
            let ends = cuts.iter().map(|c| c.0).chain([pairs.len()]);
            for ((start, next), end) in starts.zip(ends) {
                assert!(look_up(&cache, start..end, next));
            }
            assert!(
                !cache.has_index(),
                "{runs} runs cut at kept pairs made the index"
            );
            // An even cut instead, every run looking up from place 0: runs miss, so the
            // index is made.
            let even = pairs.len().div_ceil(runs);
            for start in (0..pairs.len()).step_by(even) {
                assert!(look_up(&cache, start..(start + even).min(pairs.len()), 0));
            }
            assert!(cache.has_index(), "{runs} even runs from place 0 miss");
            cache.forget_index();
        }
    }
}
