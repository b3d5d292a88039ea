//! The joints' direct solve against its references: a joint alone must get what its rows
//! solved one block after another (`solve_joints` with its equality rows, the old path)
//! converge to, and a whole random chain must leave every equality row at rest in one
//! solve, which Gauss–Seidel is far from.

use bevy::prelude::*;

use super::joint::solve_joints;
use super::joint_direct::JointSystem;
use crate::math::Softness;
use crate::rng::Rnd;
use crate::world::{JointConstraint, JointRows, STATIC, SolverBody, world_inv_inertia};

fn random_body(r: &mut Rnd) -> SolverBody {
    SolverBody {
        v: r.vec(-3.0, 3.0),
        w: r.vec(-5.0, 5.0),
        dp: r.vec(-0.02, 0.02),
        dq: Quat::from_scaled_axis(r.vec(-0.05, 0.05)),
        inv_mass: r.range(0.01, 10.0),
        inv_inertia: world_inv_inertia(r.rot(), r.vec(0.2, 30.0)),
    }
}

/// A joint of `rows` between `a` and `b` with random anchors, a small error and a rigid
/// bias (mass scale 1, impulse scale 0: what the direct solve does with the bias rate).
pub(super) fn random_joint(r: &mut Rnd, rows: JointRows, a: u32, b: u32) -> JointConstraint {
    let ra = r.vec(-0.5, 0.5);
    let rb = r.vec(-0.5, 0.5);
    let limits = (rows == JointRows::Distance).then_some((0.8, 0.8));
    JointConstraint {
        entity: Entity::PLACEHOLDER,
        a,
        b,
        rows,
        ra,
        rb,
        // B's anchor near A's (within 2 cm), or 0.8 m off for a distance joint.
        offset: ra - rb + r.vec(-0.02, 0.02) + limits.map_or(Vec3::ZERO, |_| r.dir() * 0.8),
        axis: r.dir(),
        axis_b: Vec3::Y,
        cone: None,
        rest: Quat::from_scaled_axis(r.vec(-0.02, 0.02)),
        limits,
        motor: None,
        spring: None,
        linear: r.vec(-0.1, 0.1),
        angular: Vec3::ZERO,
        axial: [0.0; 3],
        h: 1.0 / 240.0,
        force: Vec3::ZERO,
        torque: Vec3::ZERO,
        load: 0.0,
        torque_load: Vec3::ZERO,
        size: 1.0,
        softness: RIGID,
        held: RIGID,
    }
}

const KINDS: [JointRows; 5] = [
    JointRows::Fixed,
    JointRows::Spherical,
    JointRows::Revolute,
    JointRows::Prismatic,
    JointRows::Distance,
];

fn close(x: Vec3, y: Vec3, scale: f32) -> bool {
    (x - y).length() <= 1e-3 * scale
}

#[test]
fn a_joint_alone_gets_what_its_blocks_converge_to() {
    let mut rng = Rnd(5);
    for round in 0..100 {
        let kind = KINDS[round % KINDS.len()];
        let to_world = round % 3 == 0;
        let bodies: Vec<SolverBody> = (0..2).map(|_| random_body(&mut rng)).collect();
        let j = random_joint(&mut rng, kind, if to_world { STATIC } else { 0 }, 1);
        for use_bias in [true, false] {
            let (mut direct, mut reference) = (bodies.clone(), bodies.clone());
            let (mut jd, mut jr) = ([j], [j]);
            let mut system = JointSystem::default();
            system.prepare(&direct, &jd, use_bias);
            system.solve(&mut direct, &mut jd, use_bias);
            for _ in 0..2000 {
                solve_joints(&mut reference, &mut jr, 1.0 / 240.0, use_bias, true);
            }
            let scale = bodies
                .iter()
                .map(|b| b.v.length() + b.w.length())
                .sum::<f32>();
            for (d, r) in direct.iter().zip(&reference) {
                assert!(
                    close(d.v, r.v, scale) && close(d.w, r.w, scale),
                    "round {round} {kind:?} bias {use_bias}: direct {:?} {:?}, blocks {:?} {:?}",
                    d.v,
                    d.w,
                    r.v,
                    r.w
                );
            }
            let impulse = jd[0].linear.length() + jr[0].linear.length() + 1e-3;
            assert!(
                close(jd[0].linear, jr[0].linear, impulse),
                "round {round} {kind:?}: impulses {} and {}",
                jd[0].linear,
                jr[0].linear
            );
        }
    }
}

/// Largest relative velocity at a point joint's anchors, m/s.
fn opening_speed(bodies: &[SolverBody], joints: &[JointConstraint]) -> f32 {
    joints
        .iter()
        .map(|j| {
            let at = |i: u32, r: Vec3| {
                if i == STATIC {
                    Vec3::ZERO
                } else {
                    let b = &bodies[i as usize];
                    b.v + b.w.cross(b.dq * r)
                }
            };
            (at(j.b, j.rb) - at(j.a, j.ra)).length()
        })
        .fold(0.0, f32::max)
}

#[test]
fn a_chain_solved_at_once_leaves_every_joint_at_rest() {
    // 30 light links under a body a hundred times heavier, hung from the world, random
    // velocities: one direct relax solve stops every anchor's relative motion; one
    // Gauss–Seidel pass leaves most of it.
    let mut rng = Rnd(9);
    let n = 31;
    let mut bodies: Vec<SolverBody> = (0..n).map(|_| random_body(&mut rng)).collect();
    for b in &mut bodies[..n - 1] {
        b.inv_mass = 10.0;
    }
    bodies[n - 1].inv_mass = 0.1;
    let joints: Vec<JointConstraint> = (0..n as u32)
        .map(|i| {
            let a = if i == 0 { STATIC } else { i - 1 };
            random_joint(&mut rng, JointRows::Spherical, a, i)
        })
        .collect();
    let before = opening_speed(&bodies, &joints);
    let (mut direct, mut gs) = (bodies.clone(), bodies.clone());
    let (mut jd, mut jg) = (joints.clone(), joints.clone());
    let mut system = JointSystem::default();
    system.prepare(&direct, &jd, false);
    system.solve(&mut direct, &mut jd, false);
    solve_joints(&mut gs, &mut jg, 1.0 / 240.0, false, true);
    let (after, gauss_seidel) = (opening_speed(&direct, &jd), opening_speed(&gs, &jg));
    assert!(after < 1e-4 * before, "{before} m/s left {after}");
    assert!(gauss_seidel > 100.0 * after, "one pass left {gauss_seidel}");
}

/// A rigid bias (mass scale 1, impulse scale 0), so that the blocks one by one converge
/// to the direct solve's answer.
const RIGID: Softness = Softness {
    bias_rate: 60.0,
    mass_scale: 1.0,
    impulse_scale: 0.0,
};
