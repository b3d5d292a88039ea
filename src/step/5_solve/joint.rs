//! Joints in the soft step, beside the contacts and like them (Box2D v3's recipe): each
//! substep their accumulated impulses are applied again (warm start), then each pass
//! solves their rows with a soft bias toward the position error, and the relax pass
//! solves them rigidly without it. The anchors start at the step's start and turn with
//! their bodies (`dq`); errors are measured from the bodies' motion this step (`dp`,
//! `dq`), so they stay precise far from the origin.
//!
//! Rows, per kind: the point (a 3×3 block), the turns (a 3×3 block, or the two across a
//! hinge's axis as a 2×2 block), the offsets across a slider's axis (2×2), and one-row
//! motors, limits, springs and distances. Limits are speculative, like contacts: a limit
//! not yet reached may be approached as far as it is, no farther, in one substep.

use bevy::prelude::*;

use crate::math::Softness;
use crate::world::{JointConstraint, JointRows, SolverBody, body, store};

/// The joint's geometry now: anchors from the centres of mass, the offset from anchor A
/// to anchor B (the point error), and the axis, all world frame.
pub(super) struct Now {
    pub ra: Vec3,
    pub rb: Vec3,
    pub d: Vec3,
    pub axis: Vec3,
}

pub(super) fn now(j: &JointConstraint, a: &SolverBody, b: &SolverBody) -> Now {
    let (ra, rb) = (a.dq * j.ra, b.dq * j.rb);
    Now {
        ra,
        rb,
        d: j.offset + (b.dp - a.dp) + rb - ra,
        axis: a.dq * j.axis,
    }
}

/// `r × x` as a matrix.
fn skew(r: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, r.z, -r.y),
        Vec3::new(-r.z, 0.0, r.x),
        Vec3::new(r.y, -r.x, 0.0),
    )
}

/// Linear impulse `p` on B at arm `arm_b`, its opposite on A at `arm_a`.
fn apply_linear(a: &mut SolverBody, b: &mut SolverBody, arm_a: Vec3, arm_b: Vec3, p: Vec3) {
    a.v -= a.inv_mass * p;
    a.w -= a.inv_inertia * arm_a.cross(p);
    b.v += b.inv_mass * p;
    b.w += b.inv_inertia * arm_b.cross(p);
}

/// Angular impulse `l` on B, its opposite on A.
fn apply_angular(a: &mut SolverBody, b: &mut SolverBody, l: Vec3) {
    a.w -= a.inv_inertia * l;
    b.w += b.inv_inertia * l;
}

/// Velocity of B's point at `arm_b` relative to A's at `arm_a`.
fn point_velocity(a: &SolverBody, b: &SolverBody, arm_a: Vec3, arm_b: Vec3) -> Vec3 {
    b.v + b.w.cross(arm_b) - a.v - a.w.cross(arm_a)
}

/// The inverse effective mass of a linear row along unit `n`.
pub(super) fn linear_k(a: &SolverBody, b: &SolverBody, arm_a: Vec3, arm_b: Vec3, n: Vec3) -> f32 {
    let (ca, cb) = (arm_a.cross(n), arm_b.cross(n));
    a.inv_mass + b.inv_mass + ca.dot(a.inv_inertia * ca) + cb.dot(b.inv_inertia * cb)
}

/// The inverse of `k`, or zero when the row cannot move (both sides immovable).
fn inv(k: f32) -> f32 {
    if k > 1e-12 { 1.0 / k } else { 0.0 }
}

/// B's rotation error relative to A as a rotation vector, rad (zero at rest).
pub(super) fn rotation_error(j: &JointConstraint, a: &SolverBody, b: &SolverBody) -> (Quat, Vec3) {
    let mut q = (b.dq * j.rest * a.dq.inverse()).normalize();
    if q.w < 0.0 {
        q = -q;
    }
    (q, q.to_scaled_axis())
}

/// The angle of `q`'s turn about unit `axis`, rad, in (−π, π].
fn twist_angle(q: Quat, axis: Vec3) -> f32 {
    2.0 * Vec3::new(q.x, q.y, q.z).dot(axis).atan2(q.w)
}

