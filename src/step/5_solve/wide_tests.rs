//! The batched passes against the scalar ones they stand for (Jolt's way: the plain
//! loop is kept as the reference for the fast path). On random contacts between random
//! bodies, the contacts of each batch solved one after another by the scalar pass and
//! side by side by the lanes must leave every velocity and impulse bit for bit equal.

use bevy::prelude::*;

use super::bounce::restitution_steps;
use super::contact::friction_anchor;
use super::iterate::{apply_normal, apply_restitution, solve_listed, warm_start_listed};
use super::{Pass, solve_steps, warm_start_steps};
use crate::math::Softness;
use crate::rng::Rnd;
use crate::world::{
    Anchoring, AngularRow, ConstraintPoint, ContactBatches, ContactConstraint, ContactKey,
    FrictionAnchor, LANES, NO_CONTACT, NO_ROLL, STATIC, SolveStep, SolverBody, body,
    coupling_index, normal_couplings, row_velocity, world_inv_inertia,
};

pub(super) fn random_body(r: &mut Rnd) -> SolverBody {
    let kind = r.unit();
    let (inv_mass, inv_inertia) = if kind < 0.1 {
        (0.0, Mat3::ZERO) // kinematic
    } else if kind < 0.2 {
        (r.range(0.1, 2.0), Mat3::ZERO) // locked rotation
    } else if kind < 0.6 {
        (
            r.range(0.01, 2.0),
            Mat3::from_diagonal(Vec3::splat(r.range(0.2, 3.0))),
        )
    } else {
        let principal = r.vec(0.2, 3.0);
        (r.range(0.01, 2.0), world_inv_inertia(r.rot(), principal))
    };
    let still = inv_inertia == Mat3::ZERO && r.unit() < 0.5;
    SolverBody {
        v: r.vec(-3.0, 3.0),
        w: if still { Vec3::ZERO } else { r.vec(-5.0, 5.0) },
        dp: r.vec(-0.02, 0.02),
        dq: Quat::from_scaled_axis(r.vec(-0.05, 0.05)),
        inv_mass,
        inv_inertia,
    }
}

fn isotropic(b: &SolverBody) -> bool {
    b.inv_inertia == Mat3::from_diagonal(Vec3::splat(b.inv_inertia.x_axis.x))
}

pub(super) fn random_contact(r: &mut Rnd, bodies: &[SolverBody], fixed: bool) -> ContactConstraint {
    let n = bodies.len() as u32;
    let pick = |r: &mut Rnd| ((r.unit() * n as f32) as u32).min(n - 1);
    let (mut a, mut b) = (pick(r), pick(r));
    while a == b {
        b = pick(r);
    }
    if fixed {
        a = STATIC;
    }
    let (sa, sb) = (body(bodies, a), body(bodies, b));
    let normal = r.dir();
    let (t1, t2) = normal.any_orthonormal_pair();
    let len = 1 + (r.unit() * 4.0) as usize % 4;
    let spin = [sa, sb].map(|s| s.w != Vec3::ZERO || s.inv_inertia != Mat3::ZERO);
    let mut points = [ConstraintPoint::default(); 4];
    for p in &mut points[..len] {
        let (ra, rb) = (r.vec(-0.5, 0.5), r.vec(-0.5, 0.5));
        let normal_row = AngularRow::new(&sa, &sb, ra, rb, normal);
        let linear = sa.inv_mass + sb.inv_mass;
        let k = linear + normal_row.inv_mass(spin);
        *p = ConstraintPoint {
            ra,
            rb,
            // Some points apart (speculative), most touching or overlapping.
            adjusted_separation: r.range(-0.05, 0.02),
            normal_row,
            normal_mass: if k > 0.0 { 1.0 / k } else { 0.0 },
            normal_impulse: if r.unit() < 0.3 {
                0.0
            } else {
                r.range(0.0, 2.0)
            },
            twist_arm: r.range(0.0, 0.7),
            max_normal_impulse: if r.unit() < 0.5 {
                0.0
            } else {
                r.range(0.0, 2.0)
            },
            relative_velocity: r.range(-4.0, 1.0),
            separation: 0.0,
        };
    }
    let mut c = ContactConstraint {
        a,
        b,
        manifold: 0,
        normal,
        tangent1: t1,
        tangent2: t2,
        anchoring: Anchoring {
            turn: [r.unit() < 0.7, r.unit() < 0.7],
            roll: NO_ROLL,
        },
        spin,
        // As prepare marks them: a turning anisotropic body's rows are refreshed every
        // substep, and such contacts stay out of the batches.
        refresh: [sa, sb]
            .iter()
            .zip(spin)
            .any(|(s, spin)| spin && !isotropic(s)),
        report: false,
        friction: if r.unit() < 0.2 {
            0.0
        } else {
            r.range(0.1, 1.0)
        },
        restitution: 0.0,
        approach_gain: 9.81 / 60.0,
        softness: Softness::new(r.range(5.0, 60.0), r.range(1.0, 10.0), 1.0 / 240.0),
        max_push: if r.unit() < 0.3 { 0.05 } else { 3.0 },
        points,
        len,
        coupling: normal_couplings(&points[..len], sa.inv_mass + sb.inv_mass, spin),
        anchor: FrictionAnchor::default(),
    };
    let anchor = (r.vec(-0.5, 0.5), r.vec(-0.5, 0.5));
    c.anchor = friction_anchor(&sa, &sb, anchor, &c, len);
    c.anchor.tangent_impulse = Vec2::new(r.range(-0.5, 0.5), r.range(-0.5, 0.5));
    c.anchor.twist_impulse = if len > 1 { r.range(-0.3, 0.3) } else { 0.0 };
    c
}

