//! The per-iteration contact passes: warm start, the Gauss–Seidel solve (soft or relaxed)
//! and restitution. Each constraint loads its two bodies once and stores them once; each
//! row uses the angular parts prepared in [`AngularRow`], and a body that cannot turn
//! (static, or `LockRotation`) runs no angular terms at all. A sweep over a manifold's
//! normal rows reads the bodies once and moves them once, the rows seeing each other's
//! impulses through their couplings ([`normal_couplings`]): the same Gauss–Seidel sweep
//! (up to rounding), with the bodies' velocities updated once a sweep, not once a point.

use bevy::prelude::*;

use crate::math::lanes::three_operand_copy;
use crate::world::{
    AngularRow, ConstraintPoint, ContactConstraint, FrictionAnchor, MAX_POINTS, RollingArms,
    SolverBody, body, coupling_index, normal_couplings, row_velocity, store,
};

/// Linear impulse `p` on b and −p on a, with the angular parts `ang_a`, `ang_b`
/// (inverse inertia times r × p, already scaled).
#[inline]
fn apply(a: &mut SolverBody, b: &mut SolverBody, p: Vec3, ang: [Vec3; 2], spin: [bool; 2]) {
    a.v -= a.inv_mass * p;
    b.v += b.inv_mass * p;
    if spin[0] {
        a.w -= ang[0];
    }
    if spin[1] {
        b.w += ang[1];
    }
}

/// A normal impulse `dl` at one point.
#[inline]
pub(super) fn apply_normal(
    a: &mut SolverBody,
    b: &mut SolverBody,
    n: Vec3,
    row: &AngularRow,
    dl: f32,
    spin: [bool; 2],
) {
    apply(a, b, n * dl, [row.ia * dl, row.ib * dl], spin);
}

/// Normal impulses `dl` at `points`, all at once: Σ dl·n on the bodies, and their
/// moments Σ dl (r × n) through each inverse inertia once (the same impulse as point by
/// point, with a third of the arithmetic; the rounding differs). The warm start applies
/// last step's impulses so, and each normal sweep its own.
#[inline(always)]
fn apply_normals(
    (a, b): (&mut SolverBody, &mut SolverBody),
    n: Vec3,
    points: &[ConstraintPoint],
    dl: impl IntoIterator<Item = f32>,
    spin: [bool; 2],
) {
    let (mut total, mut ra, mut rb) = (0.0, Vec3::ZERO, Vec3::ZERO);
    for (p, dl) in points.iter().zip(dl) {
        total += dl;
        ra += p.normal_row.ra * dl;
        rb += p.normal_row.rb * dl;
    }
    let moments = [a.inv_inertia * ra, b.inv_inertia * rb];
    apply(a, b, n * total, moments, spin);
}

/// A twist impulse `d` about the normal: +d on b, −d on a.
#[inline]
fn apply_twist(
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &FrictionAnchor,
    d: f32,
    spin: [bool; 2],
) {
    if spin[0] {
        a.w -= f.twist_ia * d;
    }
    if spin[1] {
        b.w += f.twist_ib * d;
    }
}

/// How fast b turns relative to a about the normal `n`, rad/s (a body that cannot
/// turn has w = 0).
#[inline]
fn twist_velocity(a: &SolverBody, b: &SolverBody, n: Vec3) -> f32 {
    b.w.dot(n) - a.w.dot(n)
}

/// `x` held to `lo..=hi` as the batched pass's `clamp` does it (a NaN stays NaN; no
/// panic on a NaN bound).
#[inline]
fn clamp_to(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x < lo { lo } else { x };
    if x > hi { hi } else { x }
}

/// A friction impulse `d` (along tangent1, tangent2) at the friction anchor.
#[inline]
fn apply_tangent(
    a: &mut SolverBody,
    b: &mut SolverBody,
    tangents: [Vec3; 2],
    rows: &[AngularRow; 2],
    d: Vec2,
    spin: [bool; 2],
) {
    let p = tangents[0] * d.x + tangents[1] * d.y;
    let ang = [
        rows[0].ia * d.x + rows[1].ia * d.y,
        rows[0].ib * d.x + rows[1].ib * d.y,
    ];
    apply(a, b, p, ang, spin);
}

three_operand_copy! {
    /// Applies last step's accumulated impulses (already in the constraints) of the listed
    /// contacts (the scalar ones of a step, [`SolveStep::Scalar`](crate::world::SolveStep);
    /// the batched ones have their own pass).
    pub fn warm_start_listed / warm_start_listed_vex => warm_start_listed_any(
        bodies: &mut [SolverBody],
        constraints: &[ContactConstraint],
        listed: &[u32],
    )
}

