//! Compound bodies: colliders on child entities of a `RigidBody` (and on their children,
//! down to the next body) are parts of that body. Each part is placed by the chain of
//! transforms from the body (the body's own scale included), weighs its own [`Mass`] or
//! its volume at its [`ColliderDensity`] (else the body's, else water), and the body's
//! mass, centre of mass and inertia are summed from the parts by the parallel-axis
//! theorem. The solver works in the principal frame at the centre of mass; writeback turns
//! that back into the body's `Transform`. A `Mass` on the body scales the parts to that
//! total; `AngularInertia` and `CenterOfMass` on the body override what the parts give.

use bevy::ecs::query::QueryData;
use bevy::prelude::*;

use super::FilterItem;
use crate::body::*;
use crate::collider::{Collider, Shape};
use crate::math::{part_tensor, principal_axes};
use crate::world::{ColliderEntry, ContactFilter, FixedSet, STATIC};

/// Tumble's bookkeeping: this collider is a part of the body above it, not a static
/// collider. Added by tumble; don't insert it yourself.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct BodyPart;

/// How deep below a body the walk goes: far past any real hierarchy (a glTF scene's
/// nesting is a few levels), only so that a malformed one cannot make it run forever.
/// A part below it is left out with a warning, never silently.
const MAX_DEPTH: usize = 1024;

/// What a part of a compound body reads.
#[derive(QueryData)]
pub struct PartItem {
    transform: &'static Transform,
    collider: Option<&'static Collider>,
    children: Option<&'static Children>,
    is_body: Has<RigidBody>,
    mass: Option<&'static Mass>,
    density: Option<&'static ColliderDensity>,
    friction: Option<&'static Friction>,
    restitution: Option<&'static Restitution>,
    order: Option<&'static SpawnOrder>,
    filter: FilterItem,
    marked: Has<BodyPart>,
}

/// One collider of a compound body, in the body's frame.
#[derive(Clone, Debug)]
pub struct Part {
    pub entity: Entity,
    /// Its [`SpawnOrder`] key.
    pub key: u64,
    /// Scaled by the whole chain's scale.
    pub shape: Shape,
    /// Centre and rotation in the body's frame (m, before the body's rotation).
    pub pos: Vec3,
    pub rot: Quat,
    /// Its mass, kg (before the body's `Mass` rescales the total).
    pub mass: f32,
    pub friction: f32,
    pub restitution: f32,
    pub filter: ContactFilter,
    /// Already carries [`BodyPart`].
    pub marked: bool,
}

/// The mass properties a compound body's parts add up to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summed {
    /// kg.
    pub mass: f32,
    /// Centre of mass in the body's frame, m.
    pub com: Vec3,
    /// Principal moments about the centre of mass, kg·m².
    pub moments: Vec3,
    /// The principal frame's rotation in the body's frame.
    pub frame: Quat,
}

/// The parts of one body, and the walk's stack, kept between bodies and steps so that
/// gathering a body with children allocates nothing once warm.
#[derive(Default)]
pub struct PartScratch {
    pub parts: Vec<Part>,
    stack: Vec<(Entity, Transform, usize)>,
}

impl PartScratch {
    /// Replaces `parts` with the colliders under `children`, placed in the body's frame
    /// (`scale`: the body's own world scale). Stops at entities that are bodies themselves.
    pub fn collect(
        &mut self,
        children: &Children,
        scale: Vec3,
        body_density: Option<f32>,
        query: &Query<PartItem>,
    ) {
        let Self { parts, stack } = self;
        parts.clear();
        stack.clear();
        let start = Transform::from_scale(scale);
        stack.extend(children.iter().rev().map(|c| (c, start, 1)));
        while let Some((entity, above, depth)) = stack.pop() {
            let Ok(item) = query.get(entity) else {
                continue;
            };
            if item.is_body {
                continue;
            }
            if depth > MAX_DEPTH {
                warn_once!(
                    "tumble: entity {entity} is more than {MAX_DEPTH} levels below its body; \
                     it and what is under it are left out"
                );
                continue;
            }
            let placed = above.mul_transform(*item.transform);
            if let Some(c) = item.collider {
                let shape = c.shape.scaled(placed.scale);
                let density = item
                    .density
                    .map(|d| d.0)
                    .or(body_density)
                    .unwrap_or(DEFAULT_DENSITY);
                let mass = item.mass.map_or_else(|| shape.volume() * density, |m| m.0);
                parts.push(Part {
                    entity,
                    key: item.order.map_or(u64::MAX - entity.to_bits(), |o| o.0),
                    shape,
                    pos: placed.translation,
                    rot: placed.rotation.normalize(),
                    mass,
                    friction: item.friction.map_or(DEFAULT_FRICTION, |f| f.0),
                    restitution: item.restitution.map_or(0.0, |r| r.0),
                    filter: item.filter.get(),
                    marked: item.marked,
                });
            }
            if let Some(grand) = item.children {
                stack.extend(grand.iter().rev().map(|c| (c, placed, depth + 1)));
            }
        }
    }

    /// Puts the collected parts of `owner` (a static body, or a sleeping one) into the
    /// fixed set at its pose `tf`.
    pub fn insert_fixed(&self, fixed: &mut FixedSet, owner: Entity, tf: &Transform, asleep: bool) {
        let at = (tf.translation, tf.rotation.normalize());
        for p in &self.parts {
            let entry = part_entry(p, (owner, STATIC), at, (Vec3::ZERO, Quat::IDENTITY));
            fixed.insert(ColliderEntry { asleep, ..entry });
        }
    }
}