/// The contacts of `steps` in the order a pass meets them (a batch's lanes in lane
/// order: they share no moved body, so any order of them gives the same bits): the
/// order the scalar reference must take to compute the same bits.
fn pass_order(batches: &ContactBatches, steps: std::ops::Range<usize>) -> Vec<u32> {
    let mut order = Vec::new();
    for step in &batches.steps[steps] {
        match step {
            SolveStep::Batches(r) => {
                let lanes = batches.batches[r.clone()].iter().flat_map(|b| b.contact);
                order.extend(lanes.filter(|&c| c != NO_CONTACT));
            }
            SolveStep::Scalar(c) => order.push(*c),
        }
    }
    order
}

pub(super) fn assert_same(bodies: &[SolverBody], reference: &[SolverBody], what: &str) {
    for (i, (x, y)) in bodies.iter().zip(reference).enumerate() {
        assert!(
            x.v == y.v && x.w == y.w,
            "{what}: body {i}: {x:?} against {y:?}"
        );
    }
}

/// Each compiled copy of the batched passes (see `math::lanes::three_operand`): the
/// one this CPU picks, and the plain one.
#[test]
fn batched_passes_compute_the_scalar_passes_bit_for_bit() {
    crate::math::lanes::in_each_copy(batched_passes_match_scalar);
}

fn batched_passes_match_scalar() {
    const BODIES: usize = 160;
    const CONTACTS: usize = 400;
    const FIXED: usize = 60;
    let mut r = Rnd(0x5eed_0017);
    let mut lanes_used = (0, 0);
    for round in 0..40 {
        // Enough bodies that a level holds several batches of eight disjoint contacts.
        let bodies: Vec<SolverBody> = (0..BODIES).map(|_| random_body(&mut r)).collect();
        let constraints: Vec<ContactConstraint> = (0..CONTACTS)
            .map(|i| random_contact(&mut r, &bodies, i < FIXED))
            .collect();
        let used = passes_match_scalar(&bodies, constraints, FIXED, &format!("round {round}"));
        lanes_used = (lanes_used.0 + used.0, lanes_used.1 + used.1);
    }
    // The test means something only if the lanes are mostly full.
    let fill = lanes_used.0 as f32 / lanes_used.1 as f32;
    assert!(fill > 0.6, "lanes {:.0} % full", 100.0 * fill);
}

