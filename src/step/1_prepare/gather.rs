//! One body's solver state from its components: mass properties, forces, the hot and
//! cold per-body records.

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Shape;
use crate::settings::SolverSettings;
use crate::world::{BodyState, ForceModel, SolverBody, world_inv_inertia};

/// The per-body inputs of one dynamic or kinematic body.
pub(super) struct BodyInput<'a> {
    pub entity: Entity,
    pub kind: RigidBody,
    /// Where the centre of mass is (the solver's position).
    pub pos: Vec3,
    /// A sphere turning about its centre: its contact point stays under it.
    pub round: bool,
    pub rot: Quat,
    pub vel: Velocity,
    /// Mass (kg) and principal moments of inertia (kg·m²), from [`mass_properties`] or
    /// the compound's parts.
    pub mass_props: (f32, Vec3),
    pub force: Option<&'a ExternalForce>,
    pub damping: Vec2,
    pub gravity_scale: f32,
    pub rotation_locked: bool,
    /// Seconds it has been slow enough to sleep.
    pub sleep_time: f32,
    /// A kinematic body moved by its Transform, and where it gets to by the frame's end.
    pub driven: bool,
    pub target: Option<(Vec3, Quat)>,
}

/// A body's mass (kg) and principal moments of inertia (kg·m²): its [`Mass`], or its
/// collider's volume at its [`ColliderDensity`] (default [`DEFAULT_DENSITY`]); its
/// [`AngularInertia`], or that of the solid shape. A body without a collider rotates like
/// a solid ball of 0.5 m radius.
#[inline]
pub fn mass_properties(shape: Option<&Shape>, mass: &MassInput) -> (f32, Vec3) {
    let ball = Shape::Sphere { radius: 0.5 };
    let shape = shape.unwrap_or(&ball);
    let density = mass.density.map_or(DEFAULT_DENSITY, |d| d.0);
    let m = mass.mass.map_or(shape.volume() * density, |m| m.0);
    let inertia = mass
        .inertia
        .map_or_else(|| shape.principal_inertia(m), |i| i.0);
    (m, inertia)
}

/// The components that set a body's mass properties.
#[derive(Clone, Copy, Debug, Default)]
pub struct MassInput<'a> {
    pub mass: Option<&'a Mass>,
    pub density: Option<&'a ColliderDensity>,
    pub inertia: Option<&'a AngularInertia>,
}

/// Builds a body's solver state and pushes it to the hot and cold arrays. Only its own
/// `ExternalForce` goes into the force model here; gravity, drag, wind and the global push
/// are the force stage's effects.
///
/// Written straight into the arrays: built in a local and returned, the 192-byte state
/// was written field by field and read back in 16-byte pieces at once, and the reads
/// waited on the writes (store forwarding fails). With the velocity's copy, such waits
/// held 12 % of 1,000 free balls' step samples; prepare took 40 %.
#[inline]
pub(super) fn gather_body(
    b: BodyInput,
    settings: &SolverSettings,
    states: &mut Vec<BodyState>,
    solver_bodies: &mut Vec<SolverBody>,
) {
    let dynamic = b.kind == RigidBody::Dynamic;
    let (m, inertia) = b.mass_props;
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
    states.push(BodyState {
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
        round: b.round,
        in_contact: false,
        sleep_time: b.sleep_time,
        driven: b.driven,
        target: b.target,
    });
    solver_bodies.push(SolverBody {
        v,
        w,
        dp: Vec3::ZERO,
        dq: Quat::IDENTITY,
        inv_mass,
        inv_inertia: world_inv_inertia(b.rot, inv_inertia),
    });
}