/// The mass, centre of mass and principal inertia of `parts` together: masses add, the
/// centre is their mass-weighted mean, and each part's inertia is carried to it by the
/// parallel-axis theorem before the sum is diagonalised.
pub fn sum_parts(parts: &[Part]) -> Summed {
    let mass: f32 = parts.iter().map(|p| p.mass).sum();
    // Each part's own centre of mass (off its origin for a cone).
    let centre = |p: &Part| p.pos + p.rot * p.shape.center_of_mass();
    let com = parts.iter().map(|p| centre(p) * p.mass).sum::<Vec3>() / mass;
    let tensor = parts
        .iter()
        .map(|p| {
            // A hull's moments lie along its own principal axes.
            part_tensor(
                p.shape.principal_inertia(p.mass),
                p.rot * p.shape.principal_frame(),
                p.mass,
                centre(p) - com,
            )
        })
        .fold(Mat3::ZERO, |a, b| a + b);
    let (moments, frame) = principal_axes(tensor);
    Summed {
        mass,
        com,
        moments,
        frame,
    }
}

/// A compound body's mass properties: the parts' sum, with the body's [`Mass`] (the
/// total: the parts are scaled to it), [`AngularInertia`] (principal moments, in the
/// parts' principal frame) and [`CenterOfMass`] taking precedence.
pub fn compound_mass(
    parts: &[Part],
    mass: Option<&Mass>,
    inertia: Option<&AngularInertia>,
    com: Option<&CenterOfMass>,
) -> Summed {
    let summed = sum_parts(parts);
    let total = mass.map_or(summed.mass, |m| m.0);
    Summed {
        mass: total,
        com: com.map_or(summed.com, |c| c.0),
        moments: inertia.map_or(summed.moments * (total / summed.mass), |i| i.0),
        frame: summed.frame,
    }
}

/// The collider entry of part `p` of body `owner` (solver index `body`) whose origin is at
/// `(pos, rot)`, with its centre of mass at `com` and principal frame `frame` (both in
/// the body's frame).
pub fn part_entry(
    p: &Part,
    (owner, body): (Entity, u32),
    (pos, rot): (Vec3, Quat),
    (com, frame): (Vec3, Quat),
) -> ColliderEntry {
    let inv = frame.inverse();
    let (at, turned) = (pos + rot * p.pos, (rot * p.rot).normalize());
    ColliderEntry {
        owner,
        offset: inv * (p.pos - com),
        local_rot: (inv * p.rot).normalize(),
        friction: p.friction,
        restitution: p.restitution,
        filter: p.filter,
        ..ColliderEntry::new(p.entity, p.key, body, p.shape.clone(), at, turned)
    }
}

/// The body's own collider as a part at its origin: its volume at the body's density
/// (the body's `Mass` is the compound's total, not this part's).
pub fn own_part(
    entity: Entity,
    key: u64,
    shape: Shape,
    density: Option<&ColliderDensity>,
    (friction, restitution, filter): (f32, f32, ContactFilter),
) -> Part {
    let mass = shape.volume() * density.map_or(DEFAULT_DENSITY, |d| d.0);
    Part {
        entity,
        key,
        shape,
        pos: Vec3::ZERO,
        rot: Quat::IDENTITY,
        mass,
        friction,
        restitution,
        filter,
        marked: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(shape: Shape, pos: Vec3, mass: f32) -> Part {
        Part {
            entity: Entity::PLACEHOLDER,
            key: 0,
            shape,
            pos,
            rot: Quat::IDENTITY,
            mass,
            friction: 0.5,
            restitution: 0.0,
            filter: ContactFilter::default(),
            marked: true,
        }
    }

    #[test]
    fn two_halves_of_a_box_sum_to_the_whole_box() {
        // A 2 × 1 × 1 box of 2 kg as two 1 m cubes of 1 kg side by side.
        let cube = Shape::Cuboid {
            half_extents: Vec3::splat(0.5),
        };
        let whole = Shape::Cuboid {
            half_extents: Vec3::new(1.0, 0.5, 0.5),
        };
        let s = sum_parts(&[
            part(cube.clone(), Vec3::new(-0.5, 0.0, 0.0), 1.0),
            part(cube, Vec3::new(0.5, 0.0, 0.0), 1.0),
        ]);
        assert_eq!(s.mass, 2.0);
        assert!(s.com.length() < 1e-6);
        let expected = whole.principal_inertia(2.0);
        let turned = Mat3::from_quat(s.frame)
            * Mat3::from_diagonal(s.moments)
            * Mat3::from_quat(s.frame).transpose();
        let diff = turned - Mat3::from_diagonal(expected);
        assert!(
            diff.to_cols_array().iter().all(|x| x.abs() < 1e-5),
            "{} vs {expected}",
            s.moments
        );
    }

    #[test]
    fn a_hull_part_turns_with_its_own_axes() {
        // A long box's hull turned 30° about z, as the only part: the sum is the box's
        // inertia turned by those 30°, whatever frame the hull's own axes came out in.
        let h = Vec3::new(0.6, 0.1, 0.2);
        let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_6);
        let corners: Vec<Vec3> = (0..8)
            .map(|i| {
                let s = Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                turn * (s * h)
            })
            .collect();
        let hull = crate::collider::Collider::convex_hull(&corners)
            .unwrap()
            .shape;
        let s = sum_parts(&[part(hull, Vec3::ZERO, 3.0)]);
        let box_inertia = Shape::Cuboid { half_extents: h }.principal_inertia(3.0);
        let expected = Mat3::from_quat(turn)
            * Mat3::from_diagonal(box_inertia)
            * Mat3::from_quat(turn).transpose();
        let got = Mat3::from_quat(s.frame)
            * Mat3::from_diagonal(s.moments)
            * Mat3::from_quat(s.frame).transpose();
        let diff = got - expected;
        assert!(
            diff.to_cols_array().iter().all(|x| x.abs() < 1e-4),
            "{got} vs {expected}"
        );
    }
}
