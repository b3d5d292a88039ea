//! A box as a frame (centre, axes, half extents) and the face helpers box–box and
//! box–plane share: the face most against a normal, and a clipped face's points kept
//! within the margin and reduced to four.

use bevy::prelude::*;

use super::polygon::{Polygon, reduce};
use super::{Manifold, Posed};

/// A box's frame: centre, axes (columns), half extents.
#[derive(Clone, Copy)]
pub struct BoxFrame {
    pub pos: Vec3,
    pub axes: Mat3,
    pub half: Vec3,
}

impl BoxFrame {
    #[inline]
    pub fn new(p: &Posed, half: Vec3) -> Self {
        Self {
            pos: p.pos,
            axes: Mat3::from_quat(p.rot),
            half,
        }
    }
}

/// The face of `b` whose outward normal points most against `n`.
#[inline]
pub fn most_anti_parallel_face(b: &BoxFrame, n: Vec3) -> usize {
    let dots = [0, 1, 2].map(|k| b.axes.col(k).dot(n));
    let k = (0..3)
        .max_by(|&i, &j| dots[i].abs().total_cmp(&dots[j].abs()))
        .unwrap();
    // Outward normal sign·axis must point against n.
    2 * k + usize::from(dots[k] > 0.0)
}

/// Keeps the polygon's vertices within `margin` of the plane n·x = plane (measured along
/// n), reduces them to four, and adds them midway between the vertex and the plane.
#[inline]
pub fn push_face_points(
    poly: &Polygon,
    n: Vec3,
    plane: f32,
    margin: f32,
    base_id: u32,
    out: &mut Manifold,
) {
    let mut pts = [(Vec3::ZERO, 0.0, 0); 12];
    let mut len = 0;
    for i in 0..poly.len {
        let s = n.dot(poly.v[i]) - plane;
        if s <= margin {
            pts[len] = (poly.v[i] - n * (0.5 * s), s, base_id | poly.id[i]);
            len += 1;
        }
    }
    let (idx, count) = reduce(&pts[..len], n);
    for &i in &idx[..count] {
        out.push(pts[i].0, pts[i].1, pts[i].2);
    }
}
