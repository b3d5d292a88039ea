//! Entities with a parent. A static collider under a parent is placed by its whole chain
//! of transforms (a glTF level's nested meshes), read at the moment it enters the fixed
//! set: `GlobalTransform` would still be the identity in the first fixed step after a
//! spawn. A collider under a `RigidBody` (a compound body) and a body under a parent that
//! is not at the origin are not supported yet: they are refused, with the reason, rather
//! than simulated in the wrong place.

use bevy::prelude::*;

use crate::body::RigidBody;

/// What walking up a hierarchy reads.
pub type ChainQuery<'w, 's> =
    Query<'w, 's, (&'static Transform, Option<&'static ChildOf>, Has<RigidBody>)>;

/// Hierarchies deeper than this are cut off (Bevy's hierarchies have no cycles; this only
/// bounds the work).
const MAX_DEPTH: usize = 64;

/// An entity's transform in the world, composed up its `ChildOf` chain, and whether an
/// ancestor is a rigid body.
pub fn world_transform(entity: Entity, chain: &ChainQuery) -> (Transform, bool) {
    let Ok((&local, mut parent, _)) = chain.get(entity) else {
        return (Transform::IDENTITY, false);
    };
    let (mut world, mut under_body) = (local, false);
    for _ in 0..MAX_DEPTH {
        let Some(p) = parent else { break };
        let Ok((&t, next, is_body)) = chain.get(p.parent()) else {
            break;
        };
        world = t.mul_transform(world);
        under_body |= is_body;
        parent = next;
    }
    (world, under_body)
}

/// Why an entity with a parent can't be simulated yet, if it can't.
pub fn unsupported(
    is_body: bool,
    has_collider: bool,
    local: &Transform,
    world: &Transform,
    under_body: bool,
) -> Option<(&'static str, String)> {
    if under_body && has_collider && !is_body {
        return Some((
            "ChildOf",
            "a collider on a child of a RigidBody (a compound body) is not supported yet".into(),
        ));
    }
    if is_body && local != world {
        return Some((
            "ChildOf",
            "a body under a parent that is not at the origin is not supported yet".into(),
        ));
    }
    None
}
