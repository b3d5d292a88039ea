//! Stage 1, prepare: validate bodies and gather the awake ones from the ECS into the
//! contiguous arrays of [`PhysicsWorld`]; keep the fixed set (static colliders, sleeping
//! bodies) up to date from what changed. A body with invalid input is left out, tagged
//! with [`PhysicsRejected`], and reported once in the log by entity and field.

mod compound;
mod fixed;
mod gather;
mod hierarchy;
mod impulses;
mod joints;
mod kinematic;
mod lifecycle;
mod reach;
mod settings;
mod validate;

use bevy::ecs::query::QueryData;
use bevy::prelude::*;

use crate::body::*;
use crate::collider::{Collider, Shape};
use crate::effects::{Effects, GravityScale, LockRotation};
use crate::events::CollisionEventsEnabled;
use crate::layers::{CollisionLayers, Sensor};
use crate::settings::SolverSettings;
use crate::world::{BodyFrame, ColliderEntry, ContactFilter, NO_PARENT, PhysicsWorld, STATIC};

pub use compound::BodyPart;
use compound::{Part, PartItem, PartScratch, compound_mass, own_part, part_entry};
pub use fixed::{InFixedSet, sync_fixed_set};
use gather::{BodyInput, gather_body};
use gather::{MassInput, mass_properties};
use hierarchy::{ChainQuery, parent_frame, unsupported, world_transform};
use impulses::apply_impulse;
pub use impulses::clear_impulses;
pub use joints::prepare_joints;
use kinematic::{Drive, drive_kinematic};
pub use lifecycle::{
    PendingRechecks, SpawnCounter, number_collider, readmit_rejected, record_marker, record_removal,
};
pub use reach::wake_reached_sleepers;
pub use settings::{guard_fixed_rate, validate_settings};
pub use validate::validate;
use validate::{BodyChecks, check_body, validate_mass_properties, validate_scalars};

/// The components prepare reads from each awake body (and the impulse it consumes).
#[derive(QueryData)]
#[query_data(mutable)]
pub struct BodyItem {
    entity: Entity,
    transform: &'static Transform,
    collider: Option<&'static Collider>,
    kind: &'static RigidBody,
    velocity: Option<&'static Velocity>,
    mass: Option<&'static Mass>,
    density: Option<&'static ColliderDensity>,
    angular_inertia: Option<&'static AngularInertia>,
    center_of_mass: Option<&'static CenterOfMass>,
    restitution: Option<&'static Restitution>,
    friction: Option<&'static Friction>,
    force: Option<&'static ExternalForce>,
    impulse: Option<&'static mut ExternalImpulse>,
    linear_damping: Option<&'static LinearDamping>,
    angular_damping: Option<&'static AngularDamping>,
    sleep_timer: Option<&'static SleepTimer>,
    gravity_scale: Option<&'static GravityScale>,
    lock_rotation: Has<LockRotation>,
    order: Option<&'static SpawnOrder>,
    filter: FilterItem,
    parent: Has<ChildOf>,
    children: Option<&'static Children>,
}

/// What decides whether and how a collider touches others.
#[derive(QueryData)]
pub struct FilterItem {
    layers: Option<&'static CollisionLayers>,
    sensor: Has<Sensor>,
    events: Has<CollisionEventsEnabled>,
    friction_combine: Option<&'static FrictionCombine>,
    restitution_combine: Option<&'static RestitutionCombine>,
}

impl FilterItemItem<'_, '_> {
    /// The collider's [`ContactFilter`].
    pub fn get(&self) -> ContactFilter {
        let default = ContactFilter::default();
        ContactFilter {
            layers: self.layers.copied().unwrap_or_default(),
            sensor: self.sensor,
            events: self.events,
            combine: (
                self.friction_combine.map_or(default.combine.0, |c| c.0),
                self.restitution_combine.map_or(default.combine.1, |c| c.0),
            ),
        }
    }
}

/// Which entities prepare gathers each step: bodies that are not asleep, not already in
/// the fixed set and not rejected. Colliders without a `RigidBody` are static and live
/// in the fixed set ([`sync_fixed_set`]).
pub type BodyQueryFilter = (
    With<RigidBody>,
    Without<Sleeping>,
    Without<InFixedSet>,
    Without<PhysicsRejected>,
);

