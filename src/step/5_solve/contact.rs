//! Contact constraints: one row per point along the normal plus a two-row friction disc.
//! Plain functions over the solver-body and constraint slices.

use bevy::prelude::*;

use super::softness::Softness;
use crate::collider::Shape;
use crate::step::narrow_phase::Manifold;
use crate::world::{BodyState, ColliderEntry, STATIC, SolverBody};

/// The solver body every static collider shares: never moves, infinite mass.
pub const STATIC_BODY: SolverBody = SolverBody {
    v: Vec3::ZERO,
    w: Vec3::ZERO,
    dp: Vec3::ZERO,
    dq: Quat::IDENTITY,
    inv_mass: 0.0,
    inv_inertia: Mat3::ZERO,
};

/// One contact point prepared for the solver.
#[derive(Clone, Copy, Debug)]
pub struct ContactConstraint {
    /// Body indices, or [`STATIC`].
    pub a: u32,
    pub b: u32,
    /// Where the result goes: manifold index and point index.
    pub manifold: u32,
    pub point: u32,
    pub normal: Vec3,
    pub tangent1: Vec3,
    pub tangent2: Vec3,
    /// Anchors from each body's centre to the contact point, world frame, start of step.
    pub ra: Vec3,
    pub rb: Vec3,
    /// Whether each anchor turns with its body when measuring separation. A sphere's
    /// contact point stays under its centre as it rolls, so its anchor does not turn.
    pub turn_a: bool,
    pub turn_b: bool,
    /// Separation at the start of the step minus n·(rb − ra), so that the current
    /// separation is this plus n·(cb − ca) for the moved anchor points ca, cb.
    pub adjusted_separation: f32,
    pub normal_mass: f32,
    pub tangent_mass: Vec2,
    pub normal_impulse: f32,
    /// Friction impulse along (tangent1, tangent2).
    pub tangent_impulse: Vec2,
    /// Largest normal impulse seen this step; restitution only acts on points that pushed.
    pub max_normal_impulse: f32,
    pub friction: f32,
    pub restitution: f32,
    /// Normal relative velocity just before the point first pushed (for restitution).
    pub relative_velocity: f32,
    pub softness: Softness,
}

pub(crate) fn body(bodies: &[SolverBody], i: u32) -> SolverBody {
    if i == STATIC {
        STATIC_BODY
    } else {
        bodies[i as usize]
    }
}

fn store(bodies: &mut [SolverBody], i: u32, b: SolverBody) {
    if i != STATIC {
        bodies[i as usize] = b;
    }
}

