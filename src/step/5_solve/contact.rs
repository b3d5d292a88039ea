//! Contact constraints, one per manifold: a soft non-penetration row per point, then a
//! two-row friction disc per point. Plain functions over the solver-body and constraint
//! slices; each constraint loads its two bodies once and stores them once.

use bevy::prelude::*;

use super::softness::Softness;
use crate::collider::Shape;
use crate::step::narrow_phase::{MAX_POINTS, Manifold};
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

/// One contact point of a [`ContactConstraint`].
#[derive(Clone, Copy, Debug, Default)]
pub struct ConstraintPoint {
    /// Anchors from each body's centre to the contact point, world frame, start of step.
    pub ra: Vec3,
    pub rb: Vec3,
    /// Separation at the start of the step minus n·(rb − ra), so that the current
    /// separation is this plus n·(cb − ca) for the moved anchor points ca, cb.
    pub adjusted_separation: f32,
    pub normal_mass: f32,
    /// One mass for both tangent rows; see [`isotropic_tangent_mass`].
    pub tangent_mass: f32,
    pub normal_impulse: f32,
    /// Friction impulse along (tangent1, tangent2).
    pub tangent_impulse: Vec2,
    /// Largest normal impulse this step; restitution only acts on points that pushed.
    pub max_normal_impulse: f32,
    /// Normal relative velocity before the point first pushed (for restitution).
    pub relative_velocity: f32,
}

