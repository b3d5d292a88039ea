//! Collision events and reading a body's contacts.
//!
//! Two colliders *touch* when a contact point between them overlaps or pushed this step
//! (for a [`Sensor`](crate::layers::Sensor): when they overlap), and keep touching while
//! a point stays within a slop of 5 mm (a quarter of the pair's speculative margin,
//! less for bodies under 4 cm), so a
//! landing that rebounds a millimetre is one collision. Events are opt-in per
//! collider, as in avian3d and bevy_rapier3d: a pair is reported when either collider
//! has [`CollisionEventsEnabled`], so a scene with thousands of contacts and no one
//! listening pays one flag test per contact.
//!
//! - [`CollisionStart`] on the first step a pair touches, [`CollisionEnd`] on the first
//!   step it no longer does. Each is a **message** (one per pair, `collider1` the lower
//!   entity; read with `MessageReader` after `PhysicsSystems::Writeback`) and an
//!   **entity event** triggered on every collider of the pair that has events enabled,
//!   with itself as `collider1`:
//!   `commands.entity(e).observe(|hit: On<CollisionStart>| …)`.
//! - Events never name a despawned entity: a pair whose collider was despawned ends
//!   silently. Sleeping is not separating: a pair that falls asleep touching stays
//!   started.
//! - [`CollisionStart::contact`] tells what the hit was like: points, normal, depth, the
//!   step's impulses and the speed of impact (for sounds and damage).

use bevy::ecs::entity::Entities;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use crate::settings::{CONTINUOUS_SLOP, SolverSettings};
use crate::world::PhysicsWorld;
use crate::world::{MAX_POINTS, Manifold};

/// Opts a collider in to [`CollisionStart`] / [`CollisionEnd`]: as messages for its
/// pairs, and as entity events on itself.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub struct CollisionEventsEnabled;

/// What a contact was like in the step it started.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactData {
    /// Unit normal pointing from `collider1` towards `collider2`.
    pub normal: Vec3,
    /// Contact points (world, start of the step); the first `len` are used.
    pub points: [Vec3; MAX_POINTS],
    /// How many of `points` are used, at most 4.
    pub len: usize,
    /// Deepest overlap at the start of the step, m (0 when it only just touched).
    pub penetration: f32,
    /// Normal impulse on `collider2` over the step, N·s (the same, opposite, on
    /// `collider1`); divided by the step, the mean contact force. 0 for sensors.
    pub normal_impulse: f32,
    /// Friction impulse on `collider2` over the step, world frame, N·s.
    pub friction_impulse: Vec3,
    /// How fast the surfaces approached at impact, m/s (the fastest point).
    pub impact_speed: f32,
}

impl ContactData {
    /// The contact points.
    pub fn points(&self) -> &[Vec3] {
        &self.points[..self.len]
    }

    /// The data of a manifold, seen from A (`flip`: from B).
    fn of(m: &Manifold, flip: bool) -> Self {
        let sign = if flip { -1.0 } else { 1.0 };
        let mut data = Self {
            normal: m.normal * sign,
            len: m.len,
            ..default()
        };
        for (i, p) in m.points().iter().enumerate() {
            data.points[i] = p.point;
            data.penetration = data.penetration.max(-p.separation);
            data.normal_impulse += p.total_normal_impulse;
            data.friction_impulse += p.total_tangent_impulse * sign;
            data.impact_speed = data.impact_speed.max(p.approach_speed);
        }
        data
    }
}

/// Two colliders started touching. As a message, one per pair with `collider1` the lower
/// entity; as an entity event, on each collider with [`CollisionEventsEnabled`], which
/// is then `collider1`.
#[derive(Message, EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct CollisionStart {
    /// The lower entity of the pair; in an entity event, the collider it is triggered on.
    #[event_target]
    pub collider1: Entity,
    /// The other collider.
    pub collider2: Entity,
    /// The colliders' bodies: the collider itself, the body above a compound body's part,
    /// or `None` for a static collider.
    pub body1: Option<Entity>,
    /// `collider2`'s body: the collider itself, or `None` for a static collider.
    pub body2: Option<Entity>,
    /// One of them is a sensor: an overlap, not a contact.
    pub sensor: bool,
    /// What the contact was like in the step it started.
    pub contact: ContactData,
}

/// Two colliders stopped touching (or one lost its collider, or the pair's layers
/// stopped matching). Sent like [`CollisionStart`]; never for a despawned collider.
#[derive(Message, EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct CollisionEnd {
    /// The lower entity of the pair; in an entity event, the collider it is triggered on.
    #[event_target]
    pub collider1: Entity,
    /// The other collider.
    pub collider2: Entity,
    /// `collider1`'s body: the collider itself, or `None` for a static collider.
    pub body1: Option<Entity>,
    /// `collider2`'s body: the collider itself, or `None` for a static collider.
    pub body2: Option<Entity>,
    /// One of them is a sensor: an overlap ended, not a contact.
    pub sensor: bool,
}

