//! PrepareContacts: the step's contacts built straight into the lanes they are solved in.
//!
//! First each manifold's key (its bodies, its point count, whether only the scalar pass
//! may solve it); the batches are packed from the keys alone; then each contact is built
//! and written into its batch's lanes. Only the contacts a later stage reads as
//! constraints are also kept as constraints: those the scalar pass solves, those with
//! fixed colliders (the final stop reads them), and all of them when asked (`keep_all`:
//! tests and benchmarks); restitution bounces the batched ones in their lanes. Before,
//! every contact was built into its 688-byte constraint and packed from it: on the
//! 385-cube pyramid, 1.7 MB written and read again a step.

use super::contact::{Builder, Prepared};
use super::contact_lanes::{BatchOut, ConstraintExtras, ManifoldLanes, compute};
use super::contact_load::LoadLanes;
#[cfg(target_arch = "x86_64")]
use crate::math::lanes::avx::Y8;
use crate::math::lanes::{F8, Lane, three_operand_copy};
use crate::world::{
    AnchorLanes, BodyState, BodyView, ColliderEntry, ContactBatch, ContactBatches,
    ContactConstraint, ContactKey, ContactParams, FrictionLanes, Manifold, NO_CONTACT, PointLanes,
    RollingArms, STATIC, Shared, SolverBody, prefetch,
};

/// Manifolds from which the contacts are built on two threads (when the compute pool
/// has them): a helper takes about 30 µs to wake. On 100 pyramids' 14,500 manifolds
/// splitting took 1.2-1.4 ms off the step. On the 385-cube pyramid's 2,432 it measured
/// the same as not in `stage_times` (tumble's app alone), but in `peers` at two threads,
/// where avian's app shares the pool, splitting from 1,024 left the step at 2.25-2.28 ms
/// against 2.10-2.19 from 4,096 (three interleaved runs).
pub const PARALLEL_PREPARE_FROM: usize = 4096;

/// Batches ahead of the one being built whose manifolds are fetched (their colliders one
/// batch nearer, their bodies nearer still).
const PREFETCH_AHEAD: usize = 3;

/// Builds the step's contacts: keys into `keys`, the batches (see [`ContactBatches`]),
/// and the constraints that are kept into `out` (one place a manifold; the places of
/// contacts not kept hold what they held). `per_body`: the survey's overlaps and
/// heaviest loads per body. With `split`, half the batches and half the scalar contacts
/// are built on the compute pool (another thread if it has one) while the caller builds
/// the rest; each contact depends only on its manifold, so the result is the same bits.
pub fn prepare_contacts(
    manifolds: &[Manifold],
    (colliders, states, bodies): (&[ColliderEntry], &[BodyState], &[SolverBody]),
    stiffness: ContactParams,
    per_body: (&[u32], &[f32]),
    (out, keys): (&mut Vec<ContactConstraint>, &mut Vec<ContactKey>),
    (batches, arms): (&mut ContactBatches, &mut Vec<RollingArms>),
    (split, keep_all): (bool, bool),
) -> Prepared {
    let builder = Builder::new(colliders, states, bodies, stiffness, per_body);
    // One pass over the manifolds for their keys.
    keys.clear();
    keys.extend(manifolds.iter().map(|m| builder.key(m)));
    let fixed = keys
        .iter()
        .take_while(|k| k.a == STATIC || k.b == STATIC)
        .count();
    batches.pack_keyed(keys, bodies, fixed);
    out.resize_with(manifolds.len(), ContactConstraint::default);
    arms.clear();
    // Batched contacts below this place are kept as constraints too (restitution
    // bounces the others in their lanes: see `bounce`).
    let keep_below = if keep_all { manifolds.len() } else { fixed };
    let constraints = Shared::new(out);
    let job = |part: Part, scalar: &[u32], arms: &mut Vec<RollingArms>| {
        let shared = (&builder, manifolds, keep_below, constraints);
        build_part(shared, part, scalar, arms)
    };
    let job = &job;
    let ContactBatches {
        batches: list,
        points,
        anchors,
        friction,
        scalar,
        scalar_in_order,
        ..
    } = batches;
    // The scalar contacts built in manifold order, as the manifolds lie in memory (in
    // pass order, level by level, they are all over the list: rain, whose turning boxes
    // take the scalar pass, spent 3-4 % more of its step building them).
    scalar_in_order.clear();
    scalar_in_order.extend_from_slice(scalar);
    scalar_in_order.sort_unstable();
    let scalar = &*scalar_in_order;
    let whole = Part {
        batches: list,
        points,
        anchors,
        friction,
    };
    let mut found = if !split {
        job(whole, scalar, arms)
    } else {
        let (first, second) = whole.split();
        let (scalar_first, scalar_second) = scalar.split_at(scalar.len() / 2);
        // (Allocates only if the second half has a rolling contact.)
        let mut second_arms = Vec::new();
        let mut found = [None, None];
        bevy::tasks::ComputeTaskPool::get().scope(|scope| {
            let [f0, f1] = &mut found;
            let arms1 = &mut second_arms;
            scope.spawn(async move {
                *f1 = Some(job(second, scalar_second, arms1));
            });
            *f0 = Some(job(first, scalar_first, arms));
        });
        let [Some(f0), Some(f1)] = found else {
            unreachable!("both halves ran");
        };
        // The second half's rolling motions after the first's.
        if !second_arms.is_empty() {
            let offset = arms.len() as u32;
            for &ci in scalar_second {
                let c = &mut out[ci as usize];
                if c.anchoring.rolls() {
                    c.anchoring.roll += offset;
                }
            }
            arms.append(&mut second_arms);
        }
        Prepared {
            ratio: f0.ratio.max(f1.ratio),
            relax_ratio: f0.relax_ratio.max(f1.relax_ratio),
            fixed: 0,
            refresh: f0.refresh || f1.refresh,
            report: f0.report || f1.report,
            bounce: f0.bounce || f1.bounce,
        }
    };
    found.fixed = fixed;
    found
}

