//! The data layer: [`PhysicsWorld`], the contiguous arrays the step works on between
//! prepare and writeback, and the types the stages hand each other — bodies, colliders,
//! the fixed set, contact manifolds and contact constraints. It imports no stage; every
//! stage imports it.

mod awake_tree;
mod batching;
mod body_view;
mod bounds_index;
mod collide;
mod constraint;
mod contact_batch;
mod fixed_set;
mod joint;
mod warm_start_cache;

pub(crate) use crate::geometry::{Anchors, MAX_POINTS, Manifold};
pub(crate) use crate::math::{ForceModel, Inertial};
pub(crate) use awake_tree::{AwakeTree, Leaf};
pub(crate) use batching::{
    ContactBatches, ContactKey, LANES, NO_CONTACT, SolveStep, SolveWork, prefetch,
};
pub(crate) use body_view::{BodyView, Shared, SharedBodies};
pub(crate) use collide::{coincident_nudge, collide, collide_each};
pub(crate) use constraint::{
    Anchoring, AngularRow, COUPLINGS, ConstraintPoint, ContactConstraint, ContactParams,
    FrictionAnchor, NO_ROLL, RollingArms, body, coupling_index, normal_couplings, row_velocity,
    store,
};
pub(crate) use contact_batch::{AnchorLanes, ContactBatch, FrictionLanes, PointLanes};
pub(crate) use fixed_set::FixedSet;
pub(crate) use joint::{JointConstraint, JointRows, ordered_pair};
pub(crate) use warm_start_cache::WarmStartCache;

use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use crate::body::{CoefficientCombine, RigidBody};
use crate::collider::Shape;
use crate::events::TouchingPair;
use crate::layers::CollisionLayers;

/// Body index of a static collider: no solver body, zero velocity, infinite mass.
pub(crate) const STATIC: u32 = u32::MAX;

/// The small hot state the solver iterates over. Positions are kept as changes since the
/// start of the step (`dp`, `dq`) so that contact anchors stay precise far from the origin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SolverBody {
    pub v: Vec3,
    pub w: Vec3,
    /// Position change since the start of the step.
    pub dp: Vec3,
    /// Rotation since the start of the step (world orientation = dq · q0).
    pub dq: Quat,
    pub inv_mass: f32,
    /// World-frame inverse inertia at the start of the step.
    pub inv_inertia: Mat3,
}

/// The integrators' view of a body.
impl<'a> Inertial<'a> {
    pub fn of(body: &'a BodyState) -> Self {
        Self {
            forces: &body.forces,
            inertia: body.inertia,
            inv_inertia: body.inv_inertia,
            rotation_locked: body.rotation_locked,
        }
    }
}

/// The cold per-body data of one step, parallel to [`PhysicsWorld::solver_bodies`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyState {
    pub entity: Entity,
    pub kind: RigidBody,
    /// Pose and velocity at the start of the step.
    pub x0: Vec3,
    pub q0: Quat,
    pub v0: Vec3,
    pub w0: Vec3,
    /// Principal moments of inertia (body frame) and their inverses (0 for kinematic).
    pub inertia: Vec3,
    pub inv_inertia: Vec3,
    pub forces: ForceModel,
    /// The body's own drag coefficients (linear, angular), applied when damping is on.
    pub damping: Vec2,
    pub gravity_scale: f32,
    /// No angular motion: no angular integration, zero inverse inertia.
    pub rotation_locked: bool,
    /// A sphere (or no collider): its contact geometry does not turn with it, so its spin
    /// is never limited (see `MAX_ROTATION_PER_STEP` in the solve stage).
    pub round: bool,
    /// The body touches something this step, so the solver re-integrates it with contacts.
    pub in_contact: bool,
    /// How long it has been slow enough to sleep, s.
    pub sleep_time: f32,
    /// A kinematic body moved this step by the user's Transform (see [`KinematicPose`]),
    /// and the target it is still on its way to after this step.
    pub driven: bool,
    pub target: Option<(Vec3, Quat)>,
}

/// How a body's solver pose maps back to its `Transform`, parallel to
/// [`PhysicsWorld::bodies`] (kept out of the records the solver loops read).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyFrame {
    /// The centre of mass in the body's frame, m (its [`CenterOfMass`](crate::body::CenterOfMass),
    /// or a compound's; zero for most bodies). `x0` and the solver's poses are the centre
    /// of mass's; the `Transform` is `x − rot·com`.
    pub com: Vec3,
    /// The rotation of the body's principal axes in its own frame (identity but for a
    /// compound body): the solver's orientation is the body's times this.
    pub frame: Quat,
    /// Index of its parents' composed transform in [`PhysicsWorld::parent_frames`], or
    /// [`NO_PARENT`]: its `Transform` is written back in that frame.
    pub parent: u32,
}