/// Gathers every awake body into [`PhysicsWorld`] for this step. A `RigidBody::Static`
/// met here for the first time goes into the fixed set and is not visited again.
pub fn prepare_bodies(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    time: Res<Time<Fixed>>,
    effects: Res<Effects>,
    settings: Res<SolverSettings>,
    mut query: Query<BodyItem, BodyQueryFilter>,
    chain: ChainQuery,
    part_items: Query<PartItem>,
    mut scratch: Local<PartScratch>,
) {
    let world = &mut *world;
    // The fixed step's length, also when a paused app single-steps.
    world.dt = time.timestep().as_secs_f32();
    world.solver_bodies.clear();
    world.bodies.clear();
    world.body_frames.clear();
    world.colliders.clear();
    world.wake.clear();
    world.parent_frames.clear();
    // Filled by the collision stages only when collisions are on.
    world.pairs.clear();
    // Last step's manifolds become the warm-start cache the narrow phase reads.
    world.impulse_cache.take_over(&mut world.manifolds);
    world.sensor_overlaps.clear();

    // Kinematic poses tumble wrote last step: a kinematic body whose Transform differs
    // was moved by the user, and gets there over the steps left in this frame.
    let last_poses = std::mem::take(&mut world.kinematic_poses);
    // Steps left in this frame, this one included (in whole nanoseconds: f32 seconds
    // would round 16.666666 ms / 16.666667 ms down to 0). A Transform the game set in a
    // frame is reached over the frame's steps, so two steps a frame move evenly.
    let whole = time.overstep().as_nanos() / time.timestep().as_nanos().max(1);
    let span = world.dt * (1 + whole) as f32;
    for mut item in &mut query {
        let entity = item.entity;
        let kind = *item.kind;
        // Under a parent: simulated in the world, written back in the parent's frame.
        let (tf, parent) = if item.parent {
            match parented_pose(entity, kind, &chain, &mut world.parent_frames) {
                Ok(pose) => pose,
                Err(e) => {
                    reject(&mut commands, entity, e);
                    continue;
                }
            }
        } else {
            (*item.transform, NO_PARENT)
        };
        if kind == RigidBody::Static {
            admit_static(&mut commands, world, &item, &tf, &mut scratch, &part_items);
            continue;
        }
        // By reference: a local copy was read back wider than it was written, and waited.
        let vel = item.velocity.unwrap_or(&Velocity::ZERO);
        let shape = item.collider.map(|c| scaled_shape(entity, c, &tf));
        // Colliders on its children make it a compound body. (Cleared only when used:
        // parts hold shapes, so clearing runs their drop even when empty.)
        if !scratch.parts.is_empty() {
            scratch.parts.clear();
        }
        if let Some(children) = item.children {
            let density = item.density.map(|d| d.0);
            scratch.collect(children, tf.scale, density, &part_items);
            if let (Some(shape), false) = (&shape, scratch.parts.is_empty()) {
                let key = order_key(entity, item.order);
                let material = (
                    item.friction.map_or(DEFAULT_FRICTION, |f| f.0),
                    item.restitution.map_or(0.0, |r| r.0),
                    item.filter.get(),
                );
                let own = own_part(entity, key, shape.clone(), item.density, material);
                scratch.parts.insert(0, own);
            }
        }
        let parts = &scratch.parts;
        if let Some(e) = parts.iter().find_map(|p| validate_part(&tf, kind, p).err()) {
            reject(&mut commands, entity, e);
            continue;
        }
        let damping = Vec2::new(
            item.linear_damping.map_or(0.0, |d| d.0),
            item.angular_damping.map_or(0.0, |d| d.0),
        );
        let checked = check_body(&BodyChecks {
            tf: &tf,
            vel,
            kind,
            mass: item.mass,
            shape: shape.as_ref(),
            force: item.force,
            center_of_mass: item.center_of_mass,
            friction: item.friction,
            restitution: item.restitution,
            damping,
            gravity_scale: item.gravity_scale,
        });
        if let Err(e) = checked {
            reject(&mut commands, entity, e);
            continue;
        }
        let mut rot = tf.rotation.normalize();
        let mut pos = tf.translation;
        let mut vel = *vel;
        let (mut driven, mut target) = (false, None);
        if kind == RigidBody::Kinematic
            && let Some(last) = last_poses.get(&entity)
        {
            match drive_kinematic(last, &tf, span, settings.max_linear_speed) {
                Drive::ToTarget(v, goal) => {
                    (pos, rot, vel, driven) = (last.pos, last.rot, v, true);
                    target = (span > world.dt).then_some(goal);
                }
                Drive::Stopped => vel = Velocity::ZERO,
                Drive::ByVelocity => {}
            }
        }
        let index = world.bodies.len() as u32;
        // The solver works at the centre of mass, in the principal frame; a simple
        // body's collider sits at its origin.
        let dynamic = kind == RigidBody::Dynamic;
        let compound = (!parts.is_empty())
            .then(|| compound_mass(parts, item.mass, item.angular_inertia, item.center_of_mass));
        let (com, frame) = match (dynamic, compound, item.center_of_mass) {
            (true, Some(c), _) => (c.com, c.frame),
            (true, None, Some(c)) => (c.0, Quat::IDENTITY),
            // A cone's or a hull's own centre of mass is off its origin, and a hull's
            // principal axes can lie any way.
            (true, None, None) => match shape {
                Some(ref s @ (Shape::Cone { .. } | Shape::ConvexHull(_))) => {
                    (s.center_of_mass(), s.principal_frame())
                }
                _ => (Vec3::ZERO, Quat::IDENTITY),
            },
            _ => (Vec3::ZERO, Quat::IDENTITY),
        };
        let mass_props = compound.map_or_else(
            || {
                let input = MassInput {
                    mass: item.mass,
                    density: item.density,
                    inertia: item.angular_inertia,
                };
                mass_properties(shape.as_ref(), &input)
            },
            |c| (c.mass, c.moments),
        );
        if dynamic {
            let given = (item.mass.is_some(), item.angular_inertia.is_some());
            if let Err(e) = validate_mass_properties(mass_props.0, mass_props.1, given) {
                reject(&mut commands, entity, e);
                continue;
            }
        }
        let input = BodyInput {
            entity,
            kind,
            pos: if com == Vec3::ZERO {
                pos
            } else {
                pos + rot * com
            },
            mass_props,
            round: compound.is_none()
                && matches!(shape, None | Some(Shape::Sphere { .. }))
                && com == Vec3::ZERO,
            rot: if frame == Quat::IDENTITY {
                rot
            } else {
                (rot * frame).normalize()
            },
            vel,
            force: item.force,
            damping,
            gravity_scale: item.gravity_scale.map_or(1.0, |g| g.0),
            rotation_locked: item.lock_rotation || !effects.rotation,
            sleep_time: item.sleep_timer.map_or(0.0, |t| t.0),
            driven,
            target,
        };
        gather_body(
            input,
            &settings,
            &mut world.bodies,
            &mut world.solver_bodies,
        );
        // On the stored records: borrowing the locals for an out-of-line call kept the
        // 192-byte state on the stack and copied it three times (+25 ns a body).
        if let Some(j) = item.impulse.as_mut().filter(|j| dynamic && !j.is_zero()) {
            let i = index as usize;
            apply_impulse(entity, j, &mut world.bodies[i], &mut world.solver_bodies[i]);
            // Applied once: zeroed without counting as the user's change.
            *j.bypass_change_detection() = ExternalImpulse::default();
        }
        world.body_frames.push(BodyFrame { com, frame, parent });
        if !parts.is_empty() {
            for p in parts.iter() {
                if !p.marked {
                    commands.entity(p.entity).insert(BodyPart);
                }
                let entry = part_entry(p, (entity, index), (pos, rot), (com, frame));
                world.colliders.push(entry);
            }
        } else if let Some(shape) = shape {
            // In the principal frame (turned only for a hull): the shape's centre from
            // the centre of mass, and its rotation.
            let (offset, local_rot) = if frame == Quat::IDENTITY {
                (-com, Quat::IDENTITY)
            } else {
                let inv = frame.inverse();
                (inv * -com, inv)
            };
            let key = order_key(entity, item.order);
            world.colliders.push(ColliderEntry {
                offset,
                local_rot,
                friction: item.friction.map_or(DEFAULT_FRICTION, |f| f.0),
                restitution: item.restitution.map_or(0.0, |r| r.0),
                filter: item.filter.get(),
                ..ColliderEntry::new(entity, key, index, shape, pos, rot)
            });
        }
    }
    // Read: hand the map back empty, its capacity kept, for writeback to fill (no
    // allocation per step).
    let mut last_poses = last_poses;
    last_poses.clear();
    world.kinematic_poses = last_poses;
}