/// A bilateral row's bias, mass scale and impulse scale for error `c`.
fn bilateral(c: f32, soft: &Softness, use_bias: bool) -> (f32, f32, f32) {
    if use_bias {
        (soft.bias_rate * c, soft.mass_scale, soft.impulse_scale)
    } else {
        (0.0, 1.0, 0.0)
    }
}

/// A one-sided row's (a limit's): `c` ≥ 0 is the room left, approached at most by `c/h`
/// this substep; below zero it is pushed out softly.
fn one_sided(c: f32, inv_h: f32, soft: &Softness, use_bias: bool) -> (f32, f32, f32) {
    if c > 0.0 {
        (c * inv_h, 1.0, 0.0)
    } else {
        bilateral(c, soft, use_bias)
    }
}

/// Warm start: last substep's impulses applied again.
pub fn warm_start_joints(bodies: &mut [SolverBody], joints: &[JointConstraint]) {
    for j in joints {
        let (mut a, mut b) = (body(bodies, j.a), body(bodies, j.b));
        let f = now(j, &a, &b);
        let axial = j.axial[0] + j.axial[1] - j.axial[2];
        match j.rows {
            JointRows::Fixed | JointRows::Spherical | JointRows::Revolute => {
                apply_linear(&mut a, &mut b, f.ra, f.rb, j.linear);
            }
            JointRows::Prismatic => {
                let p = j.linear + f.axis * axial;
                apply_linear(&mut a, &mut b, f.ra + f.d, f.rb, p);
            }
            JointRows::Distance => {
                let n = f.d.normalize_or(f.axis);
                apply_linear(&mut a, &mut b, f.ra, f.rb, n * axial);
            }
        }
        let mut l = j.angular;
        match j.rows {
            JointRows::Revolute => l += f.axis * axial,
            JointRows::Spherical => l += spherical_torque(j, &b, f.axis),
            _ => {}
        }
        apply_angular(&mut a, &mut b, l);
        store(bodies, j.a, a);
        store(bodies, j.b, b);
    }
}

/// One pass over the joints: with `use_bias`, toward closing their errors (soft);
/// without, rigidly on velocities (relax). The equality rows only with `equalities`:
/// the step solves them together (`joint_direct.rs`); one by one they are its reference.
pub fn solve_joints(
    bodies: &mut [SolverBody],
    joints: &mut [JointConstraint],
    h: f32,
    use_bias: bool,
    equalities: bool,
) {
    let inv_h = 1.0 / h;
    for j in joints.iter_mut() {
        let (mut a, mut b) = (body(bodies, j.a), body(bodies, j.b));
        let f = now(j, &a, &b);
        let softness = j.softness;
        let soft = &softness;
        let eq = equalities;
        match j.rows {
            JointRows::Fixed if eq => {
                solve_turns(j, &mut a, &mut b, soft, use_bias);
                solve_point(j, &mut a, &mut b, &f, soft, use_bias);
            }
            JointRows::Fixed => continue,
            JointRows::Spherical => {
                solve_cone_twist(j, &mut a, &mut b, &f, h, soft, use_bias);
                if eq {
                    solve_point(j, &mut a, &mut b, &f, soft, use_bias);
                }
            }
            JointRows::Revolute => {
                solve_hinge_axis(j, &mut a, &mut b, &f, h, soft, use_bias);
                if eq {
                    solve_hinge_turns(j, &mut a, &mut b, &f, soft, use_bias);
                    solve_point(j, &mut a, &mut b, &f, soft, use_bias);
                }
            }
            JointRows::Prismatic => {
                solve_slide_axis(j, &mut a, &mut b, &f, h, soft, use_bias);
                if eq {
                    solve_turns(j, &mut a, &mut b, soft, use_bias);
                    solve_slide_across(j, &mut a, &mut b, &f, soft, use_bias);
                }
            }
            JointRows::Distance => {
                solve_distance(j, &mut a, &mut b, &f, inv_h, soft, use_bias, eq);
            }
        }
        store(bodies, j.a, a);
        store(bodies, j.b, b);
    }
}