/// [`BodyState::parent`] of a body without a parent.
pub(crate) const NO_PARENT: u32 = u32::MAX;

/// The pose tumble wrote to a kinematic body's Transform at the end of a step, and
/// whether the user's Transform drove it there. Next step, a Transform that differs is
/// the user's move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KinematicPose {
    pub pos: Vec3,
    pub rot: Quat,
    pub driven: bool,
    /// Where the user's Transform asked it to be, when a frame's steps are not over yet
    /// (the Transform now holds the pose of this step, not the target).
    pub target: Option<(Vec3, Quat)>,
}

/// Whether principal inverse inertias are the same about every axis (a sphere, a cube,
/// a body that cannot turn): then the world inertia never changes as the body turns.
pub(crate) fn is_isotropic(inv_principal: Vec3) -> bool {
    inv_principal.x == inv_principal.y && inv_principal.y == inv_principal.z
}

/// R · diag(inv_principal) · Rᵀ.
pub(crate) fn world_inv_inertia(rot: Quat, inv_principal: Vec3) -> Mat3 {
    // Isotropic (spheres, locked rotation): the same in every frame.
    if is_isotropic(inv_principal) {
        return Mat3::from_diagonal(inv_principal);
    }
    let r = Mat3::from_quat(rot);
    r * Mat3::from_diagonal(inv_principal) * r.transpose()
}

impl BodyState {
    pub fn is_dynamic(&self) -> bool {
        self.kind == RigidBody::Dynamic
    }
}

/// How a collider takes part in contacts: its [`CollisionLayers`], whether it is a
/// [`Sensor`](crate::layers::Sensor), whether it asked for collision events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ContactFilter {
    pub layers: CollisionLayers,
    pub sensor: bool,
    pub events: bool,
    /// The combine rules this collider asks for: friction, restitution.
    pub combine: (CoefficientCombine, CoefficientCombine),
}

impl Default for ContactFilter {
    fn default() -> Self {
        Self {
            layers: CollisionLayers::default(),
            sensor: false,
            events: false,
            combine: (CoefficientCombine::GeometricMean, CoefficientCombine::Max),
        }
    }
}

impl ColliderEntry {
    /// A collider of its own (`owner` is itself) with `shape` at a pose, on body `body`
    /// ([`STATIC`] for none): centred on the body's centre of mass, the default
    /// friction, no restitution, the default filter, awake, bounds not yet computed.
    /// The one constructor, so that a new field has one place to get its default.
    pub fn new(entity: Entity, key: u64, body: u32, shape: Shape, pos: Vec3, rot: Quat) -> Self {
        Self {
            entity,
            owner: entity,
            key,
            body,
            asleep: false,
            shape,
            offset: Vec3::ZERO,
            local_rot: Quat::IDENTITY,
            pos,
            rot,
            friction: crate::body::DEFAULT_FRICTION,
            restitution: 0.0,
            filter: ContactFilter::default(),
            aabb_min: Vec3::ZERO,
            aabb_max: Vec3::ZERO,
        }
    }

    /// The body this collider belongs to, or `None` for a static collider.
    #[inline]
    pub fn body_entity(&self) -> Option<Entity> {
        (self.body != STATIC || self.asleep).then_some(self.owner)
    }
}

impl ContactFilter {
    /// Whether two colliders' pair is looked at all: their layers interact and they are
    /// not both sensors.
    pub fn allows(&self, other: &Self) -> bool {
        self.layers.interacts_with(other.layers) && !(self.sensor && other.sensor)
    }
}

/// One collider of this step. Dynamic and kinematic colliders point at their body.
#[derive(Clone, Debug)]
pub(crate) struct ColliderEntry {
    pub entity: Entity,
    /// The body it belongs to: itself, or for a part of a compound body the body above
    /// it. Static colliders own themselves.
    pub owner: Entity,
    /// The collider's [`SpawnOrder`](crate::body::SpawnOrder): pairs are visited in this
    /// order, whatever the ECS's.
    pub key: u64,
    /// Index into the body arrays, or [`STATIC`].
    pub body: u32,
    /// A sleeping body, standing in as a static collider this step.
    pub asleep: bool,
    pub shape: Shape,
    /// The shape's centre relative to its body's centre of mass, body frame, m (minus
    /// the body's [`CenterOfMass`](crate::body::CenterOfMass); zero for statics).
    pub offset: Vec3,
    /// The shape's rotation relative to its body's principal frame (identity but for
    /// the parts of a compound body).
    pub local_rot: Quat,
    /// Pose at the start of the step.
    pub pos: Vec3,
    pub rot: Quat,
    pub friction: f32,
    pub restitution: f32,
    /// Layers, sensor, events: what decides whether and how it touches others.
    pub filter: ContactFilter,
    /// Bounds swept over the step's free motion and fattened by the speculative margin.
    pub aabb_min: Vec3,
    pub aabb_max: Vec3,
}

