//! Manifold reuse: a box pair whose relative pose has barely changed since its manifold
//! was found gets that manifold moved with the two boxes instead of found again (rapier
//! does the same through parry's `try_update_contacts`). A resting stack is nearly all
//! such pairs.
//!
//! The points are fixed to the boxes ([`Anchors`]), so they move exactly with them; what
//! can go stale is only which points the clipping would find now. That is bounded by
//! [`REUSE_DRIFT`]: a manifold is reused while each of its points has moved less than the
//! drift tolerance `d` relative to the other box since it was found (along the normal
//! too), the relative rotation has turned no point of either box by more than `d` about
//! a manifold point, and the cutoff (margin plus reach) has grown by less than `d`. Then
//! no point of either box has come more than `2d` closer to the other, so a corner the
//! clipping left out (beyond the cutoff then) is still beyond the cutoff now less `3d`,
//! which the speculative margin covers (`d` is at most a quarter of it): it cannot touch
//! this step.

use bevy::prelude::*;

use crate::collider::Shape;
use crate::world::coincident_nudge;
use crate::world::{Anchors, ColliderEntry, Manifold};

/// The drift tolerance as a fraction of the thinner box's thickness (1 mm for two 1 m
/// cubes: half the resting sag a contact is allowed, `SolverSettings::max_sag`), and at
/// most a quarter of the pair's speculative margin.
///
/// Measured on the 5,050-cube pyramid (`examples/stage_times`, 20 + 580 steps): the
/// farther a cube has walked by step 600 (mostly the top cube, out of the plane)
/// falls as the tolerance grows: 3e-5: 0.71 m, 1,520 cubes above 0.1 m/s, 9,492 of 14,950
/// manifolds reused a step; 1e-4: 0.63 m, 1,169; 3e-4: 0.46 m, 225; 5e-4: 0.34 m, 109;
/// 1e-3: 0.20 m, none (14,536 reused); 2e-3: 0.23 m, none; 5e-3: 0.18 m, none. Small
/// changes give a wide spread (2e-5: 0.40 m, 4e-5: 0.42 m; changes of rounding elsewhere
/// move 1e-3's between 0.20 and 0.32 m, up to 86 cubes), but not that trend.
/// (Why is not measured; a guess: a manifold found afresh moves its points by the
/// clipping's rounding, and the warm start then pushes at slightly different places.)
/// Step 220 is the same at every tolerance (0.186-0.190 m). The narrow phase took 5.5 ms a step at 3e-5 and 2.0 at
/// 1e-3; 100 pyramids 5.1 and 2.0 ms, with no cube above 0.1 m/s at step 600 (67 at
/// 3e-5). (The trend follows the solver: under one that shakes the pyramid it reverses,
/// 1e-3 walking 0.72 m, so re-measure it when the solver changes.)
pub const REUSE_DRIFT: f32 = 1e-3;

/// The drift tolerance `d` of a pair (see the module docs), m.
fn drift_tolerance(half_extents: [Vec3; 2], margin: f32) -> f32 {
    let [ha, hb] = half_extents;
    (REUSE_DRIFT * 2.0 * ha.min_element().min(hb.min_element())).min(0.25 * margin)
}

fn half_extents(c: &ColliderEntry) -> Option<Vec3> {
    match c.shape {
        Shape::Cuboid { half_extents } => Some(half_extents),
        _ => None,
    }
}

/// Whether the pair is one whose manifolds can be reused: two boxes.
#[inline]
pub(super) fn reusable(a: &ColliderEntry, b: &ColliderEntry) -> bool {
    half_extents(a).is_some() && half_extents(b).is_some()
}

/// Records where a fresh manifold's points sit on its two boxes, found with points kept
/// up to `cutoff` (m). Nothing for other shapes, or for boxes whose centres coincide
/// (collided with a nudge the anchors would not know about).
pub(super) fn anchor(m: &mut Manifold, a: &ColliderEntry, b: &ColliderEntry, cutoff: f32) {
    let (Some(ha), Some(hb)) = (half_extents(a), half_extents(b)) else {
        return;
    };
    if coincident_nudge(a, b).is_some() {
        return;
    }
    let (to_a, to_b) = (a.rot.inverse(), b.rot.inverse());
    let mut anchors = Anchors {
        normal: to_a * m.normal,
        relative_rotation: to_a * b.rot,
        cutoff,
        half_extents: [ha, hb],
        found: true,
        ..default()
    };
    for (k, p) in m.points().iter().enumerate() {
        let half = m.normal * (0.5 * p.separation);
        anchors.a[k] = to_a * (p.point - half - a.pos);
        anchors.b[k] = to_b * (p.point + half - b.pos);
        anchors.separation[k] = p.separation;
    }
    m.anchors = anchors;
}

