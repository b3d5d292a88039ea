//! Stage 5, solve: contact impulses with the soft step, substepped.
//!
//! Only bodies that touch something are solved; they restart from the beginning of the
//! step and run the [`SolverStage`]s in order. Everything else keeps stage 2's free motion.

mod bounce;
mod contact;
mod contact_lanes;
mod contact_load;
mod continuous;
mod crew;
mod iterate;
mod joint;
mod joint_direct;
#[cfg(test)]
mod joint_direct_tests;
mod joint_forces;
mod prepare_contacts;
#[cfg(test)]
mod prepare_tests;
mod push_out;
mod split;
#[cfg(test)]
mod split_tests;
mod steps;
mod stiffness;
mod store;
mod survey;
mod wide;
#[cfg(test)]
mod wide_tests;

use bevy::prelude::*;

use crate::effects::Effects;
use crate::math::{FreeStep, Inertial, Softness, free_substep, rotate};
use crate::settings::{Gravity, Integrator, SolverSettings};
use crate::world::{
    ContactBatches, ContactParams, PhysicsWorld, STATIC, SolveWork, is_isotropic, world_inv_inertia,
};

use bounce::restitution_steps;
pub use contact::refresh_rows;
pub use continuous::sweep_against_fixed;
use crew::{Crew, StopOnDrop};
pub use iterate::stop_approach;
#[cfg(feature = "bench-internals")]
pub(crate) use iterate::{solve_listed, warm_start_listed};
use joint::{solve_joints, warm_start_joints};
use joint_direct::JointSystem;
use joint_forces::store_joint_forces;
use prepare_contacts::{PARALLEL_PREPARE_FROM, prepare_contacts};
pub(crate) use steps::{Pass, solve_steps, warm_start_steps};
pub use stiffness::substeps_for;
use stiffness::{HELD_MAX_RATE, JOINT_DAMPING_RATIO, MAX_TENSION_TURN, joint_hertz, tension_omega};
use store::store_impulses;
pub use store::sum_impulses;
use survey::{PerBody, survey_contacts};

/// The solver's stages in execution order. `PrepareContacts` runs once per step; the
/// five substep stages run `substeps` times; `Restitution`, `StopApproach` and
/// `StoreImpulses` once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolverStage {
    PrepareContacts,
    IntegrateVelocities,
    WarmStart,
    Solve,
    IntegratePositions,
    Relax,
    Restitution,
    StopApproach,
    StoreImpulses,
}

/// Scratch kept between steps so the solver does not allocate.
#[derive(Default)]
pub struct SolverScratch {
    /// Per body: touched by a contact, overlapping contacts, heaviest neighbour.
    per_body: PerBody,
    /// Each active body's free motion for the current substep.
    free: Vec<FreeStep>,
    /// How many constraints, at the front, involve a fixed collider.
    fixed_constraints: usize,
    /// Some constraint has a turning anisotropic body (see [`refresh_rows`]).
    refresh: bool,
    /// Some constraint reports its impulses (a collider with collision events).
    report: bool,
    /// Some constraint bounces (restitution above zero).
    bounce: bool,
    /// This step's contacts packed into batches solved side by side.
    batches: ContactBatches,
    /// The batches' separations were measured since the bodies last moved (see
    /// [`solve_batches`](wide::solve_batches)): a substep's Relax measures them, and the
    /// next substep's Solve, before which nothing moves, reads them.
    measured: bool,
    /// Whether this step's passes over all contacts, and over the fixed ones, split their
    /// wide levels between threads (decided once a step: `split::worth_splitting`).
    split: [bool; 2],
    /// The joints' equality rows, solved together.
    joints: JointSystem,
    /// Working space for [`tension_omega`].
    tension: Vec<(u32, f32)>,
}

/// Approach speeds a resting contact reaches, as a multiple of the speed gravity adds in
/// one step: the contact takes up to that speed back each step, and must not bounce it.
const RESTING_APPROACH: f32 = 2.0;

/// The normal approach speed below which a contact does not bounce, m/s: the setting,
/// lowered to what a resting contact can reach ([`RESTING_APPROACH`] steps of gravity's
/// speed). A body at rest under gravity approaches its support at about |g|·dt each
/// step; anything faster is an impact. In zero gravity nothing rests by approaching, so
/// every approach bounces: a fixed 1 m/s there turned every slow collision of an elastic
/// gas inelastic, and it lost half its energy in 20 s.
fn bounce_threshold(settings: &SolverSettings, effects: &Effects, gravity: Vec3, dt: f32) -> f32 {
    let g = if effects.gravity {
        gravity.length()
    } else {
        0.0
    };
    settings
        .restitution_threshold
        .min(RESTING_APPROACH * g * dt)
}