/// A body under a parent: its world pose through the chain, and the index of its
/// parent's frame (pushed to `frames`) for writeback. Out of line and cold: most bodies
/// have no parent.
#[cold]
#[inline(never)]
fn parented_pose(
    entity: Entity,
    kind: RigidBody,
    chain: &ChainQuery,
    frames: &mut Vec<Transform>,
) -> Result<(Transform, u32), (&'static str, String)> {
    let (world_tf, under_body) = world_transform(entity, chain);
    let frame = parent_frame(entity, chain);
    if let Some(e) = unsupported(kind != RigidBody::Static, &frame, under_body) {
        return Err(e);
    }
    frames.push(frame);
    Ok((world_tf, frames.len() as u32 - 1))
}

/// A `RigidBody::Static` met for the first time: it and its parts go into the fixed set,
/// and it is not gathered again. Out of line: it happens once per static body.
#[cold]
#[inline(never)]
fn admit_static(
    commands: &mut Commands,
    world: &mut PhysicsWorld,
    item: &BodyItemItem,
    tf: &Transform,
    scratch: &mut PartScratch,
    part_items: &Query<PartItem>,
) {
    let entity = item.entity;
    commands.entity(entity).insert(InFixedSet);
    if let Some(c) = item.collider {
        let key = order_key(entity, item.order);
        let material = (item.friction, item.restitution, item.filter.get());
        let entry = fixed_entry(entity, key, tf, c, material);
        match validate_static(tf, c, item.friction, item.restitution) {
            Ok(()) => world.fixed.insert(entry(false)),
            Err(e) => reject(commands, entity, e),
        }
    }
    // A static compound: its parts are static colliders it owns.
    if let Some(children) = item.children {
        let density = item.density.map(|d| d.0);
        scratch.collect(children, tf.scale, density, part_items);
        scratch.insert_fixed(&mut world.fixed, entity, tf, false);
    }
}

