//! Stage 1, prepare: validate bodies and gather them from the ECS into the contiguous
//! arrays of [`PhysicsWorld`]. A body with invalid input is left out, tagged with
//! [`PhysicsRejected`], and reported once in the log by entity and field.

use bevy::ecs::change_detection::Tick;
use bevy::ecs::query::QueryData;
use bevy::ecs::system::SystemChangeTick;
use bevy::prelude::*;

use crate::body::*;
use crate::collider::{Collider, Shape};
use crate::effects::{Effects, GravityScale, LockRotation};
use crate::settings::{GlobalForce, SolverSettings};
use crate::world::{BodyState, ColliderEntry, ForceModel, PhysicsWorld, STATIC, SolverBody};

/// The components prepare reads from each body or collider entity.
#[derive(QueryData)]
#[query_data(mutable)]
pub struct BodyItem {
    entity: Entity,
    transform: Ref<'static, Transform>,
    collider: Option<&'static Collider>,
    kind: Option<&'static RigidBody>,
    velocity: Option<Ref<'static, Velocity>>,
    mass: Option<&'static Mass>,
    restitution: Option<&'static Restitution>,
    friction: Option<&'static Friction>,
    force: Option<Ref<'static, ExternalForce>>,
    linear_damping: Option<&'static LinearDamping>,
    angular_damping: Option<&'static AngularDamping>,
    sleeping: Option<&'static mut Sleeping>,
    sleep_timer: Option<&'static SleepTimer>,
    gravity_scale: Option<&'static GravityScale>,
    lock_rotation: Has<LockRotation>,
}

/// Which entities prepare gathers: bodies and colliders that were not rejected.
pub type BodyQueryFilter = (
    Without<PhysicsRejected>,
    Or<(With<RigidBody>, With<Collider>)>,
);

/// Gathers every valid body and collider into [`PhysicsWorld`] for this step. A sleeping
/// body goes in as a static collider, unless the user changed it since it fell asleep.
#[allow(clippy::too_many_arguments)]
pub fn prepare_bodies(
    mut commands: Commands,
    mut world: ResMut<PhysicsWorld>,
    time: Res<Time<Fixed>>,
    global: Res<GlobalForce>,
    effects: Res<Effects>,
    settings: Res<SolverSettings>,
    ticks: SystemChangeTick,
    mut query: Query<BodyItem, BodyQueryFilter>,
) {
    let world = &mut *world;
    // The fixed step's length, also when a paused app single-steps.
    world.dt = time.timestep().as_secs_f32();
    world.solver_bodies.clear();
    world.bodies.clear();
    world.colliders.clear();
    world.wake.clear();
    // Filled by the collision stages only when collisions are on.
    world.pairs.clear();
    world.manifolds.clear();

    for item in &mut query {
        let entity = item.entity;
        let tf = *item.transform;
        let kind = item.kind.copied().unwrap_or(RigidBody::Static);
        let vel = match (&item.velocity, kind) {
            (Some(v), RigidBody::Dynamic | RigidBody::Kinematic) => **v,
            _ => Velocity::ZERO,
        };
        let shape = item.collider.map(|c| c.shape);
        let checked = validate(&tf, &vel, kind, item.mass, shape.as_ref())
            .and_then(|()| validate_force(item.force.as_deref()));
        if let Err((field, reason)) = checked {
            error!(
                "tumble: body {entity} left out of the simulation: {field} is invalid ({reason})"
            );
            commands
                .entity(entity)
                .insert(PhysicsRejected { field, reason });
            continue;
        }
        let mut asleep = false;
        if let Some(mut sleeping) = item.sleeping {
            if sleeping.is_added() {
                sleeping.since = ticks.this_run();
            }
            let since = sleeping.since;
            let touched = |t: Tick| t.is_newer_than(since, ticks.this_run());
            let user_changed = touched(item.transform.last_changed())
                || item
                    .velocity
                    .as_ref()
                    .is_some_and(|v| touched(v.last_changed()))
                || item
                    .force
                    .as_ref()
                    .is_some_and(|f| touched(f.last_changed()));
            let pushed = effects.global_force && global.0 != Vec3::ZERO;
            if effects.sleeping && !user_changed && !pushed {
                asleep = true;
            } else {
                commands.entity(entity).remove::<Sleeping>();
            }
        }
        let rot = tf.rotation.normalize();
        let body = if kind == RigidBody::Static || asleep {
            STATIC
        } else {
            let index = world.bodies.len() as u32;
            let input = BodyInput {
                entity,
                kind,
                pos: tf.translation,
                rot,
                vel,
                mass: item.mass,
                shape,
                force: item.force.as_deref(),
                damping: Vec2::new(
                    item.linear_damping.map_or(0.0, |d| d.0),
                    item.angular_damping.map_or(0.0, |d| d.0),
                ),
                gravity_scale: item.gravity_scale.map_or(1.0, |g| g.0),
                rotation_locked: item.lock_rotation || !effects.rotation,
            };
            let (mut state, solver) = gather_body(input, &settings);
            state.sleep_time = item.sleep_timer.map_or(0.0, |t| t.0);
            world.bodies.push(state);
            world.solver_bodies.push(solver);
            index
        };
        if let Some(shape) = shape {
            world.colliders.push(ColliderEntry {
                entity,
                body,
                asleep,
                shape,
                pos: tf.translation,
                rot,
                friction: item.friction.map_or(DEFAULT_FRICTION, |f| f.0),
                restitution: item.restitution.map_or(0.0, |r| r.0),
                aabb_min: Vec3::ZERO,
                aabb_max: Vec3::ZERO,
            });
        }
    }
}