/// Solves every contact of this step.
pub fn solve_contacts(
    mut world: ResMut<PhysicsWorld>,
    integrator: Res<Integrator>,
    settings: Res<SolverSettings>,
    effects: Res<Effects>,
    gravity: Res<Gravity>,
    mut scratch: Local<SolverScratch>,
) {
    let world = &mut *world;
    let dt = world.dt;
    world.solve_work = SolveWork::default();
    if (world.manifolds.is_empty() && world.joints.is_empty()) || dt <= 0.0 {
        world.impulse_cache.clear();
        return;
    }
    let scratch = &mut *scratch;
    let min_substeps = settings.substeps.max(1);
    let mut params = ContactParams {
        friction: effects.friction,
        hertz: settings.contact_hertz,
        gravity: gravity.0.length(),
        max_hertz: 0.0,
        damping_ratio: settings.contact_damping_ratio,
        h: dt / min_substeps as f32,
        dt,
        max_push_out: settings.max_push_out,
        max_sag: settings.max_sag,
        bounce_threshold: bounce_threshold(&settings, &effects, gravity.0, dt),
    };
    // Last step's impulses were per substep of last step's length: rescale them to this
    // step's substep, then see how stiff the stiffest contact wants to be.
    let limits = (min_substeps, settings.max_substeps);
    let vary = limits.1 > limits.0;
    let stiffest = survey_contacts(world, &params, vary, &mut scratch.per_body);
    for &i in &scratch.per_body.active {
        let (b, s) = (
            &world.bodies[i as usize],
            &mut world.solver_bodies[i as usize],
        );
        (s.dp, s.dq, s.v, s.w) = (Vec3::ZERO, Quat::IDENTITY, b.v0, b.w0);
    }
    let n = choose_substeps(world, &params, limits, stiffest, &mut scratch.tension);
    params.h = dt / n as f32;
    // Stiffness capped at a quarter of the substep rate.
    params.max_hertz = 0.25 / params.h;
    if world.last_substep > 0.0 && world.last_substep != params.h {
        let scale = params.h / world.last_substep;
        for m in world.manifolds.iter_mut() {
            m.previous_load *= scale;
            for p in m.points_mut() {
                p.normal_impulse *= scale;
                p.tangent_impulse *= scale;
                p.twist_impulse *= scale;
            }
        }
    }
    for j in world
        .joints
        .iter_mut()
        .filter(|j| j.h > 0.0 && j.h != params.h)
    {
        let scale = params.h / j.h;
        (j.linear, j.angular) = (j.linear * scale, j.angular * scale);
        j.axial = j.axial.map(|x| x * scale);
    }
    world.last_substep = params.h;
    world.substeps = n;
    // Declared before the closures that borrow it (used only if a pass splits).
    let crew = Crew::new(true);
    let run = |stage, world: &mut PhysicsWorld, scratch: &mut SolverScratch, crew| {
        run_stage(stage, world, scratch, *integrator, &settings, &params, crew)
    };
    run(SolverStage::PrepareContacts, world, scratch, None);
    let substeps = |world: &mut PhysicsWorld, scratch: &mut SolverScratch, crew| {
        for k in 0..n {
            for stage in [
                SolverStage::IntegrateVelocities,
                SolverStage::WarmStart,
                SolverStage::Solve,
                SolverStage::IntegratePositions,
                SolverStage::Relax,
            ] {
                run(stage, world, scratch, crew);
            }
            // A substep's impulses are final once relaxed (the last one's after restitution).
            if scratch.report && k + 1 < n {
                sum_impulses(
                    &world.constraints,
                    &scratch.batches.scalar,
                    &mut world.manifolds,
                );
            }
        }
    };
    if scratch.split.contains(&true) {
        // One helper for every split pass of the step (see `crew`).
        bevy::tasks::ComputeTaskPool::get().scope(|scope| {
            let crew = &crew;
            scope.spawn(async move { crew.serve() });
            let _stop = StopOnDrop(crew);
            substeps(world, scratch, Some(crew));
        });
    } else {
        substeps(world, scratch, None);
    }
    if effects.restitution {
        run(SolverStage::Restitution, world, scratch, None);
    }
    // Back to their constraints: the batched contacts with fixed colliders, which the
    // final stop reads as constraints (the rest are stored from their lanes: see
    // `store`).
    let batches = &scratch.batches;
    batches.write_back(0..batches.fixed_batches, &mut world.constraints);
    if effects.restitution {
        run(SolverStage::StopApproach, world, scratch, None);
    }
    if scratch.report {
        sum_impulses(
            &world.constraints,
            &scratch.batches.scalar,
            &mut world.manifolds,
        );
    }
    run(SolverStage::StoreImpulses, world, scratch, None);
}