/// A collider's place in the step's canonical order: its [`SpawnOrder`] (every collider
/// gets one when it appears; the entity's bits stand in until then).
#[inline]
fn order_key(entity: Entity, order: Option<&SpawnOrder>) -> u64 {
    order.map_or(u64::MAX - entity.to_bits(), |o| o.0)
}

/// A static collider's input: its pose, shape and material.
fn validate_static(
    tf: &Transform,
    c: &Collider,
    friction: Option<&Friction>,
    restitution: Option<&Restitution>,
) -> Result<(), (&'static str, String)> {
    let kind = RigidBody::Static;
    validate(
        tf,
        &Velocity::ZERO,
        kind,
        None,
        Some(&c.shape.scaled(tf.scale)),
    )
    .and_then(|()| validate_scalars(friction, restitution, Vec2::ZERO, None))
}

/// A collider's shape under its entity's `Transform::scale`. What cannot scale exactly
/// (a sphere stretched unevenly) takes its largest axis, with a warning.
#[inline]
pub fn scaled_shape(entity: Entity, collider: &Collider, tf: &Transform) -> Shape {
    if tf.scale == Vec3::ONE {
        return collider.shape.clone();
    }
    if !collider.shape.scales_exactly(tf.scale) {
        warn_once!(
            "tumble: a {:?} collider cannot scale this unevenly (entity {entity}, scale {}); \
             a sphere takes the largest axis, a capsule, cylinder or cone the larger \
             across its axis (further cases are not logged)",
            collider.shape.kind(),
            tf.scale
        );
    }
    collider.shape.scaled(tf.scale)
}

/// A compound body's part: its shape's sizes, checked as the body's own would be.
#[inline]
fn validate_part(tf: &Transform, kind: RigidBody, p: &Part) -> Result<(), (&'static str, String)> {
    validate(tf, &Velocity::ZERO, kind, None, Some(&p.shape))
        .map_err(|(field, why)| (field, format!("part {}: {why}", p.entity)))
}

/// Leaves a body out of the simulation, tagged with [`PhysicsRejected`] and logged once.
fn reject(commands: &mut Commands, entity: Entity, (field, reason): (&'static str, String)) {
    error!("tumble: body {entity} left out of the simulation: {field} is invalid ({reason})");
    commands
        .entity(entity)
        .try_remove::<InFixedSet>()
        .insert(PhysicsRejected { field, reason });
}

/// A fixed-set entry for a collider at `tf`, given whether it is asleep.
fn fixed_entry(
    entity: Entity,
    key: u64,
    tf: &Transform,
    collider: &Collider,
    (friction, restitution, filter): (Option<&Friction>, Option<&Restitution>, ContactFilter),
) -> impl Fn(bool) -> ColliderEntry {
    let shape = scaled_shape(entity, collider, tf);
    let (pos, rot) = (tf.translation, tf.rotation.normalize());
    let entry = ColliderEntry {
        friction: friction.map_or(DEFAULT_FRICTION, |f| f.0),
        restitution: restitution.map_or(0.0, |r| r.0),
        filter,
        ..ColliderEntry::new(entity, key, STATIC, shape, pos, rot)
    };
    move |asleep| ColliderEntry {
        asleep,
        ..entry.clone()
    }
}
