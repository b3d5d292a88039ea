//! Eight of everything at once: vectors and rotations whose components are lanes of
//! eight floats (one lane per independent contact), for the solver's batches. Each
//! operation does, lane by lane, exactly the arithmetic glam does on one value, in the
//! same order and without fused multiply-adds, so a lane's result is bit for bit the
//! scalar one.
//!
//! Lanes are stored as [`F8`] (two SSE halves, what every x86_64 runs) and computed in
//! any [`Lane`] type: `F8` itself in the plain copies of the hot loops, and on a CPU with
//! AVX2 [`Y8`](avx::Y8), one 256-bit register, in the copies compiled for it
//! (`#[target_feature]`). The two hold the same eight floats in the same bytes.

use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Not, Sub};

use wide::{CmpEq, CmpGt, CmpLe, CmpLt, f32x4};

#[cfg(target_arch = "x86_64")]
pub mod avx;
mod vectors;

pub use vectors::{Q8, V3};

/// Lanes in an [`F8`]: contacts solved side by side.
pub const WIDTH: usize = 8;

/// What the kernels compute with: eight f32 lanes (a mask has every bit of a lane set
/// or none), as stored ([`F8`]) or in a register the CPU has.
pub trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
    + Not<Output = Self>
{
    fn splat(x: f32) -> Self;
    /// From the stored lanes.
    fn load(x: F8) -> Self;
    /// To stored lanes.
    fn store(self) -> F8;
    /// Some lane of a mask is set.
    fn any(self) -> bool;
    /// No lane of a mask is set.
    #[inline(always)]
    fn none(self) -> bool {
        !self.any()
    }
    /// `f32::abs` per lane.
    fn abs(self) -> Self;
    /// `f32::sqrt` per lane.
    fn sqrt(self) -> Self;
    /// Lanes neither infinite nor NaN (a mask).
    fn is_finite(self) -> Self;
    /// `t` where the mask `self` is set, else `f`.
    fn blend(self, t: Self, f: Self) -> Self;
    fn cmp_lt(self, o: Self) -> Self;
    fn cmp_le(self, o: Self) -> Self;
    fn cmp_eq(self, o: Self) -> Self;
    fn cmp_gt(self, o: Self) -> Self;
    /// `f32::max` per lane as SSE computes it: `o` where `self > o` fails, `self` where
    /// `o` is NaN.
    fn max(self, o: Self) -> Self;
}

/// Eight floats, one per lane; a mask has every bit of a lane set or none. Two SSE
/// halves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct F8([f32x4; 2]);

impl F8 {
    pub const ZERO: Self = Self([f32x4::ZERO; 2]);

    #[inline(always)]
    pub fn new(v: [f32; WIDTH]) -> Self {
        Self([
            f32x4::new([v[0], v[1], v[2], v[3]]),
            f32x4::new([v[4], v[5], v[6], v[7]]),
        ])
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f32x4) -> f32x4) -> Self {
        Self([f(self.0[0]), f(self.0[1])])
    }

    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f32x4, f32x4) -> f32x4) -> Self {
        Self([f(self.0[0], o.0[0]), f(self.0[1], o.0[1])])
    }

    #[inline(always)]
    pub fn as_array_ref(&self) -> &[f32; WIDTH] {
        // SAFETY: two f32x4 in a repr(C) struct are eight f32s in order.
        unsafe { &*(self as *const Self).cast::<[f32; WIDTH]>() }
    }

    #[inline(always)]
    pub fn as_array_mut(&mut self) -> &mut [f32; WIDTH] {
        // SAFETY: as above.
        unsafe { &mut *(self as *mut Self).cast::<[f32; WIDTH]>() }
    }

    #[cfg(test)]
    pub fn to_array(self) -> [f32; WIDTH] {
        *self.as_array_ref()
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F8 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);
lane_op!(BitAnd, bitand, &);
lane_op!(BitOr, bitor, |);
lane_op!(BitXor, bitxor, ^);

impl Not for F8 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        self.map(|x| !x)
    }
}

impl Lane for F8 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Self([f32x4::splat(x); 2])
    }
    #[inline(always)]
    fn load(x: F8) -> Self {
        x
    }
    #[inline(always)]
    fn store(self) -> F8 {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        (self.0[0] | self.0[1]).any()
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(|x| x.abs())
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(|x| x.sqrt())
    }
    #[inline(always)]
    fn is_finite(self) -> Self {
        self.map(|x| x.is_finite())
    }
    #[inline(always)]
    fn blend(self, t: Self, f: Self) -> Self {
        Self([
            self.0[0].blend(t.0[0], f.0[0]),
            self.0[1].blend(t.0[1], f.0[1]),
        ])
    }
    #[inline(always)]
    fn cmp_lt(self, o: Self) -> Self {
        self.zip(o, |a, b| a.cmp_lt(b))
    }
    #[inline(always)]
    fn cmp_le(self, o: Self) -> Self {
        self.zip(o, |a, b| a.cmp_le(b))
    }
    #[inline(always)]
    fn cmp_eq(self, o: Self) -> Self {
        self.zip(o, |a, b| a.cmp_eq(b))
    }
    #[inline(always)]
    fn cmp_gt(self, o: Self) -> Self {
        self.zip(o, |a, b| a.cmp_gt(b))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.zip(o, |a, b| a.max(b))
    }
}

