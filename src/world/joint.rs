//! A joint as the solver sees it for one step: its two bodies' indices, its anchors and
//! axis at the start of the step, its limits and motor, and its accumulated impulses.

use bevy::prelude::*;

use crate::math::Softness;

/// A pair of entities in a fixed order (the lower first).
pub(crate) fn ordered_pair(a: Entity, b: Entity) -> (Entity, Entity) {
    if a <= b { (a, b) } else { (b, a) }
}

/// The rows a joint adds, by kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum JointRows {
    /// Point and all three turns.
    Fixed,
    /// Point only.
    Spherical,
    /// Point and the two turns across the axis; optional limits and motor about it.
    Revolute,
    /// The two offsets across the axis and all three turns; optional limits and motor
    /// along it.
    Prismatic,
    /// The distance between the anchors, in [min, max]; optionally a spring.
    Distance,
}

/// One joint of this step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointConstraint {
    /// The joint's entity.
    pub entity: Entity,
    /// Body indices, or [`STATIC`](super::STATIC) for the world, a static body or a
    /// sleeper.
    pub a: u32,
    pub b: u32,
    pub rows: JointRows,
    /// The anchors from their bodies' centres of mass at the start of the step, world
    /// frame, m (a fixed side's is zero: its anchor is in `offset`).
    pub ra: Vec3,
    pub rb: Vec3,
    /// From A's centre of mass (or fixed anchor) to B's, at the start of the step, m.
    pub offset: Vec3,
    /// The axis at the start of the step, world frame, unit (turns with A).
    pub axis: Vec3,
    /// B's own axis (where A's lay in B at rest), world frame at the start of the step
    /// (turns with B): a ball joint's cone is measured between the two.
    pub axis_b: Vec3,
    /// A ball joint's cone, rad: the most `axis_b` may lean from `axis`.
    pub cone: Option<f32>,
    /// B's rotation error is `dq_b · rest · dq_a⁻¹` (identity when the bodies keep the
    /// relative pose the joint counts from).
    pub rest: Quat,
    /// Revolute, prismatic or ball-joint twist limits (rad or m), or a distance joint's
    /// min and max (m).
    pub limits: Option<(f32, f32)>,
    /// Motor target speed (rad/s or m/s) and its most force (N·m or N).
    pub motor: Option<(f32, f32)>,
    /// A distance spring: rest length (m), hertz, damping ratio.
    pub spring: Option<(f32, f32, f32)>,
    /// Accumulated impulses, as in [`JointState`](crate::joint::JointForces).
    pub linear: Vec3,
    pub angular: Vec3,
    /// Motor (or a distance joint's rigid or spring row, or a ball joint's cone), lower
    /// limit, upper limit.
    pub axial: [f32; 3],
    /// The substep the impulses are per, s (0 before the first step).
    pub h: f32,
    /// The force (N) and torque (N·m) on B in the last substep, world frame: set after
    /// the solve.
    pub force: Vec3,
    pub torque: Vec3,
    /// The force (N) and torque (N·m, world) it carried last step: what its stiffness is
    /// chosen for.
    pub load: f32,
    pub torque_load: Vec3,
    /// The length its allowed sag is a fraction of, m: its longest arm or its length.
    pub size: f32,
    /// Its soft-step coefficients this step (set by the solver): of its limits, motor
    /// and spring rows (Gauss–Seidel, capped at a quarter of the substep rate) ...
    pub softness: Softness,
    /// ... and of the rows that hold it together, solved at once and exactly (capped at
    /// twice the substep rate: see `joint_direct`).
    pub held: Softness,
}
