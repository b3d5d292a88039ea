//! The crate's one seeded random source for its own tests and benches (xorshift64):
//! random poses and shapes, the same for a seed everywhere.

use bevy::prelude::*;

/// xorshift64.
pub struct Rnd(pub u64);

impl Rnd {
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Each component uniform in [lo, hi).
    pub fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }

    /// A unit vector, uniform over the sphere.
    pub fn dir(&mut self) -> Vec3 {
        loop {
            let v = self.vec(-1.0, 1.0);
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// A rotation about a random axis by a random angle.
    pub fn rot(&mut self) -> Quat {
        Quat::from_axis_angle(self.dir(), self.range(0.0, std::f32::consts::TAU))
    }
}