/// The simulation's working state. The awake bodies are gathered by prepare each step;
/// the fixed set and the contact cache survive between steps.
#[derive(Resource, Default)]
pub struct PhysicsWorld {
    /// Hot solver state, one per dynamic or kinematic body.
    pub(crate) solver_bodies: Vec<SolverBody>,
    /// Cold per-body data, parallel to `solver_bodies`.
    pub(crate) bodies: Vec<BodyState>,
    /// How each body's pose maps back to its `Transform`, parallel to `bodies`.
    pub(crate) body_frames: Vec<BodyFrame>,
    /// This step's colliders: the awake ones, then the fixed ones the broad phase found
    /// near them (copied from `fixed`).
    pub(crate) colliders: Vec<ColliderEntry>,
    /// Static colliders and sleeping bodies, kept between steps and updated only when
    /// they change.
    pub(crate) fixed: FixedSet,
    /// The awake colliders' tree: the broad phase's, refitted for the spatial queries
    /// after the step (behind a lock because queries read the world shared).
    pub(crate) awake_tree: std::sync::RwLock<AwakeTree>,
    /// Candidate collider pairs from the broad phase, as indices into `colliders`.
    pub(crate) pairs: Vec<(u32, u32)>,
    /// Contact manifolds from the narrow phase.
    pub(crate) manifolds: Vec<Manifold>,
    /// Overlaps with a [`Sensor`](crate::layers::Sensor) this step: manifolds the solver
    /// never sees, only the collision events.
    pub(crate) sensor_overlaps: Vec<Manifold>,
    /// Contact constraints built by the solver, one place a manifold: those of the
    /// contacts the scalar pass solves, of those with fixed colliders, and all when
    /// `keep_constraints` asks (a batched contact is built straight into its lanes; its
    /// place holds whatever it held).
    pub(crate) constraints: Vec<ContactConstraint>,
    /// Keep every contact's constraint (tests and benchmarks that read them).
    pub(crate) keep_constraints: bool,
    /// What packing reads of each contact (the same index).
    pub(crate) contact_keys: Vec<ContactKey>,
    /// The turning arms of the few constraints with a rolling off-centre sphere
    /// (`Anchoring::roll` indexes it).
    pub(crate) rolling_arms: Vec<RollingArms>,
    /// Last step's accumulated impulses by entity pair (and triangle, for a mesh pair:
    /// [`Manifold::sub`]), for warm starting.
    pub(crate) impulse_cache: WarmStartCache,
    /// This step's joints (empty in a scene without any).
    pub(crate) joints: Vec<JointConstraint>,
    /// Body pairs (ordered by entity) held by a joint that keeps them from colliding.
    pub(crate) joint_pairs: bevy::platform::collections::HashSet<(Entity, Entity)>,
    /// Sleeping bodies that an awake body touched this step: they wake.
    pub(crate) wake: Vec<Entity>,
    /// The composed transforms of this step's parented bodies' parents (uniform scale).
    pub(crate) parent_frames: Vec<Transform>,
    /// Kinematic bodies' poses as written at the end of the last step.
    pub(crate) kinematic_poses: HashMap<Entity, KinematicPose>,
    /// Pairs (ordered by entity) that touched last step, for the collision messages.
    pub(crate) touching: HashMap<(Entity, Entity), TouchingPair>,
    /// The fixed step of the current step, seconds.
    pub(crate) dt: f32,
    /// The contact solver's substep last step, s (0 before the first contact), which
    /// the cached warm-start impulses are per.
    pub(crate) last_substep: f32,
    /// Substeps the contact solver took last step (the setting, or more for stiff
    /// contacts).
    pub(crate) substeps: u32,
    /// Solve passes per substep in the last step.
    pub(crate) iterations: u32,
    /// Relax passes per substep in the last step.
    pub(crate) relax_iterations: u32,
    /// The contact passes' work over the batches in the last step, all passes together.
    pub(crate) solve_work: SolveWork,
    /// Of the last step's manifolds, those moved from the step before instead of found
    /// again (see the narrow phase's `reuse`).
    pub(crate) reused_manifolds: usize,
    /// Steps taken since the plugin started.
    pub(crate) step_count: u64,
}