/// The anchors together: a 3×3 block.
fn solve_point(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    soft: &Softness,
    use_bias: bool,
) {
    let k = Mat3::from_diagonal(Vec3::splat(a.inv_mass + b.inv_mass))
        - skew(f.ra) * a.inv_inertia * skew(f.ra)
        - skew(f.rb) * b.inv_inertia * skew(f.rb);
    if k.determinant().abs() <= 1e-18 {
        return;
    }
    let (bias_rate, mass_scale, impulse_scale) = bilateral(1.0, soft, use_bias);
    let cdot = point_velocity(a, b, f.ra, f.rb);
    let p = -mass_scale * (k.inverse() * (cdot + bias_rate * f.d)) - impulse_scale * j.linear;
    j.linear += p;
    apply_linear(a, b, f.ra, f.rb, p);
}

/// No relative turn: a 3×3 block on the rotation error.
fn solve_turns(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    soft: &Softness,
    use_bias: bool,
) {
    let k = a.inv_inertia + b.inv_inertia;
    if k.determinant().abs() <= 1e-18 {
        return;
    }
    let (_, e) = rotation_error(j, a, b);
    let (bias_rate, mass_scale, impulse_scale) = bilateral(1.0, soft, use_bias);
    let cdot = b.w - a.w;
    let l = -mass_scale * (k.inverse() * (cdot + bias_rate * e)) - impulse_scale * j.angular;
    j.angular += l;
    apply_angular(a, b, l);
}

/// Solves the 2×2 block `k` (symmetric: k11, k12, k22) for `rhs`; zero if singular.
fn solve2(k11: f32, k12: f32, k22: f32, rhs: Vec2) -> Vec2 {
    let det = k11 * k22 - k12 * k12;
    if det.abs() <= 1e-18 {
        return Vec2::ZERO;
    }
    Vec2::new(k22 * rhs.x - k12 * rhs.y, k11 * rhs.y - k12 * rhs.x) / det
}

/// A hinge: no turn across its axis (the two rows as a 2×2 block).
fn solve_hinge_turns(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    soft: &Softness,
    use_bias: bool,
) {
    let (t1, t2) = f.axis.any_orthonormal_pair();
    let k = a.inv_inertia + b.inv_inertia;
    let (kt1, kt2) = (k * t1, k * t2);
    let (_, e) = rotation_error(j, a, b);
    let (bias_rate, mass_scale, impulse_scale) = bilateral(1.0, soft, use_bias);
    let w = b.w - a.w;
    let rhs = Vec2::new(t1.dot(w + bias_rate * e), t2.dot(w + bias_rate * e));
    let old = Vec2::new(t1.dot(j.angular), t2.dot(j.angular));
    let x = solve2(t1.dot(kt1), t1.dot(kt2), t2.dot(kt2), rhs);
    let l = -mass_scale * x - impulse_scale * old;
    let new = old + l;
    j.angular = t1 * new.x + t2 * new.y;
    apply_angular(a, b, t1 * l.x + t2 * l.y);
}

/// One axis's motor and limits (Gauss–Seidel rows): `value` the angle (rad) or offset
/// (m) now, `mass` the axis's effective mass, `speed` its relative speed and `push` an
/// impulse along it. Motor in `axial[0]`, lower and upper limits in `axial[1]`, `[2]`.
#[allow(clippy::too_many_arguments)]
fn solve_axial(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    (value, mass, h): (f32, f32, f32),
    soft: &Softness,
    use_bias: bool,
    speed: impl Fn(&SolverBody, &SolverBody) -> f32,
    mut push: impl FnMut(&mut SolverBody, &mut SolverBody, f32),
) {
    if let Some((target, max_force)) = j.motor {
        let cdot = speed(a, b) - target;
        let max = max_force * h;
        let old = j.axial[0];
        j.axial[0] = (old - mass * cdot).clamp(-max, max);
        push(a, b, j.axial[0] - old);
    }
    if let Some((lo, hi)) = j.limits {
        for (slot, room, sign) in [(1, value - lo, 1.0), (2, hi - value, -1.0)] {
            let (bias, mass_scale, impulse_scale) = one_sided(room, 1.0 / h, soft, use_bias);
            let cdot = sign * speed(a, b);
            let old = j.axial[slot];
            let l = -mass * mass_scale * (cdot + bias) - impulse_scale * old;
            j.axial[slot] = (old + l).max(0.0);
            push(a, b, sign * (j.axial[slot] - old));
        }
    }
}