/// Runs one solver stage over the whole contact set.
fn run_stage(
    stage: SolverStage,
    world: &mut PhysicsWorld,
    scratch: &mut SolverScratch,
    integrator: Integrator,
    settings: &SolverSettings,
    params: &ContactParams,
    crew: Option<&Crew>,
) {
    // For profilers (trace level: free unless asked for).
    let _span = trace_span!("tumble::solve", stage = ?stage).entered();
    let h = params.h;
    let bodies = &mut world.solver_bodies;
    let (iterations, relax_iterations) = (world.iterations, world.relax_iterations);
    match stage {
        SolverStage::PrepareContacts => {
            let stiffness = *params;
            let (m, c, s) = (&world.manifolds, &world.colliders, &world.bodies);
            let out = (&mut world.constraints, &mut world.contact_keys);
            let arms = &mut world.rolling_arms;
            let keep = world.keep_constraints;
            let per_body = (&*scratch.per_body.overlaps, &*scratch.per_body.heaviest);
            let threads = bevy::tasks::ComputeTaskPool::try_get().map_or(1, |p| p.thread_num());
            let split = threads >= 2 && m.len() >= PARALLEL_PREPARE_FROM;
            let scene = (&**c, &**s, &**bodies);
            let lists = (&mut scratch.batches, arms);
            let found = prepare_contacts(m, scene, stiffness, per_body, out, lists, (split, keep));
            scratch.fixed_constraints = found.fixed;
            debug_assert!(
                world.contact_keys[scratch.fixed_constraints..]
                    .iter()
                    .all(|k| k.a != STATIC && k.b != STATIC),
                "contacts with fixed colliders must come first"
            );
            for j in world.joints.iter_mut() {
                let (wanted, _) = joint_hertz(j, bodies, &stiffness);
                j.softness = Softness::new(wanted.min(stiffness.max_hertz), JOINT_DAMPING_RATIO, h);
                j.held = Softness::new(wanted.min(HELD_MAX_RATE / h), JOINT_DAMPING_RATIO, h);
            }
            world.iterations = iterations_for(settings.iterations, found.ratio);
            // The relax passes follow the pairs' mass ratios, not the load a stack
            // carries: a relax pass takes out the velocity the solve passes' push-out
            // left, and through a stack of equal bodies one pass does that however much
            // they carry (Box2D and rapier relax once a substep). A light body between
            // heavy ones needs more, and so does a contact that bounces: restitution
            // reverses the relaxed velocity, and with the mass ratio's 3 passes instead of
            // the load's 5 a 682 kg ball bouncing off a 6.5 kg box gained 3 kJ
            // (tests/regress_squeezed_box_restitution.rs). Measured on the 5,050-cube
            // pyramid (2 solve passes, 1 relax; three interleaved runs): solve 24.5-26.5
            // -> 21.9-22.5 ms a step, the largest displacement after 220 steps 0.178 ->
            // 0.189 m.
            world.relax_iterations = iterations_for(settings.iterations, found.relax_ratio);
            (scratch.refresh, scratch.report) = (found.refresh, found.report);
            scratch.bounce = found.bounce;
            scratch.measured = false;
            let batches = &scratch.batches;
            let worth = |steps| split::worth_splitting(batches, &steps);
            scratch.split = [worth(0..batches.steps.len()), worth(0..batches.fixed_steps)];
        }
        SolverStage::IntegrateVelocities => {
            scratch.free.clear();
            for &i in &scratch.per_body.active {
                let (b, s) = (&world.bodies[i as usize], &mut bodies[i as usize]);
                let q = (s.dq * b.q0).normalize();
                if !b.round {
                    s.w = limit_spin(s.w, world.dt);
                }
                let fs = free_substep(integrator, b.kind, Inertial::of(b), q, s.v, s.w, h);
                s.v = fs.v.clamp_length_max(settings.max_linear_speed);
                s.w = fs.w;
                scratch.free.push(fs);
            }
        }
        SolverStage::WarmStart => {
            warm_start_joints(bodies, &world.joints);
            let (all, constraints) = (0..scratch.batches.steps.len(), &world.constraints);
            if let Some(crew) = crew.filter(|_| scratch.split[0]) {
                let runner = split::Runner::Crew(crew);
                split::warm_start_steps(runner, bodies, constraints, &scratch.batches, all);
            } else {
                warm_start_steps(bodies, constraints, &scratch.batches, all);
            }
        }
        SolverStage::Solve | SolverStage::Relax => {
            let use_bias = stage == SolverStage::Solve;
            // Contacts with fixed (static or sleeping) colliders come first (see
            // `canonical_order`), so each pass works up from the ground as stacks need;
            // they are solved once more at the end of the pass, so the world also has the
            // last word on a light body squeezed into it by a heavy one. Measured: ten-high
            // stacks creep 6.9 mm a minute awake (fixed last: 11.3, fixed first only: 7.4),
            // and the property tests find fewer bodies pushed into walls.
            let joints = !world.joints.is_empty();
            if joints {
                scratch.joints.prepare(bodies, &world.joints, use_bias);
            }
            let iterations = if use_bias {
                iterations
            } else {
                relax_iterations
            };
            for it in 0..iterations {
                // Joints first, then contacts (Box2D's order): the contacts have the
                // last word on what touches. Of the joints, the limits and motors first,
                // then the rows that hold them together.
                if joints {
                    solve_joints(bodies, &mut world.joints, h, use_bias, false);
                    scratch.joints.solve(bodies, &mut world.joints, use_bias);
                }
                let (arms, constraints) = (&world.rolling_arms, &mut world.constraints);
                let batches = &mut scratch.batches;
                let (steps, fixed_steps) = (batches.steps.len(), batches.fixed_steps);
                // The first pass over all contacts measures the separations if the
                // bodies moved since they were last measured; the rest reuse them.
                let measure = it == 0 && !scratch.measured;
                for (range, split, measure) in [
                    (0..steps, scratch.split[0], measure),
                    (0..fixed_steps, scratch.split[1], false),
                ] {
                    let pass = Pass {
                        h,
                        use_bias,
                        measure,
                    };
                    let work = if let Some(crew) = crew.filter(|_| split) {
                        let runner = split::Runner::Crew(crew);
                        let c = &mut *constraints;
                        split::solve_steps(runner, bodies, c, batches, range, arms, pass).0
                    } else {
                        solve_steps(bodies, constraints, batches, range, arms, pass)
                    };
                    world.solve_work += work;
                }
            }
            scratch.measured = true;
        }
        SolverStage::IntegratePositions => {
            // The free increment plus the contact impulses' share, h·Δv and h·Δω. A
            // turning anisotropic body's world inertia turns with it, for the contacts
            // that ask (`refresh`) and for the joints, whose anchors already turn with
            // their bodies each substep (no test measured a difference; it is the
            // consistent kinematics).
            let turn_inertia = scratch.refresh || !world.joints.is_empty();
            scratch.measured = false;
            for (&i, fs) in scratch.per_body.active.iter().zip(&scratch.free) {
                let (b, s) = (&world.bodies[i as usize], &mut bodies[i as usize]);
                s.dp += fs.dx + h * (s.v - fs.v);
                s.dq = (rotate(fs.q, s.w - fs.w, h) * b.q0.inverse()).normalize();
                if turn_inertia && !is_isotropic(b.inv_inertia) {
                    s.inv_inertia = world_inv_inertia(s.dq * b.q0, b.inv_inertia);
                }
            }
            // The world inertia of an anisotropic body turned with it: the rows follow.
            if scratch.refresh {
                let scalar = &scratch.batches.scalar;
                refresh_rows(bodies, &mut world.constraints, scalar, &world.rolling_arms);
            }
        }
        SolverStage::Restitution => {
            // (Not even a scan over the contacts when none bounces.) The batched ones
            // bounce in their lanes (see `bounce`).
            if scratch.bounce {
                let threshold = params.bounce_threshold;
                let (c, batches) = (&mut world.constraints, &mut scratch.batches);
                restitution_steps(bodies, c, batches, threshold);
            }
        }
        SolverStage::StopApproach => {
            // A bounce between two bodies can send one into a wall it is touching; the
            // world has the last word here too.
            let fixed = scratch.fixed_constraints;
            stop_approach(bodies, &mut world.constraints[..fixed], &world.rolling_arms);
        }
        SolverStage::StoreImpulses => {
            store_impulses(world, &scratch.batches);
            store_joint_forces(&mut world.joints, &world.solver_bodies, h);
        }
    }
}