#[inline(always)]
fn warm_start_listed_any(
    bodies: &mut [SolverBody],
    constraints: &[ContactConstraint],
    listed: &[u32],
) {
    listed
        .iter()
        .for_each(|&i| warm_start_one(bodies, &constraints[i as usize]));
}

#[inline(always)]
fn warm_start_one(bodies: &mut [SolverBody], c: &ContactConstraint) {
    let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
    let points = &c.points[..c.len];
    let impulses = points.iter().map(|p| p.normal_impulse);
    apply_normals((&mut a, &mut b), c.normal, points, impulses, c.spin);
    let f = &c.anchor;
    let tangents = [c.tangent1, c.tangent2];
    apply_tangent(
        &mut a,
        &mut b,
        tangents,
        &f.tangent_rows,
        f.tangent_impulse,
        c.spin,
    );
    apply_twist(&mut a, &mut b, f, f.twist_impulse, c.spin);
    store(bodies, c.a, a);
    store(bodies, c.b, b);
}

three_operand_copy! {
    /// One Gauss–Seidel pass over the listed contacts (the scalar ones of a step; the batched
    /// ones have their own pass, lane by lane the same as this): for each manifold, the
    /// normal rows of all its points (soft with bias, or rigid when relaxing), then its
    /// friction anchor's disc clamped to μ·Σλn and twist clamped to μ·Σ λn·arm with the
    /// updated normal impulses.
    /// Accumulated impulses are clamped, never increments. Speculative points (s > 0) may
    /// close their gap, not more. Impulses act at the start-of-step anchors; the separation
    /// follows the anchors as the bodies move and turn. `measure`: the bodies moved since the
    /// separations were last measured (as for [`solve_batches`](super::wide::solve_batches));
    /// else the pass reads the ones it stored, the same bits.
    pub fn solve_listed / solve_listed_vex => solve_listed_any(
        bodies: &mut [SolverBody],
        constraints: &mut [ContactConstraint],
        listed: &[u32],
        arms: &[RollingArms],
        h: f32,
        flags: (bool, bool),
    )
}

#[inline(always)]
fn solve_listed_any(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    listed: &[u32],
    arms: &[RollingArms],
    h: f32,
    (use_bias, measure): (bool, bool),
) {
    let inv_h = 1.0 / h;
    // The contacts without a rolling motion in a loop that calls nothing, then the few
    // with one (`arms` is empty when there are none).
    for &i in listed {
        let c = &mut constraints[i as usize];
        if !c.anchoring.rolls() {
            solve_one::<false>(bodies, c, arms, inv_h, (use_bias, measure));
        }
    }
    if !arms.is_empty() {
        for &i in listed {
            let c = &mut constraints[i as usize];
            if c.anchoring.rolls() {
                solve_rolling(bodies, c, arms, inv_h, (use_bias, measure));
            }
        }
    }
}

/// [`solve_one`] for a contact with a rolling motion: out of line, so that the common
/// loop above holds no call.
#[cold]
#[inline(never)]
fn solve_rolling(
    bodies: &mut [SolverBody],
    c: &mut ContactConstraint,
    arms: &[RollingArms],
    inv_h: f32,
    flags: (bool, bool),
) {
    solve_one::<true>(bodies, c, arms, inv_h, flags);
}