/// A hinge's motor and angle limits, about its axis.
fn solve_hinge_axis(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    h: f32,
    soft: &Softness,
    use_bias: bool,
) {
    if j.motor.is_none() && j.limits.is_none() {
        return;
    }
    solve_turn_axis(j, a, b, (f.axis, f.axis), h, soft, use_bias);
}

/// Motor and limits of the turn about `axis` (a hinge's, a ball joint's twist), its rows
/// along `row` (the axis itself for a hinge; for a twist, midway between the two bodies'
/// axes, where a swing does not move the twist).
fn solve_turn_axis(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    (axis, row): (Vec3, Vec3),
    h: f32,
    soft: &Softness,
    use_bias: bool,
) {
    let (q, _) = rotation_error(j, a, b);
    let angle = twist_angle(q, axis);
    let axis = row;
    let mass = inv(axis.dot((a.inv_inertia + b.inv_inertia) * axis));
    let speed = |a: &SolverBody, b: &SolverBody| axis.dot(b.w - a.w);
    let push = |a: &mut SolverBody, b: &mut SolverBody, l: f32| apply_angular(a, b, axis * l);
    solve_axial(j, a, b, (angle, mass, h), soft, use_bias, speed, push);
}

/// A ball joint's cone (B's axis within `cone` of A's) and twist limits (about A's axis).
fn solve_cone_twist(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    h: f32,
    soft: &Softness,
    use_bias: bool,
) {
    if let Some(max) = j.cone {
        let k = a.inv_inertia + b.inv_inertia;
        let axis_b = b.dq * j.axis_b;
        let (lean, n) = cone_lean(f.axis, axis_b);
        let mass = inv(n.dot(k * n));
        // Leaning further turns B about +n: the row pushes back about −n.
        let (bias, mass_scale, impulse_scale) = one_sided(max - lean, 1.0 / h, soft, use_bias);
        let cdot = -n.dot(b.w - a.w);
        let old = j.axial[0];
        let l = -mass * mass_scale * (cdot + bias) - impulse_scale * old;
        j.axial[0] = (old + l).max(0.0);
        apply_angular(a, b, n * -(j.axial[0] - old));
    }
    if j.limits.is_some() {
        let mid = (f.axis + b.dq * j.axis_b).normalize_or(f.axis);
        solve_turn_axis(j, a, b, (f.axis, mid), h, soft, use_bias);
    }
}

/// How far unit `b` leans from unit `a`, rad, and the unit axis it leans about (any
/// perpendicular of `a` when they are aligned).
fn cone_lean(a: Vec3, b: Vec3) -> (f32, Vec3) {
    let cross = a.cross(b);
    let sin = cross.length();
    let lean = sin.atan2(a.dot(b));
    let n = if sin > 1e-6 {
        cross / sin
    } else {
        a.any_orthonormal_vector()
    };
    (lean, n)
}

/// A slider's motor and offset limits, along its axis.
fn solve_slide_axis(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    h: f32,
    soft: &Softness,
    use_bias: bool,
) {
    if j.motor.is_none() && j.limits.is_none() {
        return;
    }
    let (axis, arm_a, rb) = (f.axis, f.ra + f.d, f.rb);
    let mass = inv(linear_k(a, b, arm_a, rb, axis));
    let speed = |a: &SolverBody, b: &SolverBody| axis.dot(point_velocity(a, b, arm_a, rb));
    let push = |a: &mut SolverBody, b: &mut SolverBody, l: f32| {
        apply_linear(a, b, arm_a, rb, axis * l);
    };
    let offset = axis.dot(f.d);
    solve_axial(j, a, b, (offset, mass, h), soft, use_bias, speed, push);
}