/// The substeps this step needs: enough for the stiffest contact's wanted frequency
/// (`stiffest`, Hz, from the survey; see [`stiffness`](self::stiffness)) and for the
/// joints, between the setting and `max`.
fn choose_substeps(
    world: &PhysicsWorld,
    p: &ContactParams,
    (min, max): (u32, u32),
    mut stiffest: f32,
    scratch: &mut Vec<(u32, f32)>,
) -> u32 {
    if max <= min {
        return min;
    }
    // Joints with limits: a soft limit row sags under its load as a contact does. (The
    // rows that hold a joint together are solved exactly and may be stiffer than the
    // substeps' cap: see `joint_direct`.)
    for j in world
        .joints
        .iter()
        .filter(|j| j.limits.is_some() || j.cone.is_some())
    {
        stiffest = stiffest.max(joint_hertz(j, &world.solver_bodies, p).1);
    }
    let by_contacts = substeps_for(stiffest, world.dt, min, max);
    // The joints: enough that no taut chain rings faster than the solve follows.
    let omega = tension_omega(&world.joints, &world.solver_bodies, scratch);
    let by_joints = (omega * world.dt / MAX_TENSION_TURN).ceil();
    // A saturating cast, as in `substeps_for`.
    by_contacts.max((by_joints as u32).clamp(min, max))
}

