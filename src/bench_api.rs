//! Hidden entry points for `benches/pairs.rs` (feature `bench-internals`): one shape
//! pair's manifold through our hand-written function or through parry3d, so the two can
//! be timed on the same poses. Not part of the API.

use bevy::prelude::*;

use crate::collider::Shape;
use crate::geometry::{DISPATCH, Posed, parry_collide};
use crate::world::Manifold;

pub use crate::rng::Rnd;

/// Which implementation collides the pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Implementation {
    /// The dispatch table's function (ours where we have one).
    Ours,
    /// Parry's convex manifold, converted as for every parry pair.
    Parry,
}

/// The number of points of A's manifold with B (A's kind ≤ B's kind) within `margin`.
pub fn collide(
    with: Implementation,
    a: (&Shape, Vec3, Quat),
    b: (&Shape, Vec3, Quat),
    margin: f32,
) -> usize {
    let pa = Posed {
        shape: a.0,
        pos: a.1,
        rot: a.2,
    };
    let pb = Posed {
        shape: b.0,
        pos: b.1,
        rot: b.2,
    };
    let mut m = Manifold::default();
    match with {
        Implementation::Ours => {
            if let Some(f) = DISPATCH[a.0.kind() as usize][b.0.kind() as usize] {
                f(pa, pb, margin, &mut m);
            }
        }
        Implementation::Parry => parry_collide(pa, pb, margin, &mut m),
    }
    m.len
}

/// Our sweep and prune over boxes, kept between calls as in the step (its order is last
/// call's, so nearly sorted input sorts in one pass).
#[derive(Default)]
pub struct SweepAndPrune {
    sap: crate::step::broad_phase::SweepAndPrune,
    colliders: Vec<crate::world::ColliderEntry>,
    pairs: Vec<(u32, u32)>,
}

impl SweepAndPrune {
    /// The overlapping pairs among `boxes` (min, max), each a body of its own.
    pub fn pairs(&mut self, boxes: &[(Vec3, Vec3)]) -> &[(u32, u32)] {
        use crate::world::ColliderEntry;
        self.colliders.truncate(boxes.len());
        while self.colliders.len() < boxes.len() {
            let i = self.colliders.len() as u32;
            self.colliders.push(ColliderEntry::new(
                Entity::PLACEHOLDER,
                i as u64,
                i,
                Shape::Sphere { radius: 0.5 },
                Vec3::ZERO,
                Quat::IDENTITY,
            ));
        }
        for (c, &(lo, hi)) in self.colliders.iter_mut().zip(boxes) {
            (c.aabb_min, c.aabb_max) = (lo, hi);
        }
        self.sap.pairs(&self.colliders, &mut self.pairs, usize::MAX);
        &self.pairs
    }
}

/// One contact pass of a real scene's step, batched (SIMD lanes) or one contact at a
/// time: for `benches/contact_pass.rs`.
pub struct ContactPass {
    /// The bodies and contacts as the solver had them.
    start: (
        Vec<crate::world::SolverBody>,
        Vec<crate::world::ContactConstraint>,
    ),
    /// The ones the passes work on.
    bodies: Vec<crate::world::SolverBody>,
    constraints: Vec<crate::world::ContactConstraint>,
    batches: crate::world::ContactBatches,
    fixed: usize,
    h: f32,
    /// What the last batched run's passes did.
    work: crate::world::SolveWork,
}

impl ContactPass {
    /// The contacts of `scene` after `steps` steps (sleeping off), as the solver had them.
    pub fn from_scene(scene: &crate::scene::SceneDesc, steps: usize) -> Self {
        let (mut app, _) = scene.headless_app();
        app.world_mut()
            .resource_mut::<crate::effects::Effects>()
            .sleeping = false;
        for step in 0..steps {
            if step + 1 == steps {
                // The last step keeps every contact's constraint, to be packed here.
                let mut world = app.world_mut().resource_mut::<crate::PhysicsWorld>();
                world.keep_constraints = true;
            }
            app.update();
        }
        let world = app.world().resource::<crate::PhysicsWorld>();
        let fixed = |c: &&crate::world::ContactConstraint| {
            c.a == crate::world::STATIC || c.b == crate::world::STATIC
        };
        let fixed = world.constraints.iter().take_while(fixed).count();
        let (bodies, constraints) = (world.solver_bodies.clone(), world.constraints.clone());
        let mut pass = Self {
            start: (bodies.clone(), constraints.clone()),
            bodies,
            constraints,
            batches: crate::world::ContactBatches::default(),
            fixed,
            h: world.dt / world.substeps().max(1) as f32,
            work: Default::default(),
        };
        pass.pack();
        pass
    }