/// A slider: no offset across its axis (a 2×2 block). A's arm reaches B's anchor.
fn solve_slide_across(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    soft: &Softness,
    use_bias: bool,
) {
    let (t1, t2) = f.axis.any_orthonormal_pair();
    let arm_a = f.ra + f.d;
    let row = |t: Vec3| (arm_a.cross(t), f.rb.cross(t));
    let ((a1, b1), (a2, b2)) = (row(t1), row(t2));
    let linear = a.inv_mass + b.inv_mass;
    let k11 = linear + a1.dot(a.inv_inertia * a1) + b1.dot(b.inv_inertia * b1);
    let k22 = linear + a2.dot(a.inv_inertia * a2) + b2.dot(b.inv_inertia * b2);
    let k12 = a1.dot(a.inv_inertia * a2) + b1.dot(b.inv_inertia * b2);
    let (bias_rate, mass_scale, impulse_scale) = bilateral(1.0, soft, use_bias);
    let v = point_velocity(a, b, arm_a, f.rb) + bias_rate * f.d;
    let old = Vec2::new(t1.dot(j.linear), t2.dot(j.linear));
    let x = solve2(k11, k12, k22, Vec2::new(t1.dot(v), t2.dot(v)));
    let l = -mass_scale * x - impulse_scale * old;
    let new = old + l;
    j.linear = t1 * new.x + t2 * new.y;
    apply_linear(a, b, arm_a, f.rb, t1 * l.x + t2 * l.y);
}

/// The distance between the anchors: rigid (only with `rigid_too`), or a spring and
/// limits.
#[allow(clippy::too_many_arguments)]
fn solve_distance(
    j: &mut JointConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    f: &Now,
    inv_h: f32,
    soft: &Softness,
    use_bias: bool,
    rigid_too: bool,
) {
    let length = f.d.length();
    let n = if length > 1e-6 { f.d / length } else { f.axis };
    let mass = inv(linear_k(a, b, f.ra, f.rb, n));
    let speed = |a: &SolverBody, b: &SolverBody| n.dot(point_velocity(a, b, f.ra, f.rb));
    let (lo, hi) = j.limits.unwrap_or((0.0, f32::INFINITY));
    if lo >= hi {
        if !rigid_too {
            return;
        }
        let (bias, mass_scale, impulse_scale) = bilateral(length - lo, soft, use_bias);
        let l = -mass * mass_scale * (speed(a, b) + bias) - impulse_scale * j.axial[0];
        j.axial[0] += l;
        apply_linear(a, b, f.ra, f.rb, n * l);
        return;
    }
    if let Some((rest, hertz, zeta)) = j.spring {
        // The spring acts in the relax pass too: it is the joint's physics, not a
        // correction.
        let s = Softness::new(hertz, zeta, 1.0 / inv_h);
        let bias = s.bias_rate * (length - rest);
        let l = -mass * s.mass_scale * (speed(a, b) + bias) - s.impulse_scale * j.axial[0];
        j.axial[0] += l;
        apply_linear(a, b, f.ra, f.rb, n * l);
    }
    for (slot, room, sign, present) in [
        (1, length - lo, 1.0, lo > 0.0),
        (2, hi - length, -1.0, hi.is_finite()),
    ] {
        if !present {
            continue;
        }
        let (bias, mass_scale, impulse_scale) = one_sided(room, inv_h, soft, use_bias);
        let old = j.axial[slot];
        let l = -mass * mass_scale * (sign * speed(a, b) + bias) - impulse_scale * old;
        j.axial[slot] = (old + l).max(0.0);
        apply_linear(a, b, f.ra, f.rb, n * (sign * (j.axial[slot] - old)));
    }
}

/// A ball joint's accumulated cone and twist impulses as one angular impulse on B.
/// The twist's rows lie midway between the two axes (see [`solve_turn_axis`]).
pub(super) fn spherical_torque(j: &JointConstraint, b: &SolverBody, axis: Vec3) -> Vec3 {
    let axis_b = b.dq * j.axis_b;
    let twist = (axis + axis_b).normalize_or(axis) * (j.axial[1] - j.axial[2]);
    match j.cone {
        Some(_) => twist - cone_lean(axis, axis_b).1 * j.axial[0],
        None => twist,
    }
}
