//! Joints into the step: each [`Joint`] whose bodies are here becomes a
//! [`JointConstraint`] at the start-of-step poses. A scene without joints returns at once.
//!
//! - A joint with invalid input (NaN anchors, a zero axis, limits the wrong way round) is
//!   left out with [`PhysicsRejected`] and an error naming the field, until it changes.
//! - A joint to a despawned body is removed (its `Joint` component), with a warning.
//! - Each end must be a body, a static collider, or a collider under a body (a compound
//!   body's part: the joint acts on that body, at the part's pose), and the two ends
//!   must not be one body. Otherwise the joint is refused with [`PhysicsRejected`] on
//!   the joint (logged once) and the bodies move as if it were not there; its ends are
//!   looked at again each step, and it comes back once they are right.
//! - A side that is static (or the world) holds still; a side that sleeps holds still
//!   this step and is woken if the other side is awake. A joint with no dynamic side is
//!   ignored (two statics: with a warning, once).

use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;

use super::hierarchy::{ChainQuery, owner_body};
use crate::body::{PhysicsRejected, RigidBody, Sleeping};
use crate::collider::Collider;
use crate::joint::{Joint, JointForces, JointKind};
use crate::limits::{self, MAX_FORCE, MAX_RATE, MAX_SIZE, MAX_SPEED};
use crate::math::Softness;
use crate::world::{JointConstraint, JointRows, PhysicsWorld, STATIC, ordered_pair};

/// One side of a joint this step.
struct Side {
    /// Body index or [`STATIC`].
    index: u32,
    /// Its body's rotation at the start of the step (the world's: identity).
    rot: Quat,
    /// Its centre of mass, or for a still side the anchor itself, m.
    origin: Vec3,
    /// The anchor from `origin`, m.
    arm: Vec3,
    dynamic: bool,
    asleep: Option<Entity>,
}

/// Why a side is not here.
enum Missing {
    /// The entity no longer exists.
    Despawned,
    /// Left out of the simulation (rejected): the joint waits for it.
    Rejected,
}

/// The fields a joint is refused for when an end is wrong, rather than its own values:
/// looked at again every step, since what fixes them is on other entities.
const END_FIELDS: [&str; 2] = ["Joint.body1", "Joint.body2"];

/// What resolving a joint's end reads of the entity it names.
type EndItem = (Has<RigidBody>, Has<Collider>);

/// A joint's end resolved to the body it acts on and the anchor in that body's frame.
/// `None` is the world.
type End = (Option<Entity>, Vec3);

/// Resolves one end: a body acts as itself, a collider under a body as a point of that
/// body (its anchor carried from the part's frame into the body's), a static collider
/// as itself. Anything else is not something a joint can hold.
fn resolve_end(
    field: &'static str,
    body: Option<Entity>,
    anchor: Vec3,
    ends: &Query<EndItem>,
    chain: &ChainQuery,
) -> Result<End, Result<(&'static str, String), Missing>> {
    let Some(entity) = body else {
        return Ok((None, anchor));
    };
    let Ok((is_body, is_collider)) = ends.get(entity) else {
        return Err(Err(Missing::Despawned));
    };
    if is_body {
        return Ok((Some(entity), anchor));
    }
    if !is_collider {
        return Err(Ok((
            field,
            format!("{entity} is neither a body nor a collider (no RigidBody, no Collider)"),
        )));
    }
    let Some(owner) = owner_body(entity, chain) else {
        return Ok((Some(entity), anchor)); // A static collider.
    };
    // The part's frame in its body's (unscaled) frame: the chain of local transforms
    // between them, then the body's own scale.
    let mut in_owner = Transform::IDENTITY;
    let mut at = entity;
    while at != owner {
        let Ok((&local, parent, _)) = chain.get(at) else {
            break;
        };
        in_owner = local.mul_transform(in_owner);
        let Some(p) = parent else { break };
        at = p.parent();
    }
    let scale = chain.get(owner).map_or(Vec3::ONE, |(t, _, _)| t.scale);
    Ok((Some(owner), scale * in_owner.transform_point(anchor)))
}

