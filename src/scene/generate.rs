//! Expanding generated body groups into bodies.

use bevy::prelude::*;

use super::{BodyDesc, BodyGroup};

/// A small deterministic generator (xorshift64*) so seeded piles are the same everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// A rock's points: 14 directions spread over the sphere (a Fibonacci lattice), each at
/// `radius` scaled by a seeded factor in [2/3, 4/3], m.
pub fn rock_points(radius: f32, seed: u64) -> Vec<Vec3> {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let n = 14;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let ring = (1.0 - y * y).sqrt();
            let a = golden * i as f32;
            Vec3::new(ring * a.cos(), y, ring * a.sin())
                * radius
                * (2.0 / 3.0 + 2.0 / 3.0 * rng.next())
        })
        .collect()
}

/// How many bodies a group makes, without making them.
pub fn group_size(group: &BodyGroup) -> u64 {
    match group {
        BodyGroup::Single(_) => 1,
        BodyGroup::Grid { count, .. } => count.x as u64 * count.y as u64 * count.z as u64,
        BodyGroup::Stack { count, .. }
        | BodyGroup::Pile { count, .. }
        | BodyGroup::Row { count, .. } => *count as u64,
        BodyGroup::Pyramid { base, flat, .. } => {
            let b = *base as u64;
            if *flat {
                b * (b + 1) / 2
            } else {
                b * (b + 1) * (2 * b + 1) / 6
            }
        }
    }
}

/// The bodies of one group.
pub fn expand_group(group: &BodyGroup) -> Vec<BodyDesc> {
    let at = |b: &BodyDesc, offset: Vec3| BodyDesc {
        position: b.position + offset,
        ..*b
    };
    match group {
        BodyGroup::Single(b) => vec![*b],
        BodyGroup::Grid {
            body,
            count,
            spacing,
        } => {
            let mut out = Vec::new();
            for y in 0..count.y {
                for z in 0..count.z {
                    for x in 0..count.x {
                        out.push(at(body, UVec3::new(x, y, z).as_vec3() * *spacing));
                    }
                }
            }
            out
        }
        BodyGroup::Stack {
            body,
            count,
            spacing,
            jitter,
        } => (0..*count)
            .map(|i| {
                let j = if i % 2 == 0 { *jitter } else { -*jitter };
                at(body, Vec3::Y * (i as f32 * spacing) + j)
            })
            .collect(),
        BodyGroup::Pyramid {
            body,
            base,
            spacing,
            flat,
        } => {
            let mut out = Vec::new();
            for level in 0..*base {
                let n = base - level;
                let half = (n - 1) as f32 * 0.5;
                let depth = if *flat { 1 } else { n };
                for i in 0..n {
                    for k in 0..depth {
                        let z = if *flat { 0.0 } else { k as f32 - half };
                        out.push(at(
                            body,
                            Vec3::new(i as f32 - half, level as f32, z) * *spacing,
                        ));
                    }
                }
            }
            out
        }
        BodyGroup::Pile {
            body,
            count,
            seed,
            min,
            max,
            mass_range,
        } => {
            let mut rng = Rng(seed.wrapping_mul(2_654_435_761).max(1));
            (0..*count)
                .map(|_| {
                    let p = *min + (*max - *min) * Vec3::new(rng.next(), rng.next(), rng.next());
                    let turn = Vec3::new(rng.next(), rng.next(), rng.next()) * 360.0;
                    let scale = mass_range.map(|r| r.x + (r.y - r.x) * rng.next());
                    BodyDesc {
                        position: p,
                        rotation_deg: turn,
                        mass: match (body.mass, scale) {
                            (Some(m), Some(s)) => Some(m * s),
                            (m, None) => m,
                            (None, Some(s)) => Some(s),
                        },
                        ..*body
                    }
                })
                .collect()
        }
        BodyGroup::Row {
            body,
            count,
            spacing,
            direction,
        } => {
            let d = direction.normalize_or(Vec3::X);
            (0..*count)
                .map(|i| at(body, d * (i as f32 * spacing)))
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pyramid_counts() {
        let body = BodyDesc::default();
        let full = expand_group(&BodyGroup::Pyramid {
            body,
            base: 10,
            spacing: 1.0,
            flat: false,
        });
        assert_eq!(full.len(), 385);
        let flat = expand_group(&BodyGroup::Pyramid {
            body,
            base: 4,
            spacing: 1.0,
            flat: true,
        });
        assert_eq!(flat.len(), 10);
        assert_eq!(flat.iter().filter(|b| b.position.y == 3.0).count(), 1);
    }

    #[test]
    fn piles_are_reproducible_and_inside_their_box() {
        let g = BodyGroup::Pile {
            body: BodyDesc::default(),
            count: 100,
            seed: 7,
            min: Vec3::ZERO,
            max: Vec3::ONE,
            mass_range: None,
        };
        let (a, b) = (expand_group(&g), expand_group(&g));
        assert_eq!(a, b);
        assert!(
            a.iter()
                .all(|d| d.position.cmpge(Vec3::ZERO).all() && d.position.cmple(Vec3::ONE).all())
        );
    }
}