fn effective_mass(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, dir: Vec3) -> f32 {
    let (ca, cb) = (ra.cross(dir), rb.cross(dir));
    let k = a.inv_mass + b.inv_mass + ca.dot(a.inv_inertia * ca) + cb.dot(b.inv_inertia * cb);
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

fn relative_velocity(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3) -> Vec3 {
    (b.v + b.w.cross(rb)) - (a.v + a.w.cross(ra))
}

fn apply(a: &mut SolverBody, b: &mut SolverBody, ra: Vec3, rb: Vec3, p: Vec3) {
    a.v -= a.inv_mass * p;
    a.w -= a.inv_inertia * ra.cross(p);
    b.v += b.inv_mass * p;
    b.w += b.inv_inertia * rb.cross(p);
}

/// Builds the constraint of every manifold point. `soft` and `soft_static` are the
/// softness between two moving bodies and against a static or kinematic body.
pub fn prepare_constraints(
    manifolds: &[Manifold],
    colliders: &[ColliderEntry],
    states: &[BodyState],
    bodies: &[SolverBody],
    soft: Softness,
    soft_static: Softness,
    out: &mut Vec<ContactConstraint>,
) {
    out.clear();
    for (mi, m) in manifolds.iter().enumerate() {
        let (ca, cb) = (&colliders[m.a as usize], &colliders[m.b as usize]);
        let centre = |c: &ColliderEntry| {
            if c.body == STATIC {
                c.pos
            } else {
                states[c.body as usize].x0
            }
        };
        let (sa, sb) = (body(bodies, ca.body), body(bodies, cb.body));
        let (t1, t2) = m.normal.any_orthonormal_pair();
        let against_static = sa.inv_mass == 0.0 || sb.inv_mass == 0.0;
        for (pi, p) in m.points().iter().enumerate() {
            let (ra, rb) = (p.point - centre(ca), p.point - centre(cb));
            let vrel = relative_velocity(&sa, &sb, ra, rb);
            out.push(ContactConstraint {
                a: ca.body,
                b: cb.body,
                manifold: mi as u32,
                point: pi as u32,
                normal: m.normal,
                tangent1: t1,
                tangent2: t2,
                ra,
                rb,
                turn_a: !matches!(ca.shape, Shape::Sphere { .. }),
                turn_b: !matches!(cb.shape, Shape::Sphere { .. }),
                adjusted_separation: p.separation - m.normal.dot(rb - ra),
                normal_mass: effective_mass(&sa, &sb, ra, rb, m.normal),
                tangent_mass: Vec2::new(
                    effective_mass(&sa, &sb, ra, rb, t1),
                    effective_mass(&sa, &sb, ra, rb, t2),
                ),
                normal_impulse: p.normal_impulse,
                tangent_impulse: Vec2::new(p.tangent_impulse.dot(t1), p.tangent_impulse.dot(t2)),
                max_normal_impulse: 0.0,
                friction: m.friction,
                restitution: m.restitution,
                relative_velocity: vrel.dot(m.normal),
                softness: if against_static { soft_static } else { soft },
            });
        }
    }
}

/// Applies last step's accumulated impulses (already in the constraints).
pub fn warm_start(bodies: &mut [SolverBody], constraints: &[ContactConstraint]) {
    for c in constraints {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        let (ra, rb) = (c.ra, c.rb);
        let p = c.normal * c.normal_impulse
            + c.tangent1 * c.tangent_impulse.x
            + c.tangent2 * c.tangent_impulse.y;
        apply(&mut a, &mut b, ra, rb, p);
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}

/// One Gauss–Seidel pass over the contacts: normal rows (soft with bias, or rigid when
/// relaxing), then the friction disc clamped to μ·λn. Accumulated impulses are clamped,
/// never the increments. Speculative points (s > 0) may close their gap, not more.
pub fn solve(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    h: f32,
    max_push_out: f32,
    use_bias: bool,
) {
    let inv_h = 1.0 / h;
    for c in constraints.iter_mut() {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        // Impulses act at the start-of-step anchors (fixed Jacobian for the whole step);
        // the separation follows the anchors as the bodies move and turn.
        let (ra, rb) = (c.ra, c.rb);
        let ca = if c.turn_a { a.dq * ra } else { ra };
        let cb = if c.turn_b { b.dq * rb } else { rb };
        let d = (b.dp - a.dp) + (cb - ca);
        let s = c.normal.dot(d) + c.adjusted_separation;
        let (bias, mass_scale, impulse_scale) = if s > 0.0 {
            (s * inv_h, 1.0, 0.0)
        } else if use_bias {
            let soft = c.softness;
            (
                (soft.bias_rate * s).max(-max_push_out),
                soft.mass_scale,
                soft.impulse_scale,
            )
        } else {
            (0.0, 1.0, 0.0)
        };
        let vn = relative_velocity(&a, &b, ra, rb).dot(c.normal);
        let lambda = -c.normal_mass * mass_scale * (vn + bias) - impulse_scale * c.normal_impulse;
        let new = (c.normal_impulse + lambda).max(0.0);
        if c.normal_impulse == 0.0 && new > 0.0 {
            // First push on this point: the approach speed that restitution reverses.
            c.relative_velocity = c.relative_velocity.min(vn);
        }
        let dl = new - c.normal_impulse;
        c.normal_impulse = new;
        c.max_normal_impulse = c.max_normal_impulse.max(new);
        apply(&mut a, &mut b, ra, rb, c.normal * dl);

        // Friction: both tangent rows from the same velocity, then clamp to the disc.
        let vr = relative_velocity(&a, &b, ra, rb);
        let vt = Vec2::new(vr.dot(c.tangent1), vr.dot(c.tangent2));
        let old = c.tangent_impulse;
        let limit = c.friction * c.normal_impulse;
        let new = (old - c.tangent_mass * vt).clamp_length_max(limit);
        c.tangent_impulse = new;
        let dt = new - old;
        apply(
            &mut a,
            &mut b,
            ra,
            rb,
            c.tangent1 * dt.x + c.tangent2 * dt.y,
        );
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}

/// Restitution: points that were approaching faster than `threshold` and pushed get
/// their normal velocity driven to −e times the approach speed.
pub fn apply_restitution(
    bodies: &mut [SolverBody],
    constraints: &mut [ContactConstraint],
    threshold: f32,
) {
    for c in constraints.iter_mut() {
        if c.restitution == 0.0 || c.relative_velocity > -threshold || c.max_normal_impulse == 0.0 {
            continue;
        }
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        let (ra, rb) = (c.ra, c.rb);
        let vn = relative_velocity(&a, &b, ra, rb).dot(c.normal);
        let lambda = -c.normal_mass * (vn + c.restitution * c.relative_velocity);
        let new = (c.normal_impulse + lambda).max(0.0);
        let dl = new - c.normal_impulse;
        c.normal_impulse = new;
        c.max_normal_impulse = c.max_normal_impulse.max(new);
        apply(&mut a, &mut b, ra, rb, c.normal * dl);
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}