/// What prepare reads of a body that is not awake.
type StillItem = (
    Option<&'static Transform>,
    Option<&'static GlobalTransform>,
    Has<ChildOf>,
    Has<Sleeping>,
    Has<PhysicsRejected>,
);

/// Fills [`PhysicsWorld::joints`] for this step.
#[allow(clippy::type_complexity)]
pub fn prepare_joints(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    mut joints: Query<(
        Entity,
        Ref<Joint>,
        &mut JointForces,
        Option<&PhysicsRejected>,
    )>,
    still: Query<StillItem>,
    ends: Query<EndItem>,
    chain: ChainQuery,
    mut index: Local<HashMap<Entity, u32>>,
    mut ignored: Local<HashSet<Entity>>,
) {
    let world = &mut *world;
    world.joints.clear();
    world.joint_pairs.clear();
    if joints.is_empty() {
        return;
    }
    index.clear();
    index.extend(
        world
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| (b.entity, i as u32)),
    );
    for (entity, joint, mut forces, rejected) in &mut joints {
        // Refused for its ends: looked at again every step. For its own values: when
        // they change.
        let refused_for_ends = rejected.is_some_and(|r| END_FIELDS.contains(&r.field));
        if rejected.is_some() && !refused_for_ends && !joint.is_changed() {
            continue;
        }
        let refuse = |commands: &mut Commands, (field, reason): (&'static str, String)| {
            if rejected.is_none_or(|r| r.field != field || r.reason != reason) {
                error!(
                    "tumble: joint {entity} left out of the simulation: {field} is invalid ({reason})"
                );
                commands
                    .entity(entity)
                    .insert(PhysicsRejected { field, reason });
            }
        };
        if let Err(e) = check(&joint) {
            refuse(&mut commands, e);
            continue;
        }
        let ends = (
            resolve_end(
                END_FIELDS[0],
                joint.body1,
                joint.local_anchor1,
                &ends,
                &chain,
            ),
            resolve_end(
                END_FIELDS[1],
                Some(joint.body2),
                joint.local_anchor2,
                &ends,
                &chain,
            ),
        );
        let ((body1, anchor1), (body2, anchor2)) = match ends {
            (Ok(a), Ok(b)) => (a, b),
            (Err(Err(Missing::Despawned)), _) | (_, Err(Err(Missing::Despawned))) => {
                warn!(
                    "tumble: joint {entity} holds a body that no longer exists; the joint is removed"
                );
                commands.entity(entity).remove::<Joint>();
                continue;
            }
            (Err(Ok(e)), _) | (_, Err(Ok(e))) => {
                refuse(&mut commands, e);
                continue;
            }
            _ => continue,
        };
        if body1.is_some() && body1 == body2 {
            let what = if joint.body1 == Some(joint.body2) {
                "the same entity as body1".to_string()
            } else {
                format!("a part of the same body as body1 ({})", body2.unwrap())
            };
            refuse(&mut commands, ("Joint.body2", what));
            continue;
        }
        if rejected.is_some() {
            commands.entity(entity).remove::<PhysicsRejected>();
        }
        let side =
            |body: Option<Entity>, anchor: Vec3| side_of(world, &index, &still, body, anchor);
        let (a, b) = match (side(body1, anchor1), side(body2, anchor2)) {
            (Ok(a), Ok(b)) => (a, b),
            _ => continue,
        };
        if !a.dynamic && !b.dynamic {
            let both_static = a.asleep.is_none() && b.asleep.is_none();
            if both_static && ignored.insert(entity) {
                warn!("tumble: joint {entity} holds no dynamic body (two statics?); it is ignored");
            }
            continue;
        }
        // A sleeper held by a body that moves wakes (next step it is awake).
        for (s, other) in [(&a, &b), (&b, &a)] {
            if let (Some(e), true) = (s.asleep, other.index != STATIC) {
                world.wake.push(e);
            }
        }
        let state = &mut forces.state;
        let rest = *state.rest.get_or_insert(a.rot.inverse() * b.rot);
        let axis = a.rot * joint.local_axis1.normalize();
        let (rows, limits, motor, spring) = match joint.kind {
            JointKind::Fixed => (JointRows::Fixed, None, None, None),
            JointKind::Spherical { twist, .. } => (JointRows::Spherical, twist, None, None),
            JointKind::Revolute { limits, motor } => (JointRows::Revolute, limits, motor, None),
            JointKind::Prismatic { limits, motor } => (JointRows::Prismatic, limits, motor, None),
            // No length at all: the anchors together. A distance row has no direction
            // to push along there (the anchors' offset is noise), so the body would
            // circle the pin; the point's three rows hold it still.
            JointKind::Distance {
                max, spring: None, ..
            } if max <= ZERO_LENGTH => (JointRows::Spherical, None, None, None),
            JointKind::Distance { min, max, spring } => {
                let spring = spring.map(|s| (s.rest, s.hertz, s.damping_ratio));
                (JointRows::Distance, Some((min, max)), None, spring)
            }
        };
        world.joints.push(JointConstraint {
            entity,
            a: a.index,
            b: b.index,
            rows,
            ra: a.arm,
            rb: b.arm,
            offset: b.origin - a.origin,
            axis,
            // Body 2's axis: where body 1's lay in it at rest.
            axis_b: b.rot * (rest.inverse() * joint.local_axis1.normalize()),
            cone: match joint.kind {
                JointKind::Spherical { cone, .. } => cone,
                _ => None,
            },
            rest: b.rot * rest.inverse() * a.rot.inverse(),
            limits,
            motor: motor.map(|m| (m.target_speed, m.max_force)),
            spring,
            linear: state.linear,
            angular: state.angular,
            axial: state.axial,
            h: state.h,
            force: Vec3::ZERO,
            torque: Vec3::ZERO,
            load: forces.force.length(),
            torque_load: forces.torque,
            size: a
                .arm
                .length()
                .max(b.arm.length())
                .max(length_of(&joint.kind)),
            softness: Softness::new(0.0, 0.0, 1.0),
            held: Softness::new(0.0, 0.0, 1.0),
        });
        if !joint.collide_connected
            && let (Some(body1), Some(body2)) = (body1, body2)
        {
            world.joint_pairs.insert(ordered_pair(body1, body2));
        }
    }
}