/// The per-body inputs of one dynamic or kinematic body.
struct BodyInput<'a> {
    entity: Entity,
    kind: RigidBody,
    pos: Vec3,
    rot: Quat,
    vel: Velocity,
    mass: Option<&'a Mass>,
    shape: Option<Shape>,
    force: Option<&'a ExternalForce>,
    damping: Vec2,
    gravity_scale: f32,
    rotation_locked: bool,
}

/// Builds a body's solver state. Only its own `ExternalForce` goes into the force model
/// here; gravity, drag, wind and the global push are the force stage's effects.
fn gather_body(b: BodyInput, settings: &SolverSettings) -> (BodyState, SolverBody) {
    // A dynamic body without a collider rotates like a solid ball of 0.5 m radius.
    let shape = b.shape.unwrap_or(Shape::Sphere { radius: 0.5 });
    let dynamic = b.kind == RigidBody::Dynamic;
    let m = b.mass.map_or(shape.volume() * DEFAULT_DENSITY, |m| m.0);
    let inertia = shape.principal_inertia(m);
    let inv_mass = if dynamic { 1.0 / m } else { 0.0 };
    let inv_inertia = if dynamic && !b.rotation_locked {
        inertia.recip()
    } else {
        Vec3::ZERO
    };
    let forces = match (dynamic, b.force) {
        (true, Some(f)) => ForceModel {
            accel: f.force * inv_mass,
            torque: f.torque,
            ..default()
        },
        _ => ForceModel::default(),
    };
    let v = b.vel.linear.clamp_length_max(settings.max_linear_speed);
    let w = if b.rotation_locked {
        Vec3::ZERO
    } else {
        b.vel.angular
    };
    let state = BodyState {
        entity: b.entity,
        kind: b.kind,
        x0: b.pos,
        q0: b.rot,
        v0: v,
        w0: w,
        inertia,
        inv_inertia,
        forces,
        damping: if dynamic {
            b.damping.max(Vec2::ZERO)
        } else {
            Vec2::ZERO
        },
        gravity_scale: b.gravity_scale,
        rotation_locked: b.rotation_locked && dynamic,
        in_contact: false,
        sleep_time: 0.0,
    };
    let solver = SolverBody {
        v,
        w,
        dp: Vec3::ZERO,
        dq: Quat::IDENTITY,
        inv_mass,
        inv_inertia: world_inv_inertia(b.rot, inv_inertia),
    };
    (state, solver)
}