/// The CPU has AVX2. Hot loops are compiled twice, and on such a CPU run the copy that
/// uses the three-operand (VEX) forms of the same SSE operations, which save the register
/// copies the two-operand forms need (the four-lane batched pass had a sixth fewer
/// instructions on the 385-cube pyramid), and whose batched passes compute in
/// [`avx::Y8`], eight lanes an instruction. The operations are the same, with no fused multiply-add (that needs the
/// `fma` feature, which is not enabled): the same bits. The answer is cached by std.
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn three_operand() -> bool {
    #[cfg(test)]
    if PLAIN_ONLY.get() {
        return false;
    }
    std::is_x86_feature_detected!("avx2")
}

/// A hot function compiled twice: `$name` runs `$any` (an `#[inline(always)]` function
/// taking the same arguments) compiled for AVX2's three-operand forms on a CPU that has
/// them (see [`three_operand`]), else as compiled plain.
macro_rules! three_operand_copy {
    // The two copies, calling `$plain` and `$wide` (the same function or two
    // instantiations of it).
    (@copies $(#[$doc:meta])* $vis:vis fn $name:ident / $vex:ident
        => [$($plain:tt)*] [$($wide:tt)*] ($($arg:ident: $ty:ty),*) $(-> $ret:ty)?) => {
        $(#[$doc])*
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            if $crate::math::lanes::three_operand() {
                // SAFETY: the CPU has the features (checked just above).
                return unsafe { $vex($($arg),*) };
            }
            $($plain)*($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx,avx2")]
        fn $vex($($arg: $ty),*) $(-> $ret)? {
            $($wide)*($($arg),*)
        }
    };
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $vex:ident => $any:ident
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?) => {
        $crate::math::lanes::three_operand_copy! { @copies $(#[$doc])* $vis fn $name / $vex
            => [$any] [$any] ($($arg: $ty),*) $(-> $ret)? }
    };
    // For an `$any` generic over the lanes it computes in: `$plain` in the plain copy,
    // `$wide` in the AVX2 one.
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $vex:ident => $any:ident::<$plain:ty, $wide:ty>
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?) => {
        $crate::math::lanes::three_operand_copy! { @copies $(#[$doc])* $vis fn $name / $vex
            => [$any::<$plain>] [$any::<$wide>] ($($arg: $ty),*) $(-> $ret)? }
    };
}
pub(crate) use three_operand_copy;

/// The CPU has AVX-512's 32 vector registers: the batched passes are compiled once more,
/// and on such a CPU run the copy that may use them (fewer spills; the same operations,
/// so the same bits). Checked once a pass; the answer is cached by std.
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn wide_registers() -> bool {
    #[cfg(test)]
    if PLAIN_ONLY.get() {
        return false;
    }
    std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx512vl")
}

#[cfg(test)]
thread_local! {
    /// Tests set it to run the plain copies of the hot loops on a CPU that has the
    /// features for the others, so that each copy is checked against the reference.
    pub static PLAIN_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `check` in each compiled copy of the hot loops: the plain one, then the one
/// this CPU picks (see [`PLAIN_ONLY`]).
#[cfg(test)]
pub fn in_each_copy(mut check: impl FnMut()) {
    for plain in [true, false] {
        PLAIN_ONLY.set(plain);
        check();
    }
}

/// The lanes of eight values.
#[inline(always)]
pub fn lanes(v: [f32; WIDTH]) -> F8 {
    F8::new(v)
}

/// `t` where `m` is set, else `f`.
#[inline(always)]
pub fn select<L: Lane>(m: L, t: L, f: L) -> L {
    m.blend(t, f)
}

/// Lanes `a < b`.
#[inline(always)]
pub fn lt<L: Lane>(a: L, b: L) -> L {
    a.cmp_lt(b)
}

/// Lanes `a <= b`.
#[inline(always)]
pub fn le<L: Lane>(a: L, b: L) -> L {
    a.cmp_le(b)
}

/// Lanes `a == b`.
#[inline(always)]
pub fn eq<L: Lane>(a: L, b: L) -> L {
    a.cmp_eq(b)
}

/// Lanes `a > b`.
#[inline(always)]
pub fn gt<L: Lane>(a: L, b: L) -> L {
    a.cmp_gt(b)
}

/// `-x` per lane, as f32 negates: the sign bit flipped (wide's `-x` is `0 − x`, which
/// turns −0 into +0).
#[inline(always)]
pub fn neg<L: Lane>(x: L) -> L {
    x ^ L::splat(-0.0)
}

/// `f32::max` per lane (a NaN lane takes the other value).
#[inline(always)]
pub fn max<L: Lane>(a: L, b: L) -> L {
    a.max(b)
}

/// `f32::clamp` per lane, for `lo <= hi`.
#[inline(always)]
pub fn clamp<L: Lane>(x: L, lo: L, hi: L) -> L {
    let x = select(lt(x, lo), lo, x);
    select(gt(x, hi), hi, x)
}

#[cfg(test)]
mod tests;