/// The contact of one manifold prepared for the solver.
#[derive(Clone, Copy, Debug)]
pub struct ContactConstraint {
    /// Body indices, or [`STATIC`].
    pub a: u32,
    pub b: u32,
    /// The manifold the results go back to.
    pub manifold: u32,
    pub normal: Vec3,
    pub tangent1: Vec3,
    pub tangent2: Vec3,
    /// Whether each anchor turns with its body when measuring separation. A sphere's
    /// contact point stays under its centre as it rolls, so its anchor does not turn.
    pub turn_a: bool,
    pub turn_b: bool,
    /// Whether each body can turn here (a dynamic body with rotation, or a spinning
    /// kinematic one). A static body or one with `LockRotation` runs no angular terms.
    pub spin: [bool; 2],
    pub friction: f32,
    pub restitution: f32,
    pub softness: Softness,
    pub points: [ConstraintPoint; MAX_POINTS],
    pub len: usize,
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

/// Whether a body has angular terms in a contact: it turns now or impulses can turn it.
fn spins(b: &SolverBody) -> bool {
    b.w != Vec3::ZERO || b.inv_inertia != Mat3::ZERO
}

fn effective_mass(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, dir: Vec3) -> f32 {
    let angular = |s: &SolverBody, r: Vec3| {
        let c = r.cross(dir);
        if spins(s) {
            c.dot(s.inv_inertia * c)
        } else {
            0.0
        }
    };
    let k = a.inv_mass + b.inv_mass + angular(a, ra) + angular(b, rb);
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// The friction rows' mass: the harmonic mean of the two tangent directions' effective
/// masses, the same in every direction. With a separate mass per row, an off-centre point
/// (a box corner) is heavier along one tangent than the other, the friction impulse is
/// then not opposite the slip, and a sliding box's point frictions fan out so their sum
/// falls short of μN (measured: 0.4% short, 1.3% on the acceleration of a box sliding
/// down a 0.25 rad ramp at μ = 0.2). A single mass keeps friction opposite the slip in
/// every direction, which is also what makes the cone round.
fn isotropic_tangent_mass(
    a: &SolverBody,
    b: &SolverBody,
    ra: Vec3,
    rb: Vec3,
    t1: Vec3,
    t2: Vec3,
) -> f32 {
    let k = |t: Vec3| {
        let m = effective_mass(a, b, ra, rb, t);
        if m > 0.0 { 1.0 / m } else { 0.0 }
    };
    let sum = k(t1) + k(t2);
    if sum > 0.0 { 2.0 / sum } else { 0.0 }
}

/// Velocity of b's anchor relative to a's; the angular parts only for bodies that spin.
#[inline]
fn relative_velocity(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, spin: [bool; 2]) -> Vec3 {
    let mut v = b.v - a.v;
    if spin[0] {
        v -= a.w.cross(ra);
    }
    if spin[1] {
        v += b.w.cross(rb);
    }
    v
}

/// Impulse p on b at rb, −p on a at ra; the angular parts only for bodies that spin.
#[inline]
fn apply(a: &mut SolverBody, b: &mut SolverBody, ra: Vec3, rb: Vec3, p: Vec3, spin: [bool; 2]) {
    a.v -= a.inv_mass * p;
    b.v += b.inv_mass * p;
    if spin[0] {
        a.w -= a.inv_inertia * ra.cross(p);
    }
    if spin[1] {
        b.w += b.inv_inertia * rb.cross(p);
    }
}

/// Contact stiffness rule. A soft contact is a spring-damper tuned to the pair's
/// effective mass m_eff — about the lighter body's mass. Under a load much heavier than
/// that (a heavy box on a light one, or a light box carrying a stack) it sinks by
/// load/(m_eff·ω²) and, worse, the heavy load rides an under-damped spring (damping ratio
/// ζ·√(m_eff/M)) and bounces. So both follow the mass the contact carries, M: the larger
/// of the heavier body's mass and the load last step's impulses show. With r = M/m_eff,
/// the frequency rises by √r (capped at `max_hertz`, a quarter of the substep rate, where
/// the soft step stays smooth) and the damping ratio by √r, which keeps the load's own
/// damping ratio at ζ. A contact with something that cannot move starts twice as stiff.
/// Returns the softness and r.
pub fn contact_softness(
    p: &ContactParams,
    inv_mass_a: f32,
    inv_mass_b: f32,
    load_impulse: f32,
) -> (Softness, f32) {
    let (lo, hi) = (inv_mass_a.min(inv_mass_b), inv_mass_a.max(inv_mass_b));
    if hi == 0.0 {
        return (Softness::new(0.0, 0.0, p.h), 1.0);
    }
    let light = 1.0 / hi;
    let heavy = if lo > 0.0 { 1.0 / lo } else { light };
    let carried = if p.gravity > 0.0 {
        load_impulse / (p.gravity * p.h)
    } else {
        0.0
    };
    let r = (heavy.max(carried) / light).max(1.0);
    let base = if lo == 0.0 { 2.0 * p.hertz } else { p.hertz };
    (
        Softness::new(
            (base * r.sqrt()).min(p.max_hertz),
            p.damping_ratio * r.sqrt(),
            p.h,
        ),
        r,
    )
}

/// The knobs of [`prepare_constraints`]: stiffness, substep, and whether friction runs.
#[derive(Clone, Copy, Debug)]
pub struct ContactParams {
    /// With friction off every constraint gets μ = 0 and its friction rows are skipped.
    pub friction: bool,
    pub hertz: f32,
    pub max_hertz: f32,
    /// |gravity|, to read a contact's load from its impulses.
    pub gravity: f32,
    pub damping_ratio: f32,
    /// Substep, s.
    pub h: f32,
}

/// Builds the constraint of every manifold. Returns the largest load ratio r of any
/// contact (see [`contact_softness`]), which sets how many iterations the step needs.
pub fn prepare_constraints(
    manifolds: &[Manifold],
    colliders: &[ColliderEntry],
    states: &[BodyState],
    bodies: &[SolverBody],
    stiffness: ContactParams,
    out: &mut Vec<ContactConstraint>,
) -> f32 {
    out.clear();
    let mut max_ratio = 1.0f32;
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
        let spin = [spins(&sa), spins(&sb)];
        let load: f32 = m.points().iter().map(|p| p.normal_impulse).sum();
        let (softness, r) = contact_softness(&stiffness, sa.inv_mass, sb.inv_mass, load);
        max_ratio = max_ratio.max(r);
        let mut c = ContactConstraint {
            a: ca.body,
            b: cb.body,
            manifold: mi as u32,
            normal: m.normal,
            tangent1: t1,
            tangent2: t2,
            turn_a: spin[0] && !matches!(ca.shape, Shape::Sphere { .. }),
            turn_b: spin[1] && !matches!(cb.shape, Shape::Sphere { .. }),
            spin,
            friction: if stiffness.friction { m.friction } else { 0.0 },
            restitution: m.restitution,
            softness,
            points: [ConstraintPoint::default(); MAX_POINTS],
            len: m.len,
        };
        for (cp, p) in c.points.iter_mut().zip(m.points()) {
            let (ra, rb) = (p.point - centre(ca), p.point - centre(cb));
            *cp = ConstraintPoint {
                ra,
                rb,
                adjusted_separation: p.separation - m.normal.dot(rb - ra),
                normal_mass: effective_mass(&sa, &sb, ra, rb, m.normal),
                tangent_mass: isotropic_tangent_mass(&sa, &sb, ra, rb, t1, t2),
                normal_impulse: p.normal_impulse,
                tangent_impulse: Vec2::new(p.tangent_impulse.dot(t1), p.tangent_impulse.dot(t2)),
                max_normal_impulse: 0.0,
                relative_velocity: relative_velocity(&sa, &sb, ra, rb, spin).dot(m.normal),
            };
        }
        out.push(c);
    }
    max_ratio
}

/// Applies last step's accumulated impulses (already in the constraints).
pub fn warm_start(bodies: &mut [SolverBody], constraints: &[ContactConstraint]) {
    for c in constraints {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        for p in &c.points[..c.len] {
            let t = c.tangent1 * p.tangent_impulse.x + c.tangent2 * p.tangent_impulse.y;
            apply(
                &mut a,
                &mut b,
                p.ra,
                p.rb,
                c.normal * p.normal_impulse + t,
                c.spin,
            );
        }
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}

/// One Gauss–Seidel pass: for each manifold, the normal rows of all its points (soft with
/// bias, or rigid when relaxing), then the friction disc of each point clamped to μ·λn
/// with the updated normal impulses. Accumulated impulses are clamped, never increments.
/// Speculative points (s > 0) may close their gap, not more. Impulses act at the
/// start-of-step anchors; the separation follows the anchors as the bodies move and turn.
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
        let dp = b.dp - a.dp;
        for p in c.points[..c.len].iter_mut() {
            let ca = if c.turn_a { a.dq * p.ra } else { p.ra };
            let cb = if c.turn_b { b.dq * p.rb } else { p.rb };
            let s = c.normal.dot(dp + cb - ca) + p.adjusted_separation;
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
            let vn = relative_velocity(&a, &b, p.ra, p.rb, c.spin).dot(c.normal);
            let lambda =
                -p.normal_mass * mass_scale * (vn + bias) - impulse_scale * p.normal_impulse;
            let new = (p.normal_impulse + lambda).max(0.0);
            if p.normal_impulse == 0.0 && new > 0.0 {
                // First push on this point: the approach speed that restitution reverses.
                p.relative_velocity = p.relative_velocity.min(vn);
            }
            let dl = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal_impulse = p.max_normal_impulse.max(new);
            apply(&mut a, &mut b, p.ra, p.rb, c.normal * dl, c.spin);
        }
        // Friction, skipped for frictionless pairs (and when the effect is off).
        for p in c.points[..c.len].iter_mut().filter(|_| c.friction > 0.0) {
            // Both tangent rows from the same velocity, then clamp to the disc: a round cone.
            let vr = relative_velocity(&a, &b, p.ra, p.rb, c.spin);
            let vt = Vec2::new(vr.dot(c.tangent1), vr.dot(c.tangent2));
            let old = p.tangent_impulse;
            let new = (old - p.tangent_mass * vt).clamp_length_max(c.friction * p.normal_impulse);
            p.tangent_impulse = new;
            let d = new - old;
            apply(
                &mut a,
                &mut b,
                p.ra,
                p.rb,
                c.tangent1 * d.x + c.tangent2 * d.y,
                c.spin,
            );
        }
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
    for c in constraints.iter_mut().filter(|c| c.restitution > 0.0) {
        let (mut a, mut b) = (body(bodies, c.a), body(bodies, c.b));
        for p in c.points[..c.len].iter_mut() {
            if p.relative_velocity > -threshold || p.max_normal_impulse == 0.0 {
                continue;
            }
            let vn = relative_velocity(&a, &b, p.ra, p.rb, c.spin).dot(c.normal);
            let lambda = -p.normal_mass * (vn + c.restitution * p.relative_velocity);
            let new = (p.normal_impulse + lambda).max(0.0);
            let dl = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal_impulse = p.max_normal_impulse.max(new);
            apply(&mut a, &mut b, p.ra, p.rb, c.normal * dl, c.spin);
        }
        store(bodies, c.a, a);
        store(bodies, c.b, b);
    }
}