    /// Contacts in the pass.
    pub fn contacts(&self) -> usize {
        self.constraints.len()
    }

    /// How the contacts were packed: (batches, how many of their lanes hold a contact,
    /// contacts the scalar pass solves, runs of batches a pass walks: each a level's).
    pub fn packing(&self) -> (usize, usize, usize, usize) {
        use crate::world::{NO_CONTACT, SolveStep};
        let b = &self.batches;
        let filled = (b.batches.iter().flat_map(|x| x.contact))
            .filter(|&c| c != NO_CONTACT)
            .count();
        let scalar = (b.steps.iter())
            .filter(|s| matches!(s, SolveStep::Scalar(_)))
            .count();
        let runs = b.steps.len() - scalar;
        (b.batches.len(), filled, scalar, runs)
    }

    /// Normal sweeps per batch solved in the last batched run (at least one each).
    pub fn sweeps_per_batch(&self) -> f64 {
        self.work.sweeps as f64 / self.work.batches.max(1) as f64
    }

    /// Packs the contacts into batches (once a step in the solver).
    pub fn pack(&mut self) {
        self.batches
            .build(&self.constraints, &self.bodies, self.fixed);
    }

    /// Warm start and one solve pass (the fixed contacts again at its end), batched or
    /// scalar, on the working bodies and contacts (which carry over from run to run).
    pub fn run(&mut self, batched: bool) {
        use crate::step::solve::{
            Pass, solve_listed, solve_steps, warm_start_listed, warm_start_steps,
        };
        let (bodies, constraints) = (&mut self.bodies, &mut self.constraints);
        let h = self.h;
        if batched {
            let n = self.batches.steps.len();
            let batches = &mut self.batches;
            warm_start_steps(bodies, constraints, batches, 0..n);
            let fixed = batches.fixed_steps;
            let pass = |measure| Pass {
                h,
                use_bias: true,
                measure,
            };
            let mut work = solve_steps(bodies, constraints, batches, 0..n, &[], pass(true));
            work += solve_steps(bodies, constraints, batches, 0..fixed, &[], pass(false));
            self.work = work;
        } else {
            let all: Vec<u32> = (0..constraints.len() as u32).collect();
            warm_start_listed(bodies, constraints, &all);
            solve_listed(bodies, constraints, &all, &[], h, (true, true));
            solve_listed(
                bodies,
                constraints,
                &all[..self.fixed],
                &[],
                h,
                (true, false),
            );
        }
    }

    /// The working bodies' velocities, as bits (to compare runs).
    pub fn velocity_bits(&self) -> Vec<[u32; 6]> {
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let both = |b: &crate::world::SolverBody| {
            let (v, w) = (bits(b.v), bits(b.w));
            [v[0], v[1], v[2], w[0], w[1], w[2]]
        };
        self.bodies.iter().map(both).collect()
    }

    /// Back to the solver's bodies and contacts, batches packed again.
    pub fn reset(&mut self) {
        self.bodies.clone_from(&self.start.0);
        self.constraints.clone_from(&self.start.1);
        self.pack();
    }
}

/// The step's broad phase tree ([`AwakeTree`](crate::world::AwakeTree)), kept between
/// calls as in the step: enlarged boxes and the candidate pairs they overlap carried
/// from call to call.
#[derive(Default)]
pub struct BroadPhaseTree {
    tree: crate::world::AwakeTree,
    pairs: Vec<(u32, u32)>,
}

impl BroadPhaseTree {
    /// The overlapping pairs among `boxes` (min, max), each a body of its own, in no
    /// particular order.
    pub fn pairs(&mut self, boxes: &[(Vec3, Vec3)]) -> &[(u32, u32)] {
        let leaf = |i: usize| crate::world::Leaf {
            lo: boxes[i].0,
            hi: boxes[i].1,
            body: i as u32,
        };
        self.tree
            .pairs(boxes.len(), leaf, &mut self.pairs, usize::MAX);
        &self.pairs
    }
}
