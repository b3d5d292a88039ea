//! Four of everything at once: vectors and rotations whose components are `f32x4` lanes
//! (one lane per independent contact), for the solver's batches. Each operation does,
//! lane by lane, exactly the arithmetic glam does on one value, in the same order and
//! without fused multiply-adds, so a lane's result is bit for bit the scalar one.

use bevy::prelude::*;
use wide::{CmpEq, CmpGt, CmpLe, CmpLt, f32x4};

/// Four floats, one per lane.
pub type F4 = f32x4;

/// The CPU has AVX2. Hot loops are compiled twice, and on such a CPU run the copy that
/// uses the three-operand (VEX) forms of the same SSE operations, which save the register
/// copies the two-operand forms need. The operations are the same, with no fused
/// multiply-add (that needs the `fma` feature, which is not enabled): the same bits. (The
/// batched pass: a sixth fewer instructions on the 385-cube pyramid.) The answer is cached
/// by std.
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn three_operand() -> bool {
    #[cfg(test)]
    if PLAIN_ONLY.get() {
        return false;
    }
    std::is_x86_feature_detected!("avx2")
}

#[cfg(test)]
thread_local! {
    /// Tests set it to run the plain copies of the hot loops on a CPU that has the
    /// features for the others, so that each copy is checked against the reference.
    pub static PLAIN_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The lanes of four values.
#[inline(always)]
pub fn lanes(v: [f32; 4]) -> F4 {
    F4::new(v)
}

/// `t` where `m` is set, else `f`.
#[inline(always)]
pub fn select(m: F4, t: F4, f: F4) -> F4 {
    m.blend(t, f)
}

/// Lanes `a < b`.
#[inline(always)]
pub fn lt(a: F4, b: F4) -> F4 {
    a.cmp_lt(b)
}

/// Lanes `a <= b`.
#[inline(always)]
pub fn le(a: F4, b: F4) -> F4 {
    a.cmp_le(b)
}

/// Lanes `a == b`.
#[inline(always)]
pub fn eq(a: F4, b: F4) -> F4 {
    a.cmp_eq(b)
}

/// Lanes `a > b`.
#[inline(always)]
pub fn gt(a: F4, b: F4) -> F4 {
    a.cmp_gt(b)
}

/// `-x` per lane, as f32 negates: the sign bit flipped (wide's `-x` is `0 − x`, which
/// turns −0 into +0).
#[inline(always)]
pub fn neg(x: F4) -> F4 {
    x ^ F4::splat(-0.0)
}

/// `f32::max` per lane (a NaN lane takes the other value).
#[inline(always)]
pub fn max(a: F4, b: F4) -> F4 {
    a.max(b)
}

/// `f32::clamp` per lane, for `lo <= hi`.
#[inline(always)]
pub fn clamp(x: F4, lo: F4, hi: F4) -> F4 {
    let x = select(lt(x, lo), lo, x);
    select(gt(x, hi), hi, x)
}

/// Four 3-vectors.
#[derive(Clone, Copy, Debug)]
pub struct V3 {
    pub x: F4,
    pub y: F4,
    pub z: F4,
}

impl V3 {
    pub const ZERO: Self = Self {
        x: F4::ZERO,
        y: F4::ZERO,
        z: F4::ZERO,
    };

    /// The lanes of four vectors.
    #[inline(always)]
    pub fn gather(v: [Vec3; 4]) -> Self {
        Self {
            x: lanes([v[0].x, v[1].x, v[2].x, v[3].x]),
            y: lanes([v[0].y, v[1].y, v[2].y, v[3].y]),
            z: lanes([v[0].z, v[1].z, v[2].z, v[3].z]),
        }
    }

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
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        Vec3::new(x[l], y[l], z[l])
    }

    /// `Vec3::dot`: (x·x + y·y) + z·z.
    #[inline(always)]
    pub fn dot(self, o: Self) -> F4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `s * v` per lane.
    #[inline(always)]
    pub fn scale(self, s: F4) -> Self {
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
        let sign = F4::ONE | (self.z & F4::splat(-0.0));
        let a = F4::splat(-1.0) / (sign + self.z);
        let b = self.x * self.y * a;
        (
            Self {
                x: F4::ONE + sign * self.x * self.x * a,
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
    pub fn select(m: F4, t: Self, f: Self) -> Self {
        Self {
            x: select(m, t.x, f.x),
            y: select(m, t.y, f.y),
            z: select(m, t.z, f.z),
        }
    }
}

/// Four rotations.
#[derive(Clone, Copy, Debug)]
pub struct Q4 {
    pub x: F4,
    pub y: F4,
    pub z: F4,
    pub w: F4,
}

impl Q4 {
    /// The lanes of four rotations.
    #[inline(always)]
    pub fn gather(q: [Quat; 4]) -> Self {
        Self {
            x: lanes([q[0].x, q[1].x, q[2].x, q[3].x]),
            y: lanes([q[0].y, q[1].y, q[2].y, q[3].y]),
            z: lanes([q[0].z, q[1].z, q[2].z, q[3].z]),
            w: lanes([q[0].w, q[1].w, q[2].w, q[3].w]),
        }
    }

    /// `q * v` as glam computes it on SSE2 (`Quat::mul_vec3a`):
    /// v (w² − b·b) + b (2 v·b) + (b × v)(2w), with b the vector part.
    #[inline(always)]
    pub fn rotate(self, v: V3) -> V3 {
        let b = V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        };
        let two = F4::splat(2.0);
        let b2 = b.dot(b);
        let along = v.scale(self.w * self.w - b2);
        let across = b.scale(v.dot(b) * two);
        along.add(across).add(b.cross(v).scale(self.w * two))
    }

    /// `q.conjugate() * v` as glam computes it: the inverse rotation of a unit `q`.
    #[inline(always)]
    pub fn rotate_back(self, v: V3) -> V3 {
        let conjugate = Self {
            x: neg(self.x),
            y: neg(self.y),
            z: neg(self.z),
            w: self.w,
        };
        conjugate.rotate(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vectors(seed: u32) -> [Vec3; 4] {
        let f = |i: u32| {
            ((seed.wrapping_mul(2654435761).wrapping_add(i * 40503)) % 2001) as f32 / 137.0 - 7.3
        };
        [0, 1, 2, 3].map(|l| Vec3::new(f(3 * l), f(3 * l + 1), f(3 * l + 2)))
    }

    #[test]
    fn lanes_match_glam_bit_for_bit() {
        for seed in 0..200 {
            let (a, b) = (vectors(seed), vectors(seed + 1000));
            let (la, lb) = (V3::gather(a), V3::gather(b));
            let q = a.map(|v| Quat::from_scaled_axis(v * 0.3));
            let rotated = Q4::gather(q).rotate(lb);
            let (dot, cross) = (la.dot(lb).to_array(), la.cross(lb));
            let units = a.map(|v| v.normalize());
            let mut units_z = units;
            units_z[(seed % 4) as usize] =
                Vec3::new(0.0, 0.0, if seed % 2 == 0 { 1.0 } else { -1.0 });
            let pair = V3::gather(units_z).any_orthonormal_pair();
            for l in 0..4 {
                let (t1, t2) = units_z[l].any_orthonormal_pair();
                assert_eq!([pair.0.lane(l), pair.1.lane(l)], [t1, t2]);
                assert_eq!(dot[l].to_bits(), a[l].dot(b[l]).to_bits());
                assert_eq!(cross.lane(l), a[l].cross(b[l]));
                assert_eq!(rotated.lane(l), q[l] * b[l]);
                let back = Q4::gather(q).rotate_back(lb);
                assert_eq!(back.lane(l), q[l].conjugate() * b[l]);
            }
        }
    }

    #[test]
    fn clamp_and_max_follow_f32() {
        let x = lanes([-2.0, 0.5, 3.0, f32::NAN]);
        let m = max(x, F4::ZERO).to_array();
        assert_eq!(m, [0.0, 0.5, 3.0, 0.0]);
        let c = clamp(lanes([-2.0, 0.5, 3.0, 1.0]), F4::ZERO, F4::ONE).to_array();
        assert_eq!(c, [0.0, 0.5, 1.0, 1.0]);
        let s = select(
            gt(lanes([1.0, 0.0, 2.0, -1.0]), F4::ZERO),
            F4::ONE,
            F4::ZERO,
        );
        assert_eq!(s.to_array(), [1.0, 0.0, 1.0, 0.0]);
    }
}
