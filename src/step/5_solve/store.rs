//! StoreImpulses: the step's results into the manifolds (for readers, and to warm-start
//! the next step) and the warm-start cache.
//!
//! A batched contact's impulses live in its batch's lanes until the passes end. Only
//! the contacts a later stage reads as constraints go back to them (the batches of the
//! contacts with fixed colliders, which the final stop reads; restitution bounces the
//! others in their lanes, see `bounce`); the rest go from the lanes straight to their
//! manifolds.
//! Before, every batch was written back to its 648-byte constraint and then read from
//! it again (100 pyramids: 1.0 and 1.1 ms a step).
//!
//! Also here: each point's share of its manifold's friction, and the running totals of
//! the step's impulses for colliders that report them.

use bevy::prelude::*;

use crate::world::{
    ContactBatches, ContactConstraint, MAX_POINTS, Manifold, NO_CONTACT, PhysicsWorld, prefetch,
};

/// How many batches ahead of the one being stored its manifolds are fetched.
const PREFETCH_AHEAD: usize = 2;

/// Stores the step's impulses: from the constraints for the scalar contacts and the
/// batched ones with fixed colliders (written back for the final stop), from their lanes
/// for the other batched ones.
pub(super) fn store_impulses(world: &mut PhysicsWorld, batches: &ContactBatches) {
    let (constraints, manifolds) = (&world.constraints, &mut world.manifolds);
    let written_back = batches.fixed_batches;
    let batched = batches.batches[..written_back]
        .iter()
        .flat_map(|b| b.contact);
    let scalar = batches.scalar.iter().copied();
    for ci in batched.chain(scalar).filter(|&c| c != NO_CONTACT) {
        store_constraint(&constraints[ci as usize], manifolds);
    }
    let (lanes, friction) = (
        &batches.batches[written_back..],
        &batches.friction[written_back..],
    );
    for (j, (b, f)) in lanes.iter().zip(friction).enumerate() {
        // A level's contacts sit all over the manifold list: fetched a batch ahead.
        if let Some(next) = lanes.get(j + PREFETCH_AHEAD) {
            let valid = next.contact.iter().filter(|&&c| c != NO_CONTACT);
            valid.for_each(|&c| prefetch(&manifolds[c as usize]));
        }
        let points = &batches.points[b.range()];
        let tangents = b.tangents();
        for (l, &ci) in b.contact.iter().enumerate() {
            if ci == NO_CONTACT {
                continue;
            }
            let m = &mut manifolds[ci as usize];
            let lane = |x: &crate::math::lanes::F8| x.as_array_ref()[l];
            let (mut impulses, mut approach) = ([0.0; MAX_POINTS], [0.0; MAX_POINTS]);
            for ((i, a), p) in impulses.iter_mut().zip(&mut approach).zip(points) {
                (*i, *a) = (lane(&p.normal_impulse), lane(&p.relative_velocity));
            }
            let t = [lane(&f.tangent_impulse[0]), lane(&f.tangent_impulse[1])];
            let tangent = tangents[0].lane(l) * t[0] + tangents[1].lane(l) * t[1];
            let shares = shares_of(&impulses[..m.len], tangent, lane(&f.twist_impulse));
            store_manifold(m, &impulses, &approach, shares);
        }
    }
    let colliders = &world.colliders;
    let key = |m: &Manifold| {
        let entity = |i: u32| colliders[i as usize].entity;
        (entity(m.a), entity(m.b), m.sub)
    };
    world.impulse_cache.index(&world.manifolds, key);
    let entities = colliders.iter().map(|c| c.entity);
    world.impulse_cache.remember_pairs(&world.pairs, entities);
}

/// One constraint's results into its manifold.
fn store_constraint(c: &ContactConstraint, manifolds: &mut [Manifold]) {
    store_into(c, &mut manifolds[c.manifold as usize]);
}

/// One constraint's results into manifold `m` (its own).
fn store_into(c: &ContactConstraint, m: &mut Manifold) {
    let (mut impulses, mut approach) = ([0.0; MAX_POINTS], [0.0; MAX_POINTS]);
    for ((i, a), p) in impulses
        .iter_mut()
        .zip(&mut approach)
        .zip(&c.points[..c.len])
    {
        (*i, *a) = (p.normal_impulse, p.relative_velocity);
    }
    let shares = friction_shares(c);
    store_manifold(m, &impulses, &approach, shares);
}

/// A manifold's points' normal impulses, approach (relative normal) velocities and
/// friction shares, as the step ends.
#[inline(always)]
fn store_manifold(
    m: &mut Manifold,
    impulses: &[f32; MAX_POINTS],
    approach: &[f32; MAX_POINTS],
    shares: [(Vec3, f32); MAX_POINTS],
) {
    // What this step warm-started from, last step's load, is the previous one now.
    m.previous_load = m.points().iter().map(|p| p.normal_impulse).sum();
    let points = m.points_mut().iter_mut().zip(impulses).zip(approach);
    for (((mp, &i), &a), share) in points.zip(shares) {
        mp.normal_impulse = i;
        (mp.tangent_impulse, mp.twist_impulse) = share;
        mp.approach_speed = (-a).max(0.0);
    }
}

/// Adds each point's accumulated impulses (what one substep applied) to its manifold's
/// totals for the step, for constraints that report them. Run after every substep but
/// the last, and once after restitution for the last (whose impulse restitution and the
/// final stop add to).
///
/// Only the scalar pass solves a contact that reports (`scalar`: its contacts), and only
/// theirs are kept as constraints.
pub fn sum_impulses(constraints: &[ContactConstraint], scalar: &[u32], manifolds: &mut [Manifold]) {
    let listed = scalar.iter().map(|&c| &constraints[c as usize]);
    for c in listed.filter(|c| c.report) {
        let m = &mut manifolds[c.manifold as usize];
        let shares = friction_shares(c);
        for ((mp, p), share) in m.points_mut().iter_mut().zip(&c.points).zip(shares) {
            mp.total_normal_impulse += p.normal_impulse;
            mp.total_tangent_impulse += share.0;
        }
    }
}

/// Each point's share of its constraint's friction impulse (world frame, N·s) and twist
/// impulse (N·m·s): its share of the normal impulse, or equal shares when none pushes.
pub fn friction_shares(c: &ContactConstraint) -> [(Vec3, f32); MAX_POINTS] {
    let mut impulses = [0.0; MAX_POINTS];
    for (i, p) in impulses.iter_mut().zip(&c.points[..c.len]) {
        *i = p.normal_impulse;
    }
    let t = c.anchor.tangent_impulse;
    let tangent = c.tangent1 * t.x + c.tangent2 * t.y;
    shares_of(&impulses[..c.len], tangent, c.anchor.twist_impulse)
}

/// [`friction_shares`] of the points' normal impulses `impulses`, the friction impulse
/// `tangent` (world frame) and the twist impulse `twist`.
fn shares_of(impulses: &[f32], tangent: Vec3, twist: f32) -> [(Vec3, f32); MAX_POINTS] {
    let total = impulses.iter().sum::<f32>();
    let mut shares = [(Vec3::ZERO, 0.0); MAX_POINTS];
    for (s, &i) in shares.iter_mut().zip(impulses) {
        let w = if total > 0.0 {
            i / total
        } else {
            1.0 / impulses.len() as f32
        };
        *s = (tangent * w, twist * w);
    }
    shares
}