/// One body's side of a touching contact, for [`PhysicsWorld::contacts_of`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The other collider.
    pub other: Entity,
    /// Unit normal pointing away from the body asked about, towards `other`.
    pub normal: Vec3,
    /// Contact points (world, start of the last step); the first `len` are used.
    pub points: [Vec3; MAX_POINTS],
    /// How many of `points` are used, at most 4.
    pub len: usize,
    /// Deepest overlap at the start of the last step, m (0 when it only just touched).
    pub penetration: f32,
    /// The normal force between the two at the end of the last step, N: the last
    /// substep's impulses over its length. A box of mass m resting on the ground reads
    /// m·|g|.
    pub normal_force: f32,
}

impl Contact {
    /// The contact points.
    pub fn points(&self) -> &[Vec3] {
        &self.points[..self.len]
    }
}

impl PhysicsWorld {
    /// Whether a manifold's bodies touch (not merely a speculative contact).
    pub(crate) fn is_touching(m: &Manifold) -> bool {
        m.points()
            .iter()
            .any(|p| p.separation <= 0.0 || p.normal_impulse > 0.0)
    }

    /// The entities of a manifold's two colliders.
    pub(crate) fn manifold_entities(&self, m: &Manifold) -> (Entity, Entity) {
        (
            self.colliders[m.a as usize].entity,
            self.colliders[m.b as usize].entity,
        )
    }

    /// The contacts a collider has as of the last step (touching ones only); for a
    /// compound body's entity, those of all its colliders. Sleeping bodies' contacts are
    /// not kept: a sleeper has none until it wakes.
    pub fn contacts_of(&self, collider: Entity) -> impl Iterator<Item = Contact> + '_ {
        let h = self.last_substep;
        self.manifolds
            .iter()
            .filter(|m| Self::is_touching(m))
            .filter_map(move |m| {
                let (a, b) = self.manifold_entities(m);
                let (oa, ob) = (
                    self.colliders[m.a as usize].owner,
                    self.colliders[m.b as usize].owner,
                );
                let (other, sign) = if a == collider || (oa == collider && ob != collider) {
                    (b, 1.0)
                } else if b == collider || (ob == collider && oa != collider) {
                    (a, -1.0)
                } else {
                    return None;
                };
                let mut c = Contact {
                    other,
                    normal: m.normal * sign,
                    points: [Vec3::ZERO; MAX_POINTS],
                    len: m.len,
                    penetration: 0.0,
                    normal_force: 0.0,
                };
                for (i, p) in m.points().iter().enumerate() {
                    c.points[i] = p.point;
                    c.penetration = c.penetration.max(-p.separation);
                    c.normal_force += p.normal_impulse;
                }
                c.normal_force = if h > 0.0 { c.normal_force / h } else { 0.0 };
                Some(c)
            })
    }
}

/// A pair that touched last step: the two colliders (lower entity first), whether each
/// wants entity events and has a body, and whether a sensor is involved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct TouchingPair {
    /// The two colliders, lower entity first.
    pub colliders: (Entity, Entity),
    /// Whether each has [`CollisionEventsEnabled`].
    pub events: (bool, bool),
    /// Each one's body (`None`: a static collider).
    pub bodies: (Option<Entity>, Option<Entity>),
    /// One of them is a sensor.
    pub sensor: bool,
}

impl TouchingPair {
    fn flipped(self) -> Self {
        fn swap<T>((a, b): (T, T)) -> (T, T) {
            (b, a)
        }
        Self {
            colliders: swap(self.colliders),
            events: swap(self.events),
            bodies: swap(self.bodies),
            sensor: self.sensor,
        }
    }

    fn start(self, contact: ContactData) -> CollisionStart {
        let (c1, c2) = self.colliders;
        CollisionStart {
            collider1: c1,
            collider2: c2,
            body1: self.bodies.0,
            body2: self.bodies.1,
            sensor: self.sensor,
            contact,
        }
    }

    fn end(self) -> CollisionEnd {
        let (c1, c2) = self.colliders;
        CollisionEnd {
            collider1: c1,
            collider2: c2,
            body1: self.bodies.0,
            body2: self.bodies.1,
            sensor: self.sensor,
        }
    }
}

/// Scratch kept between steps: this step's reported pairs with their contact data, and
/// a spare map to swap with `PhysicsWorld::touching`.
#[derive(Default)]
pub(crate) struct ReportScratch {
    now: Vec<(TouchingPair, ContactData)>,
    ends: Vec<TouchingPair>,
    spare: HashMap<(Entity, Entity), TouchingPair>,
}

