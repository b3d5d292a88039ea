//! Sphere–sphere: the normal joins the centres.

use bevy::prelude::*;

use super::{Manifold, Posed};

pub fn collide(a: Posed, ra: f32, b: Posed, rb: f32, margin: f32, out: &mut Manifold) {
    let d = b.pos - a.pos;
    let dist = d.length();
    let s = dist - ra - rb;
    if s > margin {
        return;
    }
    out.normal = if dist > 1e-9 { d / dist } else { Vec3::Y };
    let on_a = a.pos + out.normal * ra;
    let on_b = b.pos - out.normal * rb;
    out.push(0.5 * (on_a + on_b), s, 0);
}
