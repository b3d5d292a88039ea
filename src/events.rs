//! Collision messages and reading a body's contacts.
//!
//! Two bodies *touch* when a contact point between them overlaps or pushed this step.
//! [`CollisionStarted`] is written on the first step they touch, [`CollisionEnded`] on the
//! first step they no longer do. Read them with `MessageReader` after
//! `PhysicsSystems::Writeback`.

use bevy::platform::collections::HashSet;
use bevy::prelude::*;

use crate::step::narrow_phase::Manifold;
use crate::world::PhysicsWorld;

/// Two bodies started touching. `a` < `b` by entity order.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct CollisionStarted {
    pub a: Entity,
    pub b: Entity,
}

/// Two bodies stopped touching. `a` < `b` by entity order.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct CollisionEnded {
    pub a: Entity,
    pub b: Entity,
}

/// One body's side of a contact, for [`PhysicsWorld::contacts_of`].
#[derive(Clone, Copy, Debug)]
pub struct Contact<'a> {
    /// The other body.
    pub other: Entity,
    /// Unit normal pointing away from the body asked about, towards `other`.
    pub normal: Vec3,
    pub manifold: &'a Manifold,
}

impl PhysicsWorld {
    /// Whether a manifold's bodies touch (not merely a speculative contact).
    pub fn is_touching(m: &Manifold) -> bool {
        m.points()
            .iter()
            .any(|p| p.separation <= 0.0 || p.normal_impulse > 0.0)
    }

    /// The entities of a manifold's two colliders.
    pub fn manifold_entities(&self, m: &Manifold) -> (Entity, Entity) {
        (
            self.colliders[m.a as usize].entity,
            self.colliders[m.b as usize].entity,
        )
    }

    /// The contacts a body has as of the last step (touching ones only).
    pub fn contacts_of(&self, body: Entity) -> impl Iterator<Item = Contact<'_>> {
        self.manifolds
            .iter()
            .filter(|m| Self::is_touching(m))
            .filter_map(move |m| {
                let (a, b) = self.manifold_entities(m);
                if a == body {
                    Some(Contact {
                        other: b,
                        normal: m.normal,
                        manifold: m,
                    })
                } else if b == body {
                    Some(Contact {
                        other: a,
                        normal: -m.normal,
                        manifold: m,
                    })
                } else {
                    None
                }
            })
    }
}

/// This step's touching pairs, reused every step.
type MessageScratch = HashSet<(Entity, Entity)>;

/// Compares this step's touching pairs with last step's and writes the messages. Pairs
/// with a sleeping body keep their state: sleeping is not separating.
pub fn write_collision_messages(
    mut world: ResMut<PhysicsWorld>,
    mut started: MessageWriter<CollisionStarted>,
    mut ended: MessageWriter<CollisionEnded>,
    mut scratch: Local<MessageScratch>,
) {
    let world = &mut *world;
    // Kept between steps (cleared, not reallocated).
    let now = &mut *scratch;
    now.clear();
    for m in world
        .manifolds
        .iter()
        .filter(|m| PhysicsWorld::is_touching(m))
    {
        let (a, b) = world.manifold_entities(m);
        now.insert((a.min(b), a.max(b)));
    }
    let asleep = |e: Entity| world.fixed.get(e).is_some_and(|c| c.asleep);
    for &(a, b) in &world.touching {
        if asleep(a) || asleep(b) {
            now.insert((a, b));
        } else if !now.contains(&(a, b)) {
            ended.write(CollisionEnded { a, b });
        }
    }
    for &(a, b) in now.iter() {
        if !world.touching.contains(&(a, b)) {
            started.write(CollisionStarted { a, b });
        }
    }
    std::mem::swap(&mut world.touching, now);
}