/// A run of batches with their points and friction impulses.
struct Part<'a> {
    batches: &'a mut [ContactBatch],
    points: &'a mut [PointLanes],
    anchors: &'a mut [AnchorLanes],
    friction: &'a mut [FrictionLanes],
}

impl Part<'_> {
    /// The first half of the batches and the second, each with its own points.
    fn split(self) -> (Self, Self) {
        let half = self.batches.len() / 2;
        let cut = self
            .batches
            .get(half)
            .map_or(self.points.len(), |b| b.first as usize);
        let (b0, b1) = self.batches.split_at_mut(half);
        let (p0, p1) = self.points.split_at_mut(cut);
        let (a0, a1) = self.anchors.split_at_mut(cut);
        let (f0, f1) = self.friction.split_at_mut(half);
        (
            Part {
                batches: b0,
                points: p0,
                anchors: a0,
                friction: f0,
            },
            Part {
                batches: b1,
                points: p1,
                anchors: a1,
                friction: f1,
            },
        )
    }
}

/// What every part reads: the builder, the manifolds, the places below which batched
/// contacts are kept as constraints and kept whole, and the constraints, each written by
/// one part only.
type PartShared<'a> = (
    &'a Builder<'a>,
    &'a [Manifold],
    usize,
    Shared<ContactConstraint>,
);

three_operand_copy! {
    /// Builds a part's batched contacts into their lanes and its scalar contacts (and
    /// the batched ones below the keeping place) into their constraints.
    fn build_part / build_part_vex => build_part_any::<F8, Y8>(
        shared: PartShared,
        part: Part,
        scalar: &[u32],
        arms: &mut Vec<RollingArms>,
    ) -> Prepared
}