/// Pushes `cached` (last step's manifold of the pair, with its impulses) onto `out`,
/// moved with the boxes (colliders `ia` and `ib` this step) to their poses now, if the
/// pair has moved little enough since it was found (see the module docs) and every
/// point is still within `cutoff` (the speculative `margin` plus this step's reach, m);
/// false, `out` as it was: collide afresh. (Moved in place: a manifold is ~450 bytes,
/// and returning it then pushing it copied it twice, 2-3 % of a big scene's step.)
pub(super) fn reuse_onto(
    out: &mut Vec<Manifold>,
    cached: &Manifold,
    a: (&ColliderEntry, u32),
    b: (&ColliderEntry, u32),
    (margin, cutoff): (f32, f32),
) -> bool {
    let Some(movement) = movement(cached, a.0, b.0, margin, cutoff) else {
        return false;
    };
    out.push(*cached);
    let m = out.last_mut().expect("just pushed");
    if movement.apply(m, a, b) {
        true
    } else {
        out.pop();
        false
    }
}

/// [`reuse_onto`] into a list of its own: the moved manifold, or None.
#[cfg(test)]
pub(super) fn reuse(
    cached: &Manifold,
    a: (&ColliderEntry, u32),
    b: (&ColliderEntry, u32),
    margin: f32,
    cutoff: f32,
) -> Option<Manifold> {
    let mut out = Vec::new();
    reuse_onto(&mut out, cached, a, b, (margin, cutoff)).then(|| out[0])
}

/// What moves a reusable manifold: its normal now and the drift tolerance.
struct Movement<'a> {
    anchors: &'a Anchors,
    normal: Vec3,
    drift: f32,
    cutoff: f32,
}

/// The checks on the pair as a whole (see [`reuse_onto`]); None: collide afresh.
fn movement<'a>(
    cached: &'a Manifold,
    a: &ColliderEntry,
    b: &ColliderEntry,
    margin: f32,
    cutoff: f32,
) -> Option<Movement<'a>> {
    let anchors = &cached.anchors;
    if !anchors.found || [half_extents(a), half_extents(b)] != anchors.half_extents.map(Some) {
        return None;
    }
    let [ha, hb] = anchors.half_extents;
    let drift = drift_tolerance(anchors.half_extents, margin);
    if !(cutoff <= anchors.cutoff + drift) {
        return None;
    }
    // The turn since found, θ: a point at distance r from a manifold point moves θ·r
    // more than it; r is at most a box's diagonal. |xyz| of the turn's quaternion is
    // sin(θ/2) (its w, cos(θ/2), is 1 to within f32 here).
    let turn = (a.rot.inverse() * b.rot) * anchors.relative_rotation.inverse();
    let diagonal = 2.0 * ha.length().max(hb.length());
    let half_angle = 0.5 * drift / diagonal;
    if !(Vec3::new(turn.x, turn.y, turn.z).length_squared() <= half_angle * half_angle) {
        return None;
    }
    Some(Movement {
        anchors,
        normal: a.rot * anchors.normal,
        drift,
        cutoff,
    })
}

impl Movement<'_> {
    /// Moves `m` (a copy of the cached manifold) to the boxes' poses now, point by
    /// point; false if a point drifted too far or left the cutoff.
    fn apply(
        &self,
        m: &mut Manifold,
        (a, ia): (&ColliderEntry, u32),
        (b, ib): (&ColliderEntry, u32),
    ) -> bool {
        let Self {
            anchors,
            normal,
            drift,
            cutoff,
        } = *self;
        (m.a, m.b, m.normal) = (ia, ib, normal);
        for (k, p) in m.points_mut().iter_mut().enumerate() {
            let on_a = a.pos + a.rot * anchors.a[k];
            let on_b = b.pos + b.rot * anchors.b[k];
            let d = on_b - on_a;
            let separation = d.dot(normal);
            let moved = d - normal * anchors.separation[k];
            if !(moved.length_squared() <= drift * drift && separation <= cutoff) {
                return false;
            }
            p.point = 0.5 * (on_a + on_b);
            p.separation = separation;
            // What the solver reports afresh each step, as for a new manifold.
            p.total_normal_impulse = 0.0;
            p.total_tangent_impulse = Vec3::ZERO;
            p.approach_speed = 0.0;
        }
        true
    }
}