/// What a game, a test or an overlay may read; the arrays themselves are the step's.
impl PhysicsWorld {
    /// Fixed steps taken since the plugin started.
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// Substeps the contact solver took in the last step: the setting, or more when
    /// stiff contacts asked for them (see `SolverSettings::max_sag`).
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Solve passes per substep in the last step: the setting, or more when
    /// heavy loads on light bodies asked for them (see `SolverSettings::iterations`).
    pub fn iterations(&self) -> u32 {
        self.iterations
    }

    /// Relax passes per substep in the last step: the setting, or more when a pair's
    /// mass ratio, or a bouncing contact's load, asked for them (the solve passes follow
    /// every contact's load).
    pub fn relax_iterations(&self) -> u32 {
        self.relax_iterations
    }

    /// Sweeps over a batch's normal rows per batch and pass in the last step: 1 when
    /// every batch settles in one sweep, at most `NORMAL_SWEEPS` (0 with no batches). A
    /// count of the contact solver's work that does not depend on the machine's speed,
    /// for comparing changes on a noisy one (`examples/stage_times` prints it).
    pub fn normal_sweeps_per_batch(&self) -> f32 {
        let SolveWork { sweeps, batches } = self.solve_work;
        if batches == 0 {
            0.0
        } else {
            (sweeps as f64 / batches as f64) as f32
        }
    }

    /// Of the last step's contact manifolds, how many were last step's moved with their
    /// two boxes instead of found again (box pairs whose relative pose barely changed).
    pub fn reused_manifolds(&self) -> usize {
        self.reused_manifolds
    }

    /// Contact points of the last step's manifolds.
    pub fn contact_points(&self) -> usize {
        self.manifolds.iter().map(|m| m.len).sum()
    }

    /// Dynamic and kinematic bodies simulated in the last step (sleepers not counted).
    pub fn awake_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// Static colliders and sleeping bodies: the fixed set, kept between steps.
    pub fn fixed_colliders(&self) -> usize {
        self.fixed.len()
    }

    /// Candidate pairs the broad phase found in the last step.
    pub fn candidate_pairs(&self) -> usize {
        self.pairs.len()
    }

    /// Contact manifolds of the last step, speculative ones (not yet touching) included.
    pub fn contact_manifolds(&self) -> usize {
        self.manifolds.len()
    }

    /// Pairs reported as touching to collision events (colliders with
    /// `CollisionEventsEnabled` only).
    pub fn reported_pairs(&self) -> usize {
        self.touching.len()
    }

    /// Deepest overlap among the last step's contacts at its start, m (0 when none).
    pub fn deepest_overlap(&self) -> f32 {
        self.manifolds
            .iter()
            .flat_map(|m| m.points())
            .map(|p| -p.separation)
            .fold(0.0, f32::max)
    }

    /// Where the last step left a kinematic body (position, rotation). Its `Transform`
    /// may already hold the game's next move, which the next step drives it to.
    pub fn kinematic_pose(&self, body: Entity) -> Option<(Vec3, Quat)> {
        self.kinematic_poses.get(&body).map(|k| (k.pos, k.rot))
    }

    /// Whether a joint keeps bodies `a` and `b` (owner entities) from colliding.
    #[inline]
    pub(crate) fn jointed(&self, a: Entity, b: Entity) -> bool {
        !self.joint_pairs.is_empty() && self.joint_pairs.contains(&ordered_pair(a, b))
    }

    /// The current world pose of a collider during the step: its body's pose carried to
    /// the shape's centre, or its own for a static one.
    #[inline]
    pub(crate) fn collider_pose(&self, c: &ColliderEntry) -> (Vec3, Quat) {
        if c.body == STATIC {
            return (c.pos, c.rot);
        }
        let (p, q) = self.body_pose(c.body as usize);
        if c.local_rot == Quat::IDENTITY {
            (p + q * c.offset, q)
        } else {
            (p + q * c.offset, (q * c.local_rot).normalize())
        }
    }

    /// The current world pose of a body's centre of mass during the step.
    #[inline]
    pub(crate) fn body_pose(&self, i: usize) -> (Vec3, Quat) {
        let (b, s) = (&self.bodies[i], &self.solver_bodies[i]);
        (b.x0 + s.dp, (s.dq * b.q0).normalize())
    }
}