#[inline(always)]
fn build_part_any<L: Lane>(
    (builder, manifolds, keep_below, constraints): PartShared,
    part: Part,
    scalar: &[u32],
    arms: &mut Vec<RollingArms>,
) -> Prepared {
    let mut found = Prepared {
        ratio: 1.0,
        relax_ratio: 1.0,
        fixed: 0,
        refresh: false,
        report: false,
        bounce: false,
    };
    // A batched contact not kept is built aside.
    let mut aside = ContactConstraint::default();
    let base = part.batches.first().map_or(0, |b| b.first as usize);
    let mut lanes = ManifoldLanes::default();
    let mut extras = ConstraintExtras::default();
    let mut loads = LoadLanes::default();
    for j in 0..part.batches.len() {
        fetch_ahead(builder, manifolds, part.batches, j);
        let batch = &mut part.batches[j];
        let range = batch.range();
        let range = range.start - base..range.end - base;
        let (point, anchor) = (&mut part.points[range.clone()], &mut part.anchors[range]);
        // The lanes' headers one by one, then their points at once.
        let mut kept = false;
        for (l, ci) in batch.contact.into_iter().enumerate() {
            if ci == NO_CONTACT {
                lanes.clear(l);
                continue;
            }
            let ci = ci as usize;
            let m = &manifolds[ci];
            let c = if ci < keep_below {
                kept = true;
                // SAFETY: each contact is built by one part only, and nothing else
                // reads the constraints meanwhile.
                unsafe { &mut constraints.slice(ci..ci + 1)[0] }
            } else {
                &mut aside
            };
            let loads = Some((&mut loads, l));
            let centres = builder.header(c, ci, m, arms, &mut found, loads);
            debug_assert_eq!(ContactKey::of(c, builder.bodies), builder.key(m));
            debug_assert!(!c.anchoring.rolls(), "a rolling contact is never batched");
            batch.set_header(l, c, builder.bodies);
            let sides = [builder.bodies.at(c.a), builder.bodies.at(c.b)];
            lanes.set(l, m, c, sides, centres);
        }
        let soft = loads.soften::<L>(&builder.stiffness);
        let any = lanes.any();
        batch.bias_rate = soft.bias_rate & any;
        batch.mass_scale = soft.mass_scale & any;
        batch.impulse_scale = soft.impulse_scale & any;
        for (l, ci) in batch.contact.into_iter().enumerate() {
            if ci != NO_CONTACT {
                let lane = |v: &F8| v.as_array_ref()[l];
                found.ratio = found.ratio.max(lane(&soft.ratio));
                found.relax_ratio = found.relax_ratio.max(lane(&soft.relax));
            }
        }
        let rubbing = &mut part.friction[j];
        let out = BatchOut {
            batch,
            point,
            anchor,
            rubbing,
            extras: kept.then_some(&mut extras),
        };
        compute::<L>(&lanes, out);
        if kept {
            let lanes = (&*batch, &*point, &*anchor, &*rubbing);
            for (l, ci) in batch.contact.into_iter().enumerate() {
                let ci = ci as usize;
                if ci < keep_below {
                    // SAFETY: as `keep`'s.
                    let c = unsafe { &mut constraints.slice(ci..ci + 1)[0] };
                    extras.write(l, lanes, &manifolds[ci], c);
                }
            }
        }
    }
    for (k, &ci) in scalar.iter().enumerate() {
        // Fetched ahead as the batches are: the manifolds, then their colliders, then
        // their bodies.
        if let Some(&next) = scalar.get(k + 2 * SCALAR_AHEAD) {
            prefetch(&manifolds[next as usize]);
        }
        if let Some(&next) = scalar.get(k + SCALAR_AHEAD) {
            builder.prefetch(&manifolds[next as usize], false);
        }
        if let Some(&next) = scalar.get(k + SCALAR_AHEAD / 2) {
            builder.prefetch(&manifolds[next as usize], true);
        }
        let ci = ci as usize;
        // SAFETY: as the batched contacts'.
        let c = unsafe { &mut constraints.slice(ci..ci + 1)[0] };
        builder.build(c, ci, &manifolds[ci], arms, &mut found);
    }
    found
}

/// Scalar contacts ahead of the one being built whose colliders are fetched (their
/// manifolds twice as far, their bodies half as far).
const SCALAR_AHEAD: usize = 4;

/// Asks the CPU for what the batches after batch `j` read: a level's contacts sit all
/// over the manifold list. Their manifolds [`PREFETCH_AHEAD`] batches ahead, then their
/// colliders, then their bodies.
#[inline(always)]
fn fetch_ahead(builder: &Builder, manifolds: &[Manifold], batches: &[ContactBatch], j: usize) {
    let lanes = |b: &ContactBatch| b.contact.into_iter().filter(|&c| c != NO_CONTACT);
    if let Some(b) = batches.get(j + PREFETCH_AHEAD) {
        lanes(b).for_each(|ci| prefetch(&manifolds[ci as usize]));
    }
    if let Some(b) = batches.get(j + PREFETCH_AHEAD - 1) {
        lanes(b).for_each(|ci| builder.prefetch(&manifolds[ci as usize], false));
    }
    if let Some(b) = batches.get(j + 1) {
        lanes(b).for_each(|ci| builder.prefetch(&manifolds[ci as usize], true));
    }
}
