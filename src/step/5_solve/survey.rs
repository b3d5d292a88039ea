//! The one pass over the step's manifolds before any constraint is built. It finds:
//! - which bodies the contacts (and joints) touch: the bodies the solver restarts;
//! - per body, how many of its manifolds overlap another moving body (for the push-out
//!   share, `push_out_share`) and the heaviest body it touches (the load it will carry);
//! - the frequency the stiffest contact's sag needs (for the substeps, `substeps_for`).
//!
//! One pass, because each of three would stream every manifold (about 480 bytes) and its
//! two colliders from memory: on 100 pyramids' 14,500 manifolds three such passes took
//! 0.58, 0.48 and 0.78 ms a step.

use crate::world::{ContactParams, PhysicsWorld, STATIC};

use super::contact::mass_of;
use super::stiffness::{NeededHertz, pair_size};

/// Per body, what the survey found (indexed like `PhysicsWorld::bodies`).
#[derive(Default)]
pub(super) struct PerBody {
    /// The bodies the step's manifolds and joints touch, sorted.
    pub active: Vec<u32>,
    /// How many of its manifolds overlap another moving body (a point with negative
    /// separation).
    pub overlaps: Vec<u32>,
    /// The mass of the heaviest body it has a manifold with, kg (0 for a fixed one).
    pub heaviest: Vec<f32>,
}

/// Surveys the manifolds into `per_body` (and marks `BodyState::in_contact`), and
/// returns the frequency the stiffest contact needs, Hz, or 0 when `substeps_vary` is
/// false (the substeps are fixed: nothing to choose). Loads are read from last step's
/// impulses, taken per substep of last step's length (`p.h` is this step's at the
/// smallest substep count).
pub(super) fn survey_contacts(
    world: &mut PhysicsWorld,
    p: &ContactParams,
    substeps_vary: bool,
    per_body: &mut PerBody,
) -> f32 {
    let PerBody {
        active,
        overlaps,
        heaviest,
    } = per_body;
    let n = world.bodies.len();
    active.clear();
    overlaps.clear();
    overlaps.resize(n, 0);
    heaviest.clear();
    heaviest.resize(n, 0.0);
    let (colliders, states) = (&world.colliders, &mut world.bodies);
    let solver = &world.solver_bodies;
    for s in states.iter_mut() {
        s.in_contact = false;
    }
    let last = if world.last_substep > 0.0 {
        world.last_substep
    } else {
        p.h
    };
    // Resting: closing or parting slower than gravity changes speed in two steps.
    let resting_speed = 2.0 * p.gravity * world.dt;
    let mut stiffest = NeededHertz::default();
    let mut touch = |i: u32, states: &mut [crate::world::BodyState]| {
        if i != STATIC && !states[i as usize].in_contact {
            states[i as usize].in_contact = true;
            active.push(i);
        }
    };
    let inv_mass = |i: u32| {
        if i == STATIC {
            0.0
        } else {
            solver[i as usize].inv_mass
        }
    };
    for m in &world.manifolds {
        let (ca, cb) = (&colliders[m.a as usize], &colliders[m.b as usize]);
        let (a, b) = (ca.body, cb.body);
        touch(a, states);
        touch(b, states);
        let (ima, imb) = (inv_mass(a), inv_mass(b));
        for (i, other) in [(a, imb), (b, ima)] {
            if i != STATIC {
                heaviest[i as usize] = heaviest[i as usize].max(mass_of(other));
            }
        }
        if a != STATIC && b != STATIC && m.points().iter().any(|p| p.separation < 0.0) {
            overlaps[a as usize] += 1;
            overlaps[b as usize] += 1;
        }
        if substeps_vary {
            let load: f32 = m.points().iter().map(|p| p.normal_impulse).sum::<f32>() * p.h / last;
            let size = pair_size(&ca.shape, &cb.shape);
            let v = |i: u32| {
                if i == STATIC {
                    bevy::math::Vec3::ZERO
                } else {
                    states[i as usize].v0
                }
            };
            let resting = m.normal.dot(v(b) - v(a)).abs() <= resting_speed;
            stiffest.add(p, (ima, imb), load, size, resting);
        }
    }
    for j in &world.joints {
        touch(j.a, states);
        touch(j.b, states);
    }
    active.sort_unstable();
    stiffest.hertz()
}