/// R · diag(inv_principal) · Rᵀ.
pub fn world_inv_inertia(rot: Quat, inv_principal: Vec3) -> Mat3 {
    let r = Mat3::from_quat(rot);
    r * Mat3::from_diagonal(inv_principal) * r.transpose()
}

/// Checks one body's input. Returns the offending field and why.
pub fn validate(
    tf: &Transform,
    vel: &Velocity,
    kind: RigidBody,
    mass: Option<&Mass>,
    shape: Option<&Shape>,
) -> Result<(), (&'static str, String)> {
    if !tf.translation.is_finite() {
        return Err(("Transform.translation", format!("{}", tf.translation)));
    }
    if !tf.rotation.is_finite() || tf.rotation.length_squared() < 1e-12 {
        return Err(("Transform.rotation", format!("{:?}", tf.rotation)));
    }
    if !vel.linear.is_finite() {
        return Err(("Velocity.linear", format!("{}", vel.linear)));
    }
    if !vel.angular.is_finite() {
        return Err(("Velocity.angular", format!("{}", vel.angular)));
    }
    if let Some(m) = mass.filter(|m| kind == RigidBody::Dynamic && !(m.0.is_finite() && m.0 > 0.0))
    {
        return Err(("Mass", format!("{} kg: mass must be finite and > 0", m.0)));
    }
    if let Some(shape) = shape {
        shape
            .validate()
            .map_err(|r| ("Collider", format!("{r}: sizes must be finite and > 0")))?;
        if kind == RigidBody::Dynamic && matches!(shape, Shape::Plane { .. }) {
            return Err(("Collider", "a plane can only be static or kinematic".into()));
        }
    }
    Ok(())
}

fn validate_force(force: Option<&ExternalForce>) -> Result<(), (&'static str, String)> {
    match force {
        Some(f) if !(f.force.is_finite() && f.torque.is_finite()) => Err((
            "ExternalForce",
            format!("force {} torque {}", f.force, f.torque),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(
        tf: Transform,
        vel: Velocity,
        mass: Option<f32>,
        shape: Shape,
    ) -> Option<&'static str> {
        let mass = mass.map(Mass);
        validate(&tf, &vel, RigidBody::Dynamic, mass.as_ref(), Some(&shape))
            .err()
            .map(|e| e.0)
    }

    #[test]
    fn each_bad_field_is_named() {
        let s = Collider::sphere(1.0).shape;
        let v = Velocity::ZERO;
        assert_eq!(
            check(Transform::from_xyz(f32::NAN, 0., 0.), v, None, s),
            Some("Transform.translation")
        );
        let bad_rot = Transform {
            rotation: Quat::from_xyzw(0., f32::INFINITY, 0., 1.),
            ..default()
        };
        assert_eq!(check(bad_rot, v, None, s), Some("Transform.rotation"));
        let fast = Velocity::linear(Vec3::new(0., f32::INFINITY, 0.));
        assert_eq!(
            check(Transform::IDENTITY, fast, None, s),
            Some("Velocity.linear")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(0.0), s), Some("Mass"));
        assert_eq!(check(Transform::IDENTITY, v, Some(-2.0), s), Some("Mass"));
        assert_eq!(
            check(Transform::IDENTITY, v, Some(f32::NAN), s),
            Some("Mass")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, Collider::sphere(-1.0).shape),
            Some("Collider")
        );
        assert_eq!(
            check(Transform::IDENTITY, v, None, Collider::plane().shape),
            Some("Collider")
        );
        assert_eq!(check(Transform::IDENTITY, v, Some(1.0), s), None);
    }
}
