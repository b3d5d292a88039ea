//! The lanes against glam and f32, bit for bit; the AVX lanes against the stored ones.

use bevy::prelude::*;

use super::*;

fn vectors(seed: u32) -> [Vec3; WIDTH] {
    let f = |i: u32| {
        ((seed.wrapping_mul(2654435761).wrapping_add(i * 40503)) % 2001) as f32 / 137.0 - 7.3
    };
    std::array::from_fn(|l| {
        let l = l as u32;
        Vec3::new(f(3 * l), f(3 * l + 1), f(3 * l + 2))
    })
}

#[test]
fn lanes_match_glam_bit_for_bit() {
    for seed in 0..200 {
        let (a, b) = (vectors(seed), vectors(seed + 1000));
        let (la, lb) = (V3::<F8>::gather(a), V3::<F8>::gather(b));
        let q = a.map(|v| Quat::from_scaled_axis(v * 0.3));
        let rotated = Q8::<F8>::gather(q).rotate(lb);
        let (dot, cross) = (la.dot(lb).to_array(), la.cross(lb));
        let units = a.map(|v| v.normalize());
        let mut units_z = units;
        units_z[seed as usize % WIDTH] =
            Vec3::new(0.0, 0.0, if seed % 2 == 0 { 1.0 } else { -1.0 });
        let pair = V3::<F8>::gather(units_z).any_orthonormal_pair();
        for l in 0..WIDTH {
            let (t1, t2) = units_z[l].any_orthonormal_pair();
            assert_eq!([pair.0.lane(l), pair.1.lane(l)], [t1, t2]);
            assert_eq!(dot[l].to_bits(), a[l].dot(b[l]).to_bits());
            assert_eq!(cross.lane(l), a[l].cross(b[l]));
            assert_eq!(rotated.lane(l), q[l] * b[l]);
            let back = Q8::<F8>::gather(q).rotate_back(lb);
            assert_eq!(back.lane(l), q[l].conjugate() * b[l]);
        }
    }
}

#[test]
fn clamp_and_max_follow_f32() {
    let nan = f32::NAN;
    let x = lanes([-2.0, 0.5, 3.0, nan, -0.0, 0.0, f32::INFINITY, -7.0]);
    let m = max(x, F8::ZERO).to_array();
    let each = x.to_array().map(|x| x.max(0.0));
    assert_eq!(m.map(f32::to_bits), each.map(f32::to_bits));
    let c = clamp(x, F8::ZERO, F8::splat(1.0)).to_array();
    for (c, x) in c.iter().zip(x.to_array()) {
        let f = x.clamp(0.0, 1.0);
        assert!(
            c.to_bits() == f.to_bits() || (c.is_nan() && f.is_nan()),
            "{x}"
        );
    }
    let s = select(gt(x, F8::ZERO), F8::splat(1.0), F8::ZERO);
    assert_eq!(s.to_array(), [0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
}

#[test]
fn lane_tests_follow_f32() {
    let nan = f32::NAN;
    let v = [-2.0, 0.5, 3.0, nan, -0.0, 0.0, f32::INFINITY, -7.0];
    let x = lanes(v);
    let set = |m: F8| m.to_array().map(|b| b.to_bits() == u32::MAX);
    assert_eq!(set(x.is_finite()), v.map(f32::is_finite));
    assert_eq!(set(lt(x, F8::ZERO)), v.map(|x| x < 0.0));
    assert_eq!(set(le(x, F8::ZERO)), v.map(|x| x <= 0.0));
    assert_eq!(set(eq(x, F8::ZERO)), v.map(|x| x == 0.0));
    assert_eq!(
        x.abs().to_array().map(f32::to_bits),
        v.map(|x| x.abs().to_bits())
    );
    assert_eq!(
        neg(x).to_array().map(f32::to_bits),
        v.map(|x| (-x).to_bits())
    );
    assert_eq!(
        x.sqrt().to_array().map(f32::to_bits),
        v.map(|x| x.sqrt().to_bits())
    );
    assert!(gt(x, F8::splat(2.0)).any() && !gt(x, F8::splat(2.0)).none());
    assert!(gt(x, F8::splat(1e30)).any(), "the infinite lane");
    assert!(gt(x, F8::splat(f32::INFINITY)).none());
}

/// Every operation of [`avx::Y8`] against [`F8`]'s, bit for bit, on values that include
/// the awkward ones (NaN, ±∞, ±0, subnormals).
#[cfg(target_arch = "x86_64")]
#[test]
fn avx_lanes_match_the_stored_ones() {
    if !std::is_x86_feature_detected!("avx2") {
        return;
    }
    let awkward = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.0,
        -0.0,
        1e-40,
        -1e-40,
        f32::MAX,
        -3.5,
        2.25,
        7.0,
        -0.125,
    ];
    let mut state = 0x9e37_79b9_u32;
    let mut value = |k: usize| {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        if state.is_multiple_of(3) {
            awkward[(state as usize / 3 + k) % awkward.len()]
        } else {
            (state >> 8) as f32 / 65536.0 - 128.0
        }
    };
    for _ in 0..500 {
        let a = lanes(std::array::from_fn(&mut value));
        let b = lanes(std::array::from_fn(&mut value));
        // SAFETY: AVX2 is there (checked above).
        let (wide, plain) = unsafe { (each_op::<avx::Y8>(a, b), each_op::<F8>(a, b)) };
        for (k, (y, f)) in wide.iter().zip(&plain).enumerate() {
            assert_eq!(
                y.to_array().map(f32::to_bits),
                f.to_array().map(f32::to_bits),
                "operation {k} of {a:?}, {b:?}"
            );
        }
    }
}

/// The results of every lane operation on `a` and `b`, stored.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
fn each_op<L: Lane>(a: F8, b: F8) -> [F8; 16] {
    let (x, y) = (L::load(a), L::load(b));
    let any = if lt(x, y).any() { 1.0 } else { 0.0 };
    let none = if gt(x, y).none() { 1.0 } else { 0.0 };
    [
        x + y,
        x - y,
        x * y,
        x / y,
        x & y,
        x | y,
        x ^ y,
        !x,
        x.abs(),
        x.sqrt(),
        x.is_finite(),
        select(lt(x, y), x, y),
        le(x, y) | eq(x, y) | gt(x, y),
        max(x, y),
        clamp(x, neg(y.abs()), y.abs()) + L::splat(any) + L::splat(none),
        V3 { x, y, z: x * y }
            .any_orthonormal_pair()
            .0
            .cross(Q8 { x, y, z: y, w: x }.rotate(V3 { x: y, y: x, z: y }))
            .x,
    ]
    .map(L::store)
}
