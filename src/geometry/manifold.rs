//! Contact manifolds: what the narrow phase hands the solver.

use bevy::prelude::*;

/// Most points a manifold keeps (a box face on a box face reduces to four).
pub(crate) const MAX_POINTS: usize = 4;

/// One contact point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ContactPoint {
    /// World position at the start of the step, midway between the two surfaces.
    pub point: Vec3,
    /// Signed distance along the normal: negative when overlapping, positive for a
    /// speculative point that has not touched yet.
    pub separation: f32,
    /// Which features touch (face, edge, vertex ids). Stable while the same features touch,
    /// so the impulses carry over to the next step.
    pub id: u32,
    /// Accumulated normal impulse (N·s): warm start in, solved value out.
    pub normal_impulse: f32,
    /// This point's share of the manifold's accumulated friction impulse (its share of
    /// the normal impulse), world frame, N·s: the manifold's friction acts at one anchor
    /// (see the solver's `FrictionAnchor`), and the shares of the points that persist
    /// warm-start the next step's.
    pub tangent_impulse: Vec3,
    /// Its share of the manifold's twist impulse about the normal, N·m·s.
    pub twist_impulse: f32,
    /// Normal impulse over the whole last step, N·s (every substep's, restitution's),
    /// for colliders with collision events; 0 otherwise.
    pub total_normal_impulse: f32,
    /// Friction impulse over the whole last step, world frame, N·s (as above).
    pub total_tangent_impulse: Vec3,
    /// How fast the surfaces approached when this point first pushed in the last step,
    /// m/s (0 if they were not approaching): the speed of an impact.
    pub approach_speed: f32,
}

/// The contact between two colliders: one normal, up to [`MAX_POINTS`] points.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Manifold {
    /// Indices into the step's list of colliders.
    pub a: u32,
    pub b: u32,
    /// Unit normal pointing from A to B.
    pub normal: Vec3,
    pub points: [ContactPoint; MAX_POINTS],
    pub len: usize,
    /// Which part of the pair this is: 0, or for a pair with a triangle mesh or
    /// heightfield the touching triangle's index (a pair can have one per triangle).
    pub sub: u32,
    /// The pair's place in its step's candidate pairs (`PhysicsWorld::pairs`), where the
    /// next step looks it up (`WarmStartCache::find_at`).
    pub pair: u32,
    /// The points' normal impulses summed the step before the one they warm-start from
    /// (two steps back when prepared; 0 for a pair that is new since), N·s a substep:
    /// with last step's sum, what tells a load that stays from an impact's impulse,
    /// which lasts a step (see the solver's `SQUEEZE_RATIO`).
    pub previous_load: f32,
    /// Combined material of the pair.
    pub friction: f32,
    pub restitution: f32,
    /// Where the points sit on each collider, for a later step to reuse the manifold
    /// while the pair's relative pose barely changes (box pairs only; see the narrow
    /// phase's `reuse`).
    pub anchors: Anchors,
}

/// A manifold's points fixed to its two colliders as the shape code found them, each in
/// its collider's own frame: rigid motion of the pair moves them exactly, so while the
/// pair's relative pose stays within a small tolerance of this one, the manifold can be
/// moved instead of found again. `found == false`: nothing recorded (not a box pair).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Anchors {
    /// Each point on A's surface (point − normal·separation/2), A's frame, m.
    pub a: [Vec3; MAX_POINTS],
    /// Each point on B's surface (point + normal·separation/2), B's frame, m.
    pub b: [Vec3; MAX_POINTS],
    /// Each point's separation when found, m.
    pub separation: [f32; MAX_POINTS],
    /// The normal in A's frame.
    pub normal: Vec3,
    /// B's rotation relative to A's when found (A⁻¹·B).
    pub relative_rotation: Quat,
    /// The distance up to which points were kept when found (margin plus reach), m.
    pub cutoff: f32,
    /// The two boxes' half extents when found, m (a resized box is collided afresh).
    pub half_extents: [Vec3; 2],
    /// Whether the rest holds anything.
    pub found: bool,
}

impl Manifold {
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.len]
    }

    pub fn points_mut(&mut self) -> &mut [ContactPoint] {
        &mut self.points[..self.len]
    }

    /// Adds a point; beyond [`MAX_POINTS`] it is ignored (shape code reduces first).
    pub fn push(&mut self, point: Vec3, separation: f32, id: u32) {
        if self.len < MAX_POINTS {
            self.points[self.len] = ContactPoint {
                point,
                separation,
                id,
                ..default()
            };
            self.len += 1;
        }
    }

    /// Swaps the roles of A and B: the normal flips.
    pub fn flip(&mut self) {
        std::mem::swap(&mut self.a, &mut self.b);
        self.normal = -self.normal;
    }
}