/// A distance joint no longer than this, m, holds its anchors together as a point.
const ZERO_LENGTH: f32 = 1e-6;

/// A distance joint's longest length, m (0 for the other kinds, and for a spring or rope
/// without one).
fn length_of(kind: &JointKind) -> f32 {
    match *kind {
        JointKind::Distance { max, .. } if max.is_finite() => max,
        _ => 0.0,
    }
}

/// Where one side of a joint is this step.
fn side_of(
    world: &PhysicsWorld,
    index: &HashMap<Entity, u32>,
    still: &Query<StillItem>,
    body: Option<Entity>,
    anchor: Vec3,
) -> Result<Side, Missing> {
    let Some(entity) = body else {
        // The world: the anchor is a world point.
        return Ok(Side {
            index: STATIC,
            rot: Quat::IDENTITY,
            origin: anchor,
            arm: Vec3::ZERO,
            dynamic: false,
            asleep: None,
        });
    };
    if let Some(&i) = index.get(&entity) {
        let (b, frame) = (&world.bodies[i as usize], &world.body_frames[i as usize]);
        // The solver's orientation is the body's times its principal frame.
        let rot = (b.q0 * frame.frame.inverse()).normalize();
        return Ok(Side {
            index: i,
            rot,
            origin: b.x0,
            arm: rot * (anchor - frame.com),
            dynamic: b.is_dynamic(),
            asleep: None,
        });
    }
    let Ok((local, global, parented, asleep, rejected)) = still.get(entity) else {
        return Err(Missing::Despawned);
    };
    if rejected {
        return Err(Missing::Rejected);
    }
    // Static, asleep, or not yet admitted: it holds still at its pose — its Transform
    // (a body spawned this frame has no GlobalTransform yet), under a parent its
    // GlobalTransform.
    let tf = match (local, global) {
        (Some(tf), _) if !parented => *tf,
        (_, Some(g)) => g.compute_transform(),
        _ => Transform::IDENTITY,
    };
    let rot = tf.rotation.normalize();
    Ok(Side {
        index: STATIC,
        rot,
        origin: tf.translation + rot * anchor,
        arm: Vec3::ZERO,
        dynamic: false,
        asleep: asleep.then_some(entity),
    })
}