/// One contact's pass (see [`solve`]); `ROLLS`: it has a rolling motion.
#[inline(always)]
fn solve_one<const ROLLS: bool>(
    bodies: &mut [SolverBody],
    c: &mut ContactConstraint,
    arms: &[RollingArms],
    inv_h: f32,
    (use_bias, measure): (bool, bool),
) {
    {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        let anchoring = c.anchoring;
        let dp = b.dp - a.dp;
        let spin = c.spin;
        // A manifold's normal rows are coupled through its two bodies (a cube's corner
        // rows: 4/m on the diagonal, 1/m and −2/m off it), so one sweep leaves an impact's
        // impulses lopsided. Sweep again while a sweep moves them by more than NORMAL_TOL
        // of their sum, at most NORMAL_SWEEPS times; not when a row is held at the
        // push-out cap (a shared rate limit: converged, the shares add up).
        // Each point's separation now: the same in every sweep and pass until the
        // bodies move (positions move only between substeps), so measured once.
        // (Debug builds measure every pass, and check that the stored ones are what
        // measuring gives.)
        if measure || cfg!(debug_assertions) {
            let mut now = [0.0f32; MAX_POINTS];
            if ROLLS {
                for (s, p) in now.iter_mut().zip(&c.points[..c.len]) {
                    let (ca, cb) = anchoring.anchors(p, &a, &b, arms);
                    *s = c.normal.dot(dp + cb - ca) + p.adjusted_separation;
                }
            } else {
                let moved = c.normal.dot(dp);
                let (na, nb) = anchoring.normal_images(c.normal, &a, &b);
                for (s, p) in now.iter_mut().zip(&c.points[..c.len]) {
                    *s = moved + nb.dot(p.rb) - na.dot(p.ra) + p.adjusted_separation;
                }
            }
            for (p, s) in c.points[..c.len].iter_mut().zip(now) {
                debug_assert!(
                    measure || p.separation.to_bits() == s.to_bits(),
                    "a stored separation is stale: the bodies moved since it was measured"
                );
                p.separation = s;
            }
        }
        let mut separation = [0.0f32; MAX_POINTS];
        for (s, p) in separation.iter_mut().zip(&c.points[..c.len]) {
            *s = p.separation;
        }
        debug_assert!(
            c.coupling.map(f32::to_bits)
                == normal_couplings(&c.points[..c.len], a.inv_mass + b.inv_mass, spin)
                    .map(f32::to_bits),
            "a contact's couplings are out of date with its rows"
        );
        // Unrolled for each point count (the loops over points then have fixed bounds).
        match c.len {
            4 => normal_sweeps::<4>(&mut a, &mut b, c, &separation, inv_h, use_bias),
            3 => normal_sweeps::<3>(&mut a, &mut b, c, &separation, inv_h, use_bias),
            2 => normal_sweeps::<2>(&mut a, &mut b, c, &separation, inv_h, use_bias),
            1 => normal_sweeps::<1>(&mut a, &mut b, c, &separation, inv_h, use_bias),
            _ => {}
        }
        // Friction, skipped for frictionless pairs (and when the effect is off): the
        // disc at the anchor, clamped to μ·Σλn, then the twist, clamped to μ·Σ λn·arm.
        if c.friction > 0.0 {
            let (mut total, mut moment) = (0.0f32, 0.0f32);
            for p in &c.points[..c.len] {
                total += p.normal_impulse;
                moment += p.normal_impulse * p.twist_arm;
            }
            let tangents = [c.tangent1, c.tangent2];
            let f = &mut c.anchor;
            // Both tangent rows from the same velocity, then clamp to the disc: a round
            // cone.
            let [r1, r2] = &f.tangent_rows;
            let vt = Vec2::new(
                row_velocity(&a, &b, c.tangent1, r1, spin),
                row_velocity(&a, &b, c.tangent2, r2, spin),
            );
            let old = f.tangent_impulse;
            let mut new = (old - f.tangent_mass * vt).clamp_length_max(c.friction * total);
            // `clamp_length_max` passes NaN through: a body gone non-finite (it will be
            // frozen at writeback) must not hand NaN to its neighbour through friction.
            if !new.is_finite() {
                new = Vec2::ZERO;
            }
            f.tangent_impulse = new;
            apply_tangent(&mut a, &mut b, tangents, &f.tangent_rows, new - old, spin);
            if f.twist_mass > 0.0 {
                let limit = c.friction * moment;
                let old = f.twist_impulse;
                let vw = twist_velocity(&a, &b, c.normal);
                let mut new = clamp_to(old - f.twist_mass * vw, -limit, limit);
                if !new.is_finite() {
                    new = 0.0;
                }
                f.twist_impulse = new;
                apply_twist(&mut a, &mut b, f, new - old, spin);
            }
        }
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}

/// One contact's sweeps over its `N` normal rows (see [`solve_one`]): each reads the
/// points' normal velocities once, passes each point's impulse on to the points after it
/// through the couplings, and moves the bodies once at its end.
#[inline(always)]
fn normal_sweeps<const N: usize>(
    a: &mut SolverBody,
    b: &mut SolverBody,
    c: &mut ContactConstraint,
    separation: &[f32; MAX_POINTS],
    inv_h: f32,
    use_bias: bool,
) {
    debug_assert_eq!(N, c.len, "the sweeps' point count");
    let spin = c.spin;
    let sweeps = if N > 1 { NORMAL_SWEEPS } else { 1 };
    for _ in 0..sweeps {
        let mut vn = [0.0f32; MAX_POINTS];
        for (v, p) in vn.iter_mut().zip(&c.points[..N]) {
            *v = row_velocity(a, b, c.normal, &p.normal_row, spin);
        }
        let mut dls = [0.0f32; MAX_POINTS];
        let (mut largest, mut total, mut capped) = (0.0f32, 0.0f32, false);
        for (k, &s) in separation[..N].iter().enumerate() {
            let p = &mut c.points[k];
            let (bias, mass_scale, impulse_scale) = if s > 0.0 {
                (s * inv_h, 1.0, 0.0)
            } else if use_bias {
                let soft = c.softness;
                capped |= soft.bias_rate * s < -c.max_push;
                (
                    (soft.bias_rate * s).max(-c.max_push),
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let vn_k = vn[k];
            let lambda =
                -p.normal_mass * mass_scale * (vn_k + bias) - impulse_scale * p.normal_impulse;
            let new = (p.normal_impulse + lambda).max(0.0);
            if p.max_normal_impulse == 0.0 && new > 0.0 {
                // First push on this point: the approach speed that restitution
                // reverses, as fast as free motion made it since the step began,
                // and no faster. Other contacts' impulses (a light body squeezed
                // between a heavy one and a wall) are not an approach to reverse.
                // Until now it holds the start-of-step speed.
                let prepared = p.relative_velocity;
                p.relative_velocity = vn_k.clamp(prepared - c.approach_gain, prepared);
            }
            let dl = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal_impulse = p.max_normal_impulse.max(new);
            dls[k] = dl;
            for j in k + 1..N {
                vn[j] += c.coupling[coupling_index(j, k)] * dl;
            }
            largest = largest.max(dl.abs());
            total += new;
        }
        apply_normals((a, b), c.normal, &c.points[..N], dls, spin);
        if capped || largest <= NORMAL_TOL * total {
            break;
        }
    }
}

/// Most sweeps over one manifold's normal rows in a pass.
pub const NORMAL_SWEEPS: usize = 4;
/// A sweep that changes no row by more than this fraction of the manifold's total normal
/// impulse ends the sweeps (resting contacts: mostly after the first). At 1e-3 the large
/// pyramid's batches swept 1.85 times a pass on average, at 1e-2 1.26, with the same
/// largest displacement after 220 steps (0.179 and 0.178 m); at 3e-2 a flat 150 m/s box
/// lands 0.55 mm deep, twice what `fast_bodies` allows.
pub const NORMAL_TOL: f32 = 1e-2;

/// Restitution: points that were approaching faster than `threshold` and pushed get
/// their normal velocity driven to −e times the approach speed.
pub fn apply_restitution(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    threshold: f32,
) {
    for c in constraints.iter_mut().filter(|c| c.restitution > 0.0) {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        for p in c.points[..c.len].iter_mut() {
            if p.relative_velocity > -threshold || p.max_normal_impulse == 0.0 {
                continue;
            }
            let vn = row_velocity(&a, &b, c.normal, &p.normal_row, c.spin);
            let lambda = -p.normal_mass * (vn + c.restitution * p.relative_velocity);
            let new = (p.normal_impulse + lambda).max(0.0);
            let dl = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal_impulse = p.max_normal_impulse.max(new);
            apply_normal(&mut a, &mut b, c.normal, &p.normal_row, dl, c.spin);
        }
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}

/// After restitution: points that touch (separation ≤ 0 at the end of the step) and
/// still approach get the impulse that stops them, and no more (nothing is taken back, so
/// a bounce off this contact stays). Run over the contacts with fixed colliders: a light
/// ball knocked toward a wall by a heavy one's bounce left the step 5 mm inside the wall
/// at 12.7 m/s, and sank 1.5 cm under the next steps' load.
pub fn stop_approach(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    arms: &[RollingArms],
) {
    for c in constraints.iter_mut() {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        let anchoring = c.anchoring;
        let dp = b.dp - a.dp;
        for p in c.points[..c.len].iter_mut() {
            let (ca, cb) = anchoring.anchors(p, &a, &b, arms);
            let s = c.normal.dot(dp + cb - ca) + p.adjusted_separation;
            let vn = row_velocity(&a, &b, c.normal, &p.normal_row, c.spin);
            if s > 0.0 || vn >= 0.0 {
                continue;
            }
            let dl = -p.normal_mass * vn;
            p.normal_impulse += dl;
            p.max_normal_impulse = p.max_normal_impulse.max(p.normal_impulse);
            apply_normal(&mut a, &mut b, c.normal, &p.normal_row, dl, c.spin);
        }
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}
