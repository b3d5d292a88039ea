//! A fingerprint of the simulation state, for determinism checks: every body's pose and
//! velocity, bit for bit, in spawn order, through FNV-1a (64-bit). Two runs agree on
//! the hash exactly when they agree on every bit. `cargo run --release --example
//! state_hash -- <scene file> <steps>` prints it; `tests/determinism.rs` pins one.

use bevy::prelude::*;

use crate::body::{RigidBody, SpawnOrder, Velocity};

/// FNV-1a over the bits of every body's translation, rotation, linear and angular
/// velocity, bodies ordered by [`SpawnOrder`] (bodies without a collider last, in
/// entity order).
pub fn state_hash(world: &mut World) -> u64 {
    let mut q = world
        .query_filtered::<(Entity, Option<&SpawnOrder>, &Transform, &Velocity), With<RigidBody>>();
    let mut rows: Vec<(u64, Entity, [u32; 13])> = q
        .iter(world)
        .map(|(e, order, t, v)| (order.map_or(u64::MAX, |o| o.0), e, body_bits(t, v)))
        .collect();
    rows.sort_by_key(|&(key, e, _)| (key, e));
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for (_, _, bits) in rows {
        for x in bits {
            for byte in x.to_le_bytes() {
                hash ^= byte as u64;
                hash = hash.wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    hash
}

/// A body's translation, rotation, linear and angular velocity as raw bits: what two runs
/// must agree on to be bit-identical.
pub fn body_bits(t: &Transform, v: &Velocity) -> [u32; 13] {
    [
        t.translation.x,
        t.translation.y,
        t.translation.z,
        t.rotation.x,
        t.rotation.y,
        t.rotation.z,
        t.rotation.w,
        v.linear.x,
        v.linear.y,
        v.linear.z,
        v.angular.x,
        v.angular.y,
        v.angular.z,
    ]
    .map(f32::to_bits)
}
