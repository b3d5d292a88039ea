//! Contact polygons: a box face as a quad, Sutherland–Hodgman clipping with feature ids,
//! and the reduction of a clipped polygon to at most four points.

use bevy::prelude::*;

use super::MAX_POINTS;

/// Enough room for a quad clipped by four planes (at most 8 vertices) and then some.
const CAP: usize = 12;

/// A convex polygon whose vertices carry feature ids.
#[derive(Clone, Copy, Debug)]
pub struct Polygon {
    pub v: [Vec3; CAP],
    pub id: [u32; CAP],
    pub len: usize,
}

impl Default for Polygon {
    fn default() -> Self {
        Self {
            v: [Vec3::ZERO; CAP],
            id: [0; CAP],
            len: 0,
        }
    }
}

impl Polygon {
    pub fn push(&mut self, v: Vec3, id: u32) {
        if self.len < CAP {
            self.v[self.len] = v;
            self.id[self.len] = id;
            self.len += 1;
        }
    }

    /// [`clip_into`](Self::clip_into) a new polygon.
    #[cfg(test)]
    pub fn clip(&self, n: Vec3, d: f32, tag: u32) -> Polygon {
        let mut out = Polygon::default();
        self.clip_into(n, d, tag, &mut out);
        out
    }

    /// This polygon kept inside two slabs, each side's (axis, centre offset c = axis·centre,
    /// half width): clipped by the planes axis·x ≤ c + w and −axis·x ≤ −c + w, tagged
    /// 2k and 2k + 1 for slab k, between two buffers (no polygon zeroed and copied out per
    /// cut; see [`clip_into`](Self::clip_into)).
    pub fn clip_to_slabs(mut self, slabs: [(Vec3, f32, f32); 2]) -> Polygon {
        let mut cuts = [(Vec3::ZERO, 0.0, 0); 4];
        for (k, (axis, c, w)) in slabs.into_iter().enumerate() {
            cuts[2 * k] = (axis, c + w, 2 * k as u32);
            cuts[2 * k + 1] = (-axis, -c + w, 2 * k as u32 + 1);
        }
        let mut spare = Polygon::default();
        let (mut src, mut dst) = (&mut self, &mut spare);
        for (n, d, tag) in cuts {
            src.clip_into(n, d, tag, dst);
            std::mem::swap(&mut src, &mut dst);
        }
        *src
    }

    /// Keeps the part with n·x ≤ d, in `out` (its vertices replaced). A vertex made by
    /// cutting the edge a→b gets an id built from `tag` (which plane) and the low bits of
    /// a's and b's ids, so it stays the same while the same edge crosses the same plane.
    fn clip_into(&self, n: Vec3, d: f32, tag: u32, out: &mut Polygon) {
        out.len = 0;
        for i in 0..self.len {
            let j = (i + 1) % self.len;
            let (a, b) = (self.v[i], self.v[j]);
            let (da, db) = (n.dot(a) - d, n.dot(b) - d);
            if da <= 0.0 {
                out.push(a, self.id[i]);
            }
            if (da <= 0.0) != (db <= 0.0) {
                let t = da / (da - db);
                let id = 0x8000 | (tag << 8) | ((self.id[i] & 0xF) << 4) | (self.id[j] & 0xF);
                out.push(a + (b - a) * t, id);
            }
        }
    }
}

/// The corner of a box with half extents `h` picked by the sign bits of `id` (bit k set:
/// + along axis k), in the box frame.
pub fn corner(h: Vec3, id: u32) -> Vec3 {
    let s = |k: u32| if id & (1 << k) != 0 { 1.0 } else { -1.0 };
    Vec3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z)
}

/// Face `f` of a box (axis f/2, + side for even f) as a quad in world space, its vertices
/// in order around the face, ids = corner ids.
pub fn box_face(pos: Vec3, rot: Mat3, h: Vec3, f: usize) -> Polygon {
    let (k, sign) = (f / 2, f.is_multiple_of(2));
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let mut poly = Polygon::default();
    for (su, sv) in [(1, 1), (0, 1), (0, 0), (1, 0)] {
        let id = (u32::from(sign) << k) | (su << u) | (sv << v);
        poly.push(pos + rot * corner(h, id), id);
    }
    poly
}

/// Picks at most [`MAX_POINTS`] of `points` (position, separation, id) that keep the
/// contact area: the deepest, the farthest from it, then the two that span the largest
/// triangles on either side of that line.
pub fn reduce(points: &[(Vec3, f32, u32)], normal: Vec3) -> ([usize; MAX_POINTS], usize) {
    let n = points.len();
    if n <= MAX_POINTS {
        let mut idx = [0; MAX_POINTS];
        for (i, slot) in idx.iter_mut().enumerate().take(n) {
            *slot = i;
        }
        return (idx, n);
    }
    let deepest = (0..n)
        .min_by(|&a, &b| points[a].1.total_cmp(&points[b].1))
        .unwrap();
    let p0 = points[deepest].0;
    let far = (0..n)
        .max_by(|&a, &b| {
            (points[a].0 - p0)
                .length_squared()
                .total_cmp(&(points[b].0 - p0).length_squared())
        })
        .unwrap();
    let p1 = points[far].0;
    let area = |i: usize| (p1 - p0).cross(points[i].0 - p0).dot(normal);
    let left = (0..n).max_by(|&a, &b| area(a).total_cmp(&area(b))).unwrap();
    let right = (0..n).min_by(|&a, &b| area(a).total_cmp(&area(b))).unwrap();
    let mut idx = [deepest, far, left, right];
    // Drop repeats (degenerate, e.g. all points on a line).
    let mut len = 0;
    for i in 0..MAX_POINTS {
        if !idx[..len].contains(&idx[i]) {
            idx[len] = idx[i];
            len += 1;
        }
    }
    (idx, len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_a_square_by_a_plane_halves_it() {
        let sq = box_face(Vec3::ZERO, Mat3::IDENTITY, Vec3::ONE, 2); // +Y face
        let half = sq.clip(Vec3::X, 0.0, 1);
        assert_eq!(half.len, 4);
        assert!(half.v[..half.len].iter().all(|v| v.x <= 1e-6 && v.y == 1.0));
        let ids: Vec<_> = half.id[..half.len]
            .iter()
            .filter(|&&i| i & 0x8000 != 0)
            .collect();
        assert_eq!(ids.len(), 2, "two new vertices with clip ids");
    }

    #[test]
    fn reduce_keeps_the_corners_of_an_octagon() {
        let pts: Vec<_> = (0..8)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 8.0;
                (
                    Vec3::new(a.cos(), 0.0, a.sin()),
                    if k == 3 { -0.2 } else { -0.1 },
                    k,
                )
            })
            .collect();
        let (idx, len) = reduce(&pts, Vec3::Y);
        assert_eq!(len, 4);
        assert!(idx.contains(&3), "deepest kept");
        assert!(idx.contains(&7), "farthest from the deepest kept");
    }
}
