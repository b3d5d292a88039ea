//! Pairs with a triangle mesh or a heightfield: parry3d's composite manifolds, one per
//! triangle the other shape touches (internal edges fixed by the mesh's topology, so a
//! ball rolling across two triangles feels one flat floor). Each becomes one of our
//! manifolds, its `sub` the triangle's index so warm starting finds it next step.

use std::cell::RefCell;

use bevy::prelude::*;
use parry3d::query::{
    ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher,
};

use super::Posed;
use super::parry::{Local, point_id, pose};
use super::polygon::reduce;
use super::{MAX_POINTS, Manifold};

/// What one call needs, reused so a mesh pair allocates nothing once warm.
#[derive(Default)]
struct Scratch {
    manifolds: Vec<ContactManifold<(), ()>>,
    workspace: Option<ContactManifoldsWorkspace>,
    points: Vec<(Vec3, f32, u32)>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Collides the convex A with the mesh or heightfield B within `margin`, calling `each`
/// with one manifold per touching triangle (normal from A to B; `a`, `b` left for the
/// caller).
pub(super) fn collide(a: Posed, b: Posed, margin: f32, each: &mut dyn FnMut(Manifold)) {
    let (sa, sb) = (Local::of(a.shape), Local::of(b.shape));
    let (pa, pb) = (pose(a.pos, a.rot), pose(b.pos, b.rot));
    SCRATCH.with_borrow_mut(|s| {
        s.manifolds.clear();
        // A fresh workspace each call: the pair's triangles are found again every step.
        // (rapier keeps one per pair between steps; not done here yet.)
        s.workspace = None;
        let found = DefaultQueryDispatcher.contact_manifolds(
            &pa.inv_mul(&pb),
            sa.shape(),
            sb.shape(),
            margin,
            &mut s.manifolds,
            &mut s.workspace,
        );
        if found.is_err() {
            return;
        }
        for m in &s.manifolds {
            let normal = (pa.rotation * m.local_n1).normalize_or_zero();
            if m.points.is_empty() || normal == Vec3::ZERO {
                continue;
            }
            s.points.clear();
            for (k, c) in m.points.iter().enumerate() {
                if c.dist > margin {
                    continue;
                }
                let point = 0.5 * (pa * c.local_p1 + pb * c.local_p2);
                s.points.push((point, c.dist, point_id(c.fid1, c.fid2, k)));
            }
            if s.points.is_empty() {
                continue;
            }
            let (keep, len) = reduce(&s.points, normal);
            let mut out = Manifold {
                normal,
                sub: m.subshape2,
                ..default()
            };
            for &i in &keep[..len.min(MAX_POINTS)] {
                let (p, d, id) = s.points[i];
                out.push(p, d, id);
            }
            each(out);
        }
    });
}