/// A joint's own input: finite anchors within [`MAX_SIZE`], a usable axis, limits in
/// order, a motor's speed and force, a distance's lengths and spring, the break force.
fn check(j: &Joint) -> Result<(), (&'static str, String)> {
    let named = |e: limits::Invalid| (e.field, e.reason);
    limits::vector("Joint.local_anchor1", j.local_anchor1, MAX_SIZE).map_err(named)?;
    limits::vector("Joint.local_anchor2", j.local_anchor2, MAX_SIZE).map_err(named)?;
    let axis = j.local_axis1;
    if !(axis.is_finite() && axis.length_squared() > 1e-12) {
        return Err((
            "Joint.local_axis1",
            format!("{axis}: must be finite and not zero"),
        ));
    }
    let ordered = |field, (lo, hi): (f32, f32), max: f32| {
        if lo.is_finite() && hi.is_finite() && lo <= hi && lo >= -max && hi <= max {
            Ok(())
        } else {
            Err((
                field,
                format!("({lo}, {hi}): must be finite, min ≤ max, within ±{max}"),
            ))
        }
    };
    match j.kind {
        JointKind::Revolute { limits, motor } => {
            if let Some(l) = limits {
                ordered("Joint.kind.limits", l, std::f32::consts::PI)?;
            }
            if let Some(m) = motor {
                limits::scalar(
                    "Joint.kind.motor.target_speed",
                    m.target_speed,
                    -MAX_RATE..=MAX_RATE,
                )
                .map_err(named)?;
                limits::scalar("Joint.kind.motor.max_force", m.max_force, 0.0..=MAX_FORCE)
                    .map_err(named)?;
            }
        }
        JointKind::Prismatic { limits, motor } => {
            if let Some(l) = limits {
                ordered("Joint.kind.limits", l, MAX_SIZE)?;
            }
            if let Some(m) = motor {
                limits::scalar(
                    "Joint.kind.motor.target_speed",
                    m.target_speed,
                    -MAX_SPEED..=MAX_SPEED,
                )
                .map_err(named)?;
                limits::scalar("Joint.kind.motor.max_force", m.max_force, 0.0..=MAX_FORCE)
                    .map_err(named)?;
            }
        }
        JointKind::Distance { min, max, spring } => {
            let ok =
                min.is_finite() && min >= 0.0 && !max.is_nan() && min <= max && min <= MAX_SIZE;
            if !ok {
                return Err((
                    "Joint.kind",
                    format!("min {min}, max {max}: need 0 ≤ min ≤ max"),
                ));
            }
            if let Some(s) = spring {
                limits::scalar("Joint.kind.spring.rest", s.rest, 0.0..=MAX_SIZE).map_err(named)?;
                limits::positive("Joint.kind.spring.hertz", s.hertz, MAX_RATE).map_err(named)?;
                limits::scalar(
                    "Joint.kind.spring.damping_ratio",
                    s.damping_ratio,
                    0.0..=MAX_RATE,
                )
                .map_err(named)?;
            }
        }
        JointKind::Spherical { cone, twist } => {
            if let Some(c) = cone
                && !(c.is_finite() && (0.0..=std::f32::consts::PI).contains(&c))
            {
                return Err(("Joint.kind.cone", format!("{c}: must be within 0..=π rad")));
            }
            if let Some(t) = twist {
                ordered("Joint.kind.twist", t, std::f32::consts::PI)?;
            }
        }
        JointKind::Fixed => {}
    }
    if j.break_force.is_nan() || j.break_force <= 0.0 {
        return Err((
            "Joint.break_force",
            format!("{}: must be > 0", j.break_force),
        ));
    }
    Ok(())
}
