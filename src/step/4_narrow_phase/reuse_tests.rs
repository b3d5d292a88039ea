//! Manifold reuse against colliding afresh, the brute-force reference: on random box
//! pairs in resting contact, a pair that has not moved, or moved as one, keeps its
//! manifold to float precision; a small relative motion keeps one whose deepest point
//! and normal are within the drift bound of a fresh one; a motion past any limit
//! collides afresh.

use bevy::prelude::*;

use super::reuse::{REUSE_DRIFT, anchor, reuse};
use crate::collider::Shape;
use crate::rng::Rnd;
use crate::world::collide;
use crate::world::{ColliderEntry, Manifold};

/// The speculative margin of boxes this size (the default setting).
const MARGIN: f32 = 0.02;
/// Reach of this step (closing speeds times the step).
const REACH: f32 = 0.005;
const CUTOFF: f32 = MARGIN + REACH;

fn collider(entity: u32, shape: Shape, pos: Vec3, rot: Quat) -> ColliderEntry {
    let e = Entity::from_raw_u32(entity).unwrap();
    ColliderEntry::new(e, entity as u64, entity, shape, pos, rot)
}

fn cuboid(entity: u32, half_extents: Vec3, pos: Vec3, rot: Quat) -> ColliderEntry {
    collider(entity, Shape::Cuboid { half_extents }, pos, rot)
}

fn half_extents(c: &ColliderEntry) -> Vec3 {
    match c.shape {
        Shape::Cuboid { half_extents } => half_extents,
        _ => unreachable!(),
    }
}

/// The pair's drift tolerance d and largest turn θ (see `reuse`'s module docs).
fn limits(a: &ColliderEntry, b: &ColliderEntry) -> (f32, f32) {
    let (ha, hb) = (half_extents(a), half_extents(b));
    let d = (REUSE_DRIFT * 2.0 * ha.min_element().min(hb.min_element())).min(0.25 * MARGIN);
    (d, d / (2.0 * ha.length().max(hb.length())))
}

/// Box b resting on box a: random sizes, a random yaw and a tilt under a degree, the
/// lowest corner within 2 mm of a's top face, the whole pair at a random pose up to
/// `far` from the origin in each axis, m.
fn resting_pair(r: &mut Rnd, far: f32) -> (ColliderEntry, ColliderEntry) {
    let (ha, hb) = (r.vec(0.5, 1.0), r.vec(0.3, 0.8));
    let tilt = Quat::from_axis_angle(r.dir().with_y(0.0).normalize(), r.range(0.0, 0.017));
    let rot_b = tilt * Quat::from_rotation_y(r.range(0.0, std::f32::consts::TAU));
    let below = (0..8)
        .map(|k| {
            let corner = Vec3::new(
                if k & 1 == 0 { -hb.x } else { hb.x },
                if k & 2 == 0 { -hb.y } else { hb.y },
                if k & 4 == 0 { -hb.z } else { hb.z },
            );
            (rot_b * corner).y
        })
        .fold(f32::INFINITY, f32::min);
    let offset = Vec3::new(r.range(-0.2, 0.2), 0.0, r.range(-0.2, 0.2));
    let pos_b = offset + Vec3::Y * (ha.y - below + r.range(-0.002, 0.002));
    let (place, turn) = (r.vec(-far, far), r.rot());
    (
        cuboid(1, ha, place, turn),
        cuboid(2, hb, place + turn * pos_b, turn * rot_b),
    )
}

/// The pair's manifold found afresh, its points anchored.
fn found(a: &ColliderEntry, b: &ColliderEntry) -> Manifold {
    let mut m = collide(a, 0, b, 1, CUTOFF).expect("a resting pair touches");
    anchor(&mut m, a, b, CUTOFF);
    m
}