/// The most a non-round body in contact may turn in one step, rad (an eighth of a turn,
/// Box2D's limit too). A contact's anchors and Jacobians are prepared once per step at
/// the start pose, which holds while the body turns little; a thin rod spinning at
/// 400 rad/s about its long axis (its inertia there is tiny, so any off-centre impulse
/// spins it up) turned over a radian per substep, its stale contacts pushed the wrong
/// way, and it gained 160 kJ in one step (tests/regress_thin_rod_energy.rs). Spheres are
/// exempt: their contact point does not turn with them, and a small ball rolls fast.
pub const MAX_ROTATION_PER_STEP: f32 = std::f32::consts::FRAC_PI_4;

/// `w` limited so the body turns at most [`MAX_ROTATION_PER_STEP`] in a step of `dt` s.
pub fn limit_spin(w: Vec3, dt: f32) -> Vec3 {
    w.clamp_length_max(MAX_ROTATION_PER_STEP / dt)
}

/// Gauss–Seidel converges in about r iterations' worth of sweeps on a light body squeezed
/// by a load r times its mass; warm starting carries most of that, but a 100:1 stack
/// still needs a few passes a substep to hold without jitter. So the passes grow with the
/// decades of the largest load ratio: 1 up to 10:1, 2 up to 100:1, 3 beyond (at most 8),
/// and never below the setting. Scenes without heavy loads pay nothing. A ratio up to
/// [`RATIO_BAND`] above a decade counts as that decade.
pub fn iterations_for(setting: u32, max_ratio: f32) -> u32 {
    // A saturating cast: a ratio of 1 gives a negative logarithm, 0.
    let extra = (max_ratio.max(1.0) / (1.0 + RATIO_BAND)).log10().ceil() as u32;
    setting.max(1).max(extra.min(8))
}

/// How far above a decade a load ratio may be and still count as that decade, as a
/// fraction. A ratio read from impulses is known no better than the passes converge them
/// ([`NORMAL_TOL`](iterate::NORMAL_TOL)). A ten-cube tower's bottom contact carries
/// exactly ten cubes, and read from its impulses the ratio was 10 ± 2·10⁻⁵, step after
/// step: the passes followed the rounding, 1 or 2 a substep (1.35 on average).
pub const RATIO_BAND: f32 = iterate::NORMAL_TOL;
