//! Entities with a parent. A static collider under a parent is placed by its whole chain
//! of transforms (a glTF level's nested meshes), read at the moment it enters the fixed
//! set: `GlobalTransform` would still be the identity in the first fixed step after a
//! spawn. A collider under a body is a part of that body (see `compound`). A body under a
//! parent is simulated in the world and written back in its
//! parent's frame: its `Transform` stays local, and a moved parent carries it along. What
//! is not supported is refused with the reason rather than simulated in the wrong place:
//! a body under another body (make them siblings), and a body under a parent scaled
//! unevenly (its frame would shear).

use bevy::prelude::*;

use crate::body::RigidBody;

/// What walking up a hierarchy reads.
pub type ChainQuery<'w, 's> =
    Query<'w, 's, (&'static Transform, Option<&'static ChildOf>, Has<RigidBody>)>;

/// How far up a chain of parents the walks go: far past any real hierarchy, only so
/// that a malformed one cannot make them run forever.
const MAX_DEPTH: usize = 1024;

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

/// The nearest ancestor that is a rigid body: the owner of a compound body's part.
pub fn owner_body(entity: Entity, chain: &ChainQuery) -> Option<Entity> {
    let mut parent = chain.get(entity).ok()?.1;
    for _ in 0..MAX_DEPTH {
        let p = parent?.parent();
        let (_, next, is_body) = chain.get(p).ok()?;
        if is_body {
            return Some(p);
        }
        parent = next;
    }
    None
}

/// The composed transform of an entity's parents (identity without a parent).
pub fn parent_frame(entity: Entity, chain: &ChainQuery) -> Transform {
    match chain.get(entity) {
        Ok((_, Some(p), _)) => world_transform(p.parent(), chain).0,
        _ => Transform::IDENTITY,
    }
}

/// Why an entity with a parent can't be simulated yet, if it can't. `parent`: the
/// composed transform of its parents.
pub fn unsupported(
    is_body: bool,
    parent: &Transform,
    under_body: bool,
) -> Option<(&'static str, String)> {
    if is_body && under_body {
        return Some((
            "ChildOf",
            "a body under another body is not supported (make them siblings)".into(),
        ));
    }
    let s = parent.scale;
    if is_body && !(s.x == s.y && s.y == s.z) {
        return Some((
            "ChildOf",
            format!("a body under a parent scaled unevenly ({s}) would shear"),
        ));
    }
    None
}
