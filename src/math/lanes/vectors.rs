//! Eight 3-vectors and eight rotations in lanes ([`V3`], [`Q8`]), in any [`Lane`] type:
//! glam's arithmetic on each lane, in glam's order, so each lane is bit for bit glam's.

use bevy::prelude::*;

use super::{F8, Lane, WIDTH, lanes, neg, select};

/// Eight 3-vectors.
#[derive(Clone, Copy, Debug, Default)]
pub struct V3<L = F8> {
    pub x: L,
    pub y: L,
    pub z: L,
}

impl V3 {
    pub const ZERO: Self = Self {
        x: F8::ZERO,
        y: F8::ZERO,
        z: F8::ZERO,
    };

    /// Lane `l` set to `v`.
    #[inline(always)]
    pub fn set(&mut self, l: usize, v: Vec3) {
        self.x.as_array_mut()[l] = v.x;
        self.y.as_array_mut()[l] = v.y;
        self.z.as_array_mut()[l] = v.z;
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Vec3 {
        let (x, y, z) = (
            self.x.as_array_ref(),
            self.y.as_array_ref(),
            self.z.as_array_ref(),
        );
        Vec3::new(x[l], y[l], z[l])
    }

    /// The stored lanes as `L` lanes.
    #[inline(always)]
    pub fn get<L: Lane>(&self) -> V3<L> {
        V3 {
            x: L::load(self.x),
            y: L::load(self.y),
            z: L::load(self.z),
        }
    }
}

impl<L: Lane> V3<L> {
    #[inline(always)]
    pub fn zero() -> Self {
        Self {
            x: L::splat(0.0),
            y: L::splat(0.0),
            z: L::splat(0.0),
        }
    }

    /// The lanes as stored.
    #[inline(always)]
    pub fn put(self) -> V3 {
        V3 {
            x: self.x.store(),
            y: self.y.store(),
            z: self.z.store(),
        }
    }

    /// The lanes of eight vectors.
    #[inline(always)]
    pub fn gather(v: [Vec3; WIDTH]) -> Self {
        Self {
            x: L::load(lanes(v.map(|v| v.x))),
            y: L::load(lanes(v.map(|v| v.y))),
            z: L::load(lanes(v.map(|v| v.z))),
        }
    }

    /// `Vec3::dot`: (x·x + y·y) + z·z.
    #[inline(always)]
    pub fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `s * v` per lane.
    #[inline(always)]
    pub fn scale(self, s: L) -> Self {
        Self {
            x: s * self.x,
            y: s * self.y,
            z: s * self.z,
        }
    }

    #[inline(always)]
    pub fn add(self, o: Self) -> Self {
        Self {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    pub fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    /// `a × b` (the products in glam's order: equal bits, as products commute).
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    /// `Vec3::any_orthonormal_pair` per lane of unit vectors, in glam's operations and
    /// order (Pixar's branchless basis): the same bits. (A zero lane gives (1, 0, 0),
    /// (0, 1, 0).)
    #[inline(always)]
    pub fn any_orthonormal_pair(self) -> (Self, Self) {
        let one = L::splat(1.0);
        let sign = one | (self.z & L::splat(-0.0));
        let a = L::splat(-1.0) / (sign + self.z);
        let b = self.x * self.y * a;
        (
            Self {
                x: one + sign * self.x * self.x * a,
                y: sign * b,
                z: neg(sign) * self.x,
            },
            Self {
                x: b,
                y: sign + self.y * self.y * a,
                z: neg(self.y),
            },
        )
    }

    /// `t` where `m` is set, else `f`.
    #[inline(always)]
    pub fn select(m: L, t: Self, f: Self) -> Self {
        Self {
            x: select(m, t.x, f.x),
            y: select(m, t.y, f.y),
            z: select(m, t.z, f.z),
        }
    }
}

/// Eight rotations.
#[derive(Clone, Copy, Debug)]
pub struct Q8<L = F8> {
    pub x: L,
    pub y: L,
    pub z: L,
    pub w: L,
}

impl<L: Lane> Q8<L> {
    /// The lanes of eight rotations.
    #[inline(always)]
    pub fn gather(q: [Quat; WIDTH]) -> Self {
        Self {
            x: L::load(lanes(q.map(|q| q.x))),
            y: L::load(lanes(q.map(|q| q.y))),
            z: L::load(lanes(q.map(|q| q.z))),
            w: L::load(lanes(q.map(|q| q.w))),
        }
    }

    /// `q * v` as glam computes it on SSE2 (`Quat::mul_vec3a`):
    /// v (w² − b·b) + b (2 v·b) + (b × v)(2w), with b the vector part.
    #[inline(always)]
    pub fn rotate(self, v: V3<L>) -> V3<L> {
        let b = V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        };
        let two = L::splat(2.0);
        let b2 = b.dot(b);
        let along = v.scale(self.w * self.w - b2);
        let across = b.scale(v.dot(b) * two);
        along.add(across).add(b.cross(v).scale(self.w * two))
    }

    /// `q.conjugate() * v` as glam computes it: the inverse rotation of a unit `q`.
    #[inline(always)]
    pub fn rotate_back(self, v: V3<L>) -> V3<L> {
        let conjugate = Self {
            x: neg(self.x),
            y: neg(self.y),
            z: neg(self.z),
            w: self.w,
        };
        conjugate.rotate(v)
    }
}