/// Packs `scalar_constraints` (the first `fixed` with fixed colliders) into batches and
/// runs a warm start and three passes batched and, over the same contacts in pass
/// order, one at a time: every velocity and impulse must agree bit for bit. Returns the
/// lanes used and the lanes there were.
fn passes_match_scalar(
    bodies: &[SolverBody],
    mut scalar_constraints: Vec<ContactConstraint>,
    fixed: usize,
    what: &str,
) -> (usize, usize) {
    let h = 1.0 / 240.0;
    let mut constraints = scalar_constraints.clone();
    let mut batches = ContactBatches::default();
    batches.build(&constraints, bodies, fixed);
    let keys: Vec<_> = constraints
        .iter()
        .map(|c| ContactKey::of(c, bodies))
        .collect();
    assert!(batches.is_valid(&keys, bodies));
    let lanes = batches.batches.iter().flat_map(|b| b.contact);
    let used = (
        lanes.filter(|&c| c != NO_CONTACT).count(),
        LANES * batches.batches.len(),
    );
    let (steps, fixed_steps) = (batches.steps.len(), batches.fixed_steps);
    let (all, fixed_list) = (
        pass_order(&batches, 0..steps),
        pass_order(&batches, 0..fixed_steps),
    );

    let (mut lanes, mut scalar) = (bodies.to_vec(), bodies.to_vec());
    warm_start_steps(&mut lanes, &constraints, &batches, 0..steps);
    warm_start_listed(&mut scalar, &scalar_constraints, &all);
    assert_same(&lanes, &scalar, &format!("{what}: warm start"));

    for (pass, use_bias) in [true, false, true].into_iter().enumerate() {
        // The scalar pass measures the separations every time; the batched one only
        // in the first (nothing moves the bodies between passes here).
        let lists = [
            (0..steps, &all, pass == 0),
            (0..fixed_steps, &fixed_list, false),
        ];
        for (range, list, measure) in lists {
            let c = &mut constraints;
            let kind = Pass {
                h,
                use_bias,
                measure,
            };
            solve_steps(&mut lanes, c, &mut batches, range, &[], kind);
            let flags = (use_bias, true);
            solve_listed(&mut scalar, &mut scalar_constraints, list, &[], h, flags);
        }
        assert_same(&lanes, &scalar, &format!("{what}, pass {pass}"));
    }
    batches.write_back(0..batches.batches.len(), &mut constraints);
    for (i, (x, y)) in constraints.iter().zip(&scalar_constraints).enumerate() {
        for (p, q) in x.points[..x.len].iter().zip(&y.points) {
            assert!(
                p.normal_impulse == q.normal_impulse
                    && p.max_normal_impulse == q.max_normal_impulse
                    && p.relative_velocity == q.relative_velocity,
                "{what}: contact {i}: {p:?} against {q:?}"
            );
        }
        let (f, g) = (&x.anchor, &y.anchor);
        assert!(
            f.tangent_impulse == g.tangent_impulse && f.twist_impulse == g.twist_impulse,
            "{what}: contact {i}: {f:?} against {g:?}"
        );
    }
    used
}