/// Compares this step's touching pairs (of colliders with events enabled) with last
/// step's, writes the messages and triggers the entity events.
pub(crate) fn report_collisions(
    mut world: ResMut<PhysicsWorld>,
    mut started: MessageWriter<CollisionStart>,
    mut ended: MessageWriter<CollisionEnd>,
    mut commands: Commands,
    entities: &Entities,
    settings: Res<SolverSettings>,
    mut scratch: Local<ReportScratch>,
) {
    let world = &mut *world;
    let ReportScratch { now, ends, spare } = &mut *scratch;
    now.clear();
    // No collider asks for events and none was touching: nothing to report, and no
    // walk over every manifold (0.27 ms a step on the 5,050-cube pyramid). The same
    // early return as below, found without the walk.
    if world.touching.is_empty() && !world.colliders.iter().any(|c| c.filter.events) {
        return;
    }
    // A pair that touched stays touching while a point is within the slop: a landing
    // that rebounds a millimetre for a step is one collision, not three events.
    // The slop is a quarter of the pair's margin: 5 mm, less for bodies under 4 cm.
    let previous = &world.touching;
    let colliders = &world.colliders;
    let slop = |m: &Manifold| {
        let (a, b) = (&colliders[m.a as usize], &colliders[m.b as usize]);
        CONTINUOUS_SLOP * settings.margin_for(a.shape.pair_thickness(&b.shape))
    };
    let contacts = world.manifolds.iter().filter(|m| {
        PhysicsWorld::is_touching(m)
            || (m.points().iter().any(|p| p.separation <= slop(m))
                && previous.contains_key(&ordered(
                    colliders[m.a as usize].entity,
                    colliders[m.b as usize].entity,
                )))
    });
    let overlaps = world
        .sensor_overlaps
        .iter()
        .filter(|m| m.points().iter().any(|p| p.separation <= 0.0));
    for (m, sensor) in contacts
        .map(|m| (m, false))
        .chain(overlaps.map(|m| (m, true)))
    {
        let (a, b) = (
            &world.colliders[m.a as usize],
            &world.colliders[m.b as usize],
        );
        if !(a.filter.events || b.filter.events) {
            continue;
        }
        let pair = TouchingPair {
            colliders: (a.entity, b.entity),
            events: (a.filter.events, b.filter.events),
            bodies: (a.body_entity(), b.body_entity()),
            sensor,
        };
        let flip = a.entity > b.entity;
        let pair = if flip { pair.flipped() } else { pair };
        now.push((pair, ContactData::of(m, flip)));
    }
    if now.is_empty() && world.touching.is_empty() {
        return;
    }
    let previous = std::mem::replace(&mut world.touching, std::mem::take(spare));
    let next = &mut world.touching;
    next.clear();
    for &(pair, contact) in now.iter() {
        // A pair with a mesh can have several manifolds (one per triangle): one event.
        if !previous.contains_key(&pair.colliders) && !next.contains_key(&pair.colliders) {
            started.write(pair.start(contact));
            trigger_both(&mut commands, pair, |p| p.start(contact));
        }
        next.insert(pair.colliders, pair);
    }
    // A pair of two fixed colliders (static or asleep) is not looked at: it keeps its
    // state, since sleeping is not separating. A pair with an awake side was.
    let fixed = |e: Entity| world.fixed.contains(e);
    for (&(a, b), &pair) in previous.iter() {
        if next.contains_key(&(a, b)) {
            continue;
        }
        if fixed(a) && fixed(b) {
            next.insert((a, b), pair);
        } else if entities.contains(a) && entities.contains(b) {
            ends.push(pair);
        }
    }
    // In a fixed order, not the map's.
    ends.sort_unstable_by_key(|p| p.colliders);
    for &pair in ends.iter() {
        ended.write(pair.end());
        trigger_both(&mut commands, pair, |p| p.end());
    }
    ends.clear();
    *spare = previous;
}

/// The pair's key: lower entity first.
fn ordered(a: Entity, b: Entity) -> (Entity, Entity) {
    (a.min(b), a.max(b))
}

/// Triggers `event` on each collider of the pair that asked for events, with itself as
/// `collider1`.
fn trigger_both<E>(commands: &mut Commands, pair: TouchingPair, event: impl Fn(TouchingPair) -> E)
where
    E: EntityEvent + for<'a> Event<Trigger<'a> = bevy::ecs::event::EntityTrigger>,
{
    if pair.events.0 {
        commands.trigger(event(pair));
    }
    if pair.events.1 {
        commands.trigger(event(pair.flipped()));
    }
}