fn deepest(m: &Manifold) -> f32 {
    m.points()
        .iter()
        .map(|p| p.separation)
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn an_unmoved_pair_keeps_its_manifold() {
    let mut r = Rnd(7);
    for _ in 0..200 {
        let (a, b) = resting_pair(&mut r, 50.0);
        let m = found(&a, &b);
        let again = reuse(&m, (&a, 0), (&b, 1), MARGIN, CUTOFF).expect("unmoved: reused");
        assert!(again.normal.distance(m.normal) < 1e-6);
        // Float precision 85 m out.
        for (p, q) in again.points().iter().zip(m.points()) {
            assert!(p.point.distance(q.point) < 3e-5, "{} {}", p.point, q.point);
            assert!((p.separation - q.separation).abs() < 1e-5);
        }
    }
}

#[test]
fn a_pair_closing_along_its_normal_closes_every_point_by_as_much() {
    let mut r = Rnd(13);
    for _ in 0..200 {
        // Near the origin, where float precision is well under the drift tolerance
        // (18 µm or more for these boxes).
        let (a, b) = resting_pair(&mut r, 1.0);
        let m = found(&a, &b);
        let (d, _) = limits(&a, &b);
        let closer = ColliderEntry {
            pos: b.pos - m.normal * 0.5 * d,
            ..b.clone()
        };
        let moved = reuse(&m, (&a, 0), (&closer, 1), MARGIN, CUTOFF).expect("within the drift");
        for (p, q) in moved.points().iter().zip(m.points()) {
            assert!((p.separation - (q.separation - 0.5 * d)).abs() < 0.05 * d);
            assert!(p.point.distance(q.point - m.normal * 0.25 * d) < 0.05 * d);
        }
    }
}

#[test]
fn a_pair_moved_as_one_keeps_its_manifold() {
    let mut r = Rnd(11);
    for _ in 0..200 {
        let (a, b) = resting_pair(&mut r, 10.0);
        let m = found(&a, &b);
        let (shift, turn) = (r.vec(-5.0, 5.0), r.rot());
        let carry = |c: &ColliderEntry| ColliderEntry {
            pos: shift + turn * c.pos,
            rot: turn * c.rot,
            ..c.clone()
        };
        let (a2, b2) = (carry(&a), carry(&b));
        let moved =
            reuse(&m, (&a2, 0), (&b2, 1), MARGIN, CUTOFF).expect("no relative motion: reused");
        // The manifold carried by the same motion, to float precision 15 m out. (Not
        // compared with a fresh one: with b's face tilted under a degree from a's, the
        // clipping's choice of reference face may flip on a rounding difference.)
        assert!(moved.normal.dot(turn * m.normal) > 1.0 - 1e-6);
        for (p, q) in moved.points().iter().zip(m.points()) {
            assert!(p.point.distance(shift + turn * q.point) < 2e-4);
            assert!((p.separation - q.separation).abs() < 2e-5);
        }
    }
}

#[test]
fn a_small_relative_motion_stays_within_the_drift_bound() {
    let mut r = Rnd(23);
    let mut reused = 0;
    for _ in 0..400 {
        let (a, b) = resting_pair(&mut r, 10.0);
        let m = found(&a, &b);
        let (d, turn) = limits(&a, &b);
        // Up to half the drift by translation and half by turning about b's centre.
        let nudge = Quat::from_axis_angle(r.dir(), r.range(0.0, 0.5 * turn));
        let b2 = ColliderEntry {
            pos: b.pos + r.dir() * r.range(0.0, 0.5 * d),
            rot: nudge * b.rot,
            ..b.clone()
        };
        let Some(moved) = reuse(&m, (&a, 0), (&b2, 1), MARGIN, CUTOFF) else {
            continue;
        };
        reused += 1;
        let fresh = collide(&a, 0, &b2, 1, CUTOFF).expect("still touching");
        let (depth, fresh_depth) = (deepest(&moved), deepest(&fresh));
        assert!(
            (depth - fresh_depth).abs() <= 2.0 * d,
            "deepest {depth} against {fresh_depth}, d = {d}"
        );
        assert!(moved.normal.angle_between(fresh.normal) <= turn + 1e-3);
    }
    // A motion within half of each limit moves a point by at most d: nearly all reused.
    assert!(reused >= 390, "{reused} of 400 reused");
}

#[test]
fn a_motion_past_a_limit_collides_afresh() {
    let mut r = Rnd(31);
    for _ in 0..100 {
        let (a, b) = resting_pair(&mut r, 10.0);
        let m = found(&a, &b);
        let (d, turn) = limits(&a, &b);
        let with = |pos: Vec3, rot: Quat| ColliderEntry {
            pos,
            rot,
            ..b.clone()
        };
        let slide = m.normal.any_orthonormal_vector() * 2.0 * d;
        let twist = Quat::from_axis_angle(m.normal, 2.5 * turn);
        let grown = Shape::Cuboid {
            half_extents: half_extents(&b) * 1.01,
        };
        let cases = [
            ("slid 2d", with(b.pos + slide, b.rot), CUTOFF),
            ("pushed 2d", with(b.pos - m.normal * 2.0 * d, b.rot), CUTOFF),
            ("turned 2.5θ", with(b.pos, twist * b.rot), CUTOFF),
            (
                "resized",
                ColliderEntry {
                    shape: grown,
                    ..b.clone()
                },
                CUTOFF,
            ),
            ("reach grew 2d", b.clone(), CUTOFF + 2.0 * d),
        ];
        for (what, b2, cutoff) in cases {
            assert!(
                reuse(&m, (&a, 0), (&b2, 1), MARGIN, cutoff).is_none(),
                "{what}: reused"
            );
        }
    }
}

#[test]
fn only_box_pairs_are_anchored() {
    let a = cuboid(1, Vec3::ONE, Vec3::ZERO, Quat::IDENTITY);
    let ball = collider(
        2,
        Shape::Sphere { radius: 0.5 },
        Vec3::Y * 1.49,
        Quat::IDENTITY,
    );
    let mut m = collide(&a, 0, &ball, 1, CUTOFF).expect("touching");
    anchor(&mut m, &a, &ball, CUTOFF);
    assert!(!m.anchors.found);
    assert!(reuse(&m, (&a, 0), (&ball, 1), MARGIN, CUTOFF).is_none());
    // Coincident centres are collided with a nudge the anchors do not know of.
    let twin = cuboid(3, Vec3::ONE, Vec3::ZERO, Quat::IDENTITY);
    let mut m = collide(&a, 0, &twin, 1, CUTOFF).expect("touching");
    anchor(&mut m, &a, &twin, CUTOFF);
    assert!(!m.anchors.found);
}