/// The couplings against what they stand for: a unit normal impulse at point k, applied
/// to the bodies point by point (as restitution still applies it), changes point j's
/// normal velocity by K_jk. Each side of the comparison rounds a few dot products of
/// terms no larger than the velocities and K themselves, so they agree to a few ε of
/// those magnitudes; a coupling missing a body's turn, or a term, is off by O(1).
#[test]
fn couplings_are_the_velocity_change_of_a_unit_impulse() {
    let mut r = Rnd(0x5eed_0031);
    let bodies: Vec<SolverBody> = (0..8).map(|_| random_body(&mut r)).collect();
    let mut checked = 0;
    for _ in 0..500 {
        let fixed = r.unit() < 0.3;
        let c = random_contact(&mut r, &bodies, fixed);
        let (a0, b0) = (body(&bodies, c.a), body(&bodies, c.b));
        for k in 0..c.len {
            let (mut a, mut b) = (a0, b0);
            let row_k = &c.points[k].normal_row;
            apply_normal(&mut a, &mut b, c.normal, row_k, 1.0, c.spin);
            for j in k + 1..c.len {
                let row = &c.points[j].normal_row;
                let before = row_velocity(&a0, &b0, c.normal, row, c.spin);
                let after = row_velocity(&a, &b, c.normal, row, c.spin);
                let coupling = c.coupling[coupling_index(j, k)];
                let tol = 16.0 * f32::EPSILON * (before.abs() + after.abs() + coupling.abs());
                assert!(
                    (after - before - coupling).abs() <= tol,
                    "K[{j}][{k}] = {coupling}, the impulse moved the row by {}",
                    after - before
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 500, "only {checked} pairs of points checked");
}

/// Restitution where the contacts are solved (the batched ones in their lanes, in pass
/// order) against `apply_restitution` over every constraint in pass order, in each
/// compiled copy: the same velocities and impulses, bit for bit.
#[test]
fn batched_restitution_computes_the_scalar_one_bit_for_bit() {
    crate::math::lanes::in_each_copy(batched_restitution_matches_scalar);
}

fn batched_restitution_matches_scalar() {
    const BODIES: usize = 160;
    const CONTACTS: usize = 400;
    const FIXED: usize = 60;
    const THRESHOLD: f32 = 1.0;
    let mut r = Rnd(0x5eed_0041);
    let mut bounced = 0;
    for round in 0..20 {
        let bodies: Vec<SolverBody> = (0..BODIES).map(|_| random_body(&mut r)).collect();
        let mut scalar_constraints: Vec<ContactConstraint> = (0..CONTACTS)
            .map(|i| {
                let mut c = random_contact(&mut r, &bodies, i < FIXED);
                c.restitution = if r.unit() < 0.3 {
                    0.0
                } else {
                    r.range(0.1, 1.0)
                };
                c
            })
            .collect();
        let mut constraints = scalar_constraints.clone();
        let mut batches = ContactBatches::default();
        batches.build(&constraints, &bodies, FIXED);
        let (mut lanes, mut scalar) = (bodies.clone(), bodies.clone());
        restitution_steps(&mut lanes, &mut constraints, &mut batches, THRESHOLD);
        for i in pass_order(&batches, 0..batches.steps.len()) {
            let c = std::slice::from_mut(&mut scalar_constraints[i as usize]);
            apply_restitution(&mut scalar, c, THRESHOLD);
        }
        assert_same(&lanes, &scalar, &format!("round {round}: restitution"));
        batches.write_back(0..batches.batches.len(), &mut constraints);
        for (i, (x, y)) in constraints.iter().zip(&scalar_constraints).enumerate() {
            for (p, q) in x.points[..x.len].iter().zip(&y.points) {
                assert!(
                    p.normal_impulse.to_bits() == q.normal_impulse.to_bits()
                        && p.max_normal_impulse.to_bits() == q.max_normal_impulse.to_bits(),
                    "round {round}: contact {i}: {p:?} against {q:?}"
                );
            }
        }
        let moved = lanes.iter().zip(&bodies).filter(|(x, y)| x.v != y.v);
        bounced += moved.count();
    }
    // Something must have bounced for the comparison to mean anything.
    assert!(bounced > 500, "only {bounced} bodies moved by restitution");
}

/// A tower's contacts (a chain: body i on body i − 1, the bottom one on the ground) make
/// one level each, too narrow for a batch; the run is coloured instead: the ground
/// contact alone (the fixed part), then every other link side by side, then the rest.
/// The two colours in their lanes compute the scalar pass's bits in that order, in each
/// compiled copy.
#[test]
fn a_chain_is_solved_in_two_colours() {
    let mut r = Rnd(0x5eed_00c4);
    let n = 12;
    // Every one dynamic (random bodies include fixed ones, which would cut the chain)
    // and round (a turning anisotropic body's contacts take the scalar pass).
    let dynamic = |mut b: SolverBody| {
        b.inv_mass = 1.0;
        b.inv_inertia = Mat3::from_diagonal(Vec3::splat(6.0));
        b
    };
    let bodies: Vec<SolverBody> = (0..n).map(|_| dynamic(random_body(&mut r))).collect();
    // Each contact drawn between its two bodies alone (indices 0 and 1 of `pair`), then
    // put on their places in the chain: `on` is the lower body, or None for the ground.
    let mut link = |on: Option<u32>, top: u32| {
        let lower = on.map_or(bodies[top as usize], |i| bodies[i as usize]);
        let pair = [lower, bodies[top as usize]];
        let mut c = random_contact(&mut r, &pair, on.is_none());
        let place = |i: u32| match i {
            STATIC => STATIC,
            0 => on.unwrap_or(top),
            _ => top,
        };
        (c.a, c.b) = (place(c.a), place(c.b));
        c
    };
    let mut constraints = vec![link(None, 0)];
    constraints.extend((1..n as u32).map(|i| link(Some(i - 1), i)));
    let mut batches = ContactBatches::default();
    batches.build(&constraints, &bodies, 1);
    let lanes = |b: usize| -> Vec<u32> {
        let lanes = batches.batches[b].contact.into_iter();
        lanes.filter(|&c| c != NO_CONTACT).collect()
    };
    assert_eq!(
        batches.steps,
        [
            SolveStep::Scalar(0),
            SolveStep::Batches(0..1),
            SolveStep::Batches(1..2)
        ]
    );
    assert_eq!(lanes(0), [1, 3, 5, 7, 9, 11]);
    assert_eq!(lanes(1), [2, 4, 6, 8, 10]);
    crate::math::lanes::in_each_copy(|| {
        passes_match_scalar(&bodies, constraints.clone(), 1, "chain");
    });
}
