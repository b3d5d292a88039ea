//! [`Y8`]: eight lanes in one AVX register, for the hot loops' copies compiled with AVX2
//! (see [`three_operand`](super::three_operand)). Its operations call the AVX
//! intrinsics, which are inlined only into functions compiled with AVX: `Y8` is used
//! only there.
//!
//! Each operation gives the bits [`F8`]'s does: the same IEEE operations per lane, the
//! same choice of operand in `max` (SSE's rule), masks of all bits or none.

use std::arch::x86_64::{
    __m256, _CMP_EQ_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_UNORD_Q, _mm256_add_ps,
    _mm256_and_ps, _mm256_blendv_ps, _mm256_cmp_ps, _mm256_div_ps, _mm256_max_ps,
    _mm256_movemask_ps, _mm256_mul_ps, _mm256_or_ps, _mm256_set1_ps, _mm256_sqrt_ps, _mm256_sub_ps,
    _mm256_xor_ps,
};
use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Not, Sub};

use super::{F8, Lane};

/// Eight f32 lanes in one 256-bit register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Y8(__m256);

// SAFETY (every `unsafe` below): Y8 values are made and used only inside functions
// compiled with AVX and AVX2 (`#[target_feature(enable = "avx,avx2")]` or wider), which
// run only on CPUs that have them; the intrinsics have no other precondition.

macro_rules! binary {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for Y8 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                Self(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}
binary!(Add, add, _mm256_add_ps);
binary!(Sub, sub, _mm256_sub_ps);
binary!(Mul, mul, _mm256_mul_ps);
binary!(Div, div, _mm256_div_ps);
binary!(BitAnd, bitand, _mm256_and_ps);
binary!(BitOr, bitor, _mm256_or_ps);
binary!(BitXor, bitxor, _mm256_xor_ps);

impl Not for Y8 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        self ^ Self::splat(f32::from_bits(u32::MAX))
    }
}

impl Y8 {
    #[inline(always)]
    fn cmp<const P: i32>(self, o: Self) -> Self {
        Self(unsafe { _mm256_cmp_ps::<P>(self.0, o.0) })
    }
}

impl Lane for Y8 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Self(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn load(x: F8) -> Self {
        // SAFETY: 32 bytes of eight f32 lanes in order, both sides.
        Self(unsafe { std::mem::transmute::<F8, __m256>(x) })
    }
    #[inline(always)]
    fn store(self) -> F8 {
        // SAFETY: as `load`.
        unsafe { std::mem::transmute::<__m256, F8>(self.0) }
    }
    #[inline(always)]
    fn any(self) -> bool {
        unsafe { _mm256_movemask_ps(self.0) != 0 }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self & Self::splat(f32::from_bits(0x7fff_ffff))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn is_finite(self) -> Self {
        // |x| ≤ f32::MAX: false for ±∞ and NaN.
        self.abs().cmp::<_CMP_LE_OQ>(Self::splat(f32::MAX))
    }
    #[inline(always)]
    fn blend(self, t: Self, f: Self) -> Self {
        Self(unsafe { _mm256_blendv_ps(f.0, t.0, self.0) })
    }
    #[inline(always)]
    fn cmp_lt(self, o: Self) -> Self {
        self.cmp::<_CMP_LT_OQ>(o)
    }
    #[inline(always)]
    fn cmp_le(self, o: Self) -> Self {
        self.cmp::<_CMP_LE_OQ>(o)
    }
    #[inline(always)]
    fn cmp_eq(self, o: Self) -> Self {
        self.cmp::<_CMP_EQ_OQ>(o)
    }
    #[inline(always)]
    fn cmp_gt(self, o: Self) -> Self {
        self.cmp::<_CMP_GT_OQ>(o)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // maxps gives `o` unless self > o; a NaN `o` gives way to self (wide's rule).
        let larger = Self(unsafe { _mm256_max_ps(self.0, o.0) });
        o.cmp::<_CMP_UNORD_Q>(o).blend(self, larger)
    }
}
