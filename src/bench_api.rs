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
        use crate::world::{ColliderEntry, ContactFilter};
        self.colliders.truncate(boxes.len());
        while self.colliders.len() < boxes.len() {
            let i = self.colliders.len() as u32;
            self.colliders.push(ColliderEntry {
                entity: Entity::PLACEHOLDER,
                owner: Entity::PLACEHOLDER,
                key: i as u64,
                body: i,
                asleep: false,
                shape: Shape::Sphere { radius: 0.5 },
                offset: Vec3::ZERO,
                local_rot: Quat::IDENTITY,
                pos: Vec3::ZERO,
                rot: Quat::IDENTITY,
                friction: 0.5,
                restitution: 0.0,
                filter: ContactFilter::default(),
                aabb_min: Vec3::ZERO,
                aabb_max: Vec3::ZERO,
            });
        }
        for (c, &(lo, hi)) in self.colliders.iter_mut().zip(boxes) {
            (c.aabb_min, c.aabb_max) = (lo, hi);
        }
        self.sap.pairs(&self.colliders, &mut self.pairs, usize::MAX);
        &self.pairs
    }
}

/// One contact pass of a real scene's step, batched (SIMD lanes) or one contact at a
/// time, from the same start: for `benches/contact_pass.rs`.
pub struct ContactPass {
    bodies: Vec<crate::world::SolverBody>,
    constraints: Vec<crate::world::ContactConstraint>,
    batches: crate::world::ContactBatches,
    fixed: usize,
    h: f32,
}

impl ContactPass {
    /// The contacts of `scene` after `steps` steps (sleeping off), as the solver had them.
    pub fn from_scene(scene: &crate::scene::SceneDesc, steps: usize) -> Self {
        let (mut app, _) = scene.headless_app();
        app.world_mut()
            .resource_mut::<crate::effects::Effects>()
            .sleeping = false;
        for _ in 0..steps {
            app.update();
        }
        let world = app.world().resource::<crate::PhysicsWorld>();
        let fixed = |c: &&crate::world::ContactConstraint| {
            c.a == crate::world::STATIC || c.b == crate::world::STATIC
        };
        let fixed = world.constraints.iter().take_while(fixed).count();
        let (bodies, constraints) = (world.solver_bodies.clone(), world.constraints.clone());
        let mut batches = crate::world::ContactBatches::default();
        batches.build(&constraints, &bodies, fixed);
        Self {
            bodies,
            constraints,
            batches,
            fixed,
            h: world.dt / world.substeps().max(1) as f32,
        }
    }

    /// Contacts in the pass.
    pub fn contacts(&self) -> usize {
        self.constraints.len()
    }

    /// Packs the contacts into batches again, from the scene's impulses (once a step in
    /// the solver).
    pub fn pack(&mut self) {
        self.batches
            .build(&self.constraints, &self.bodies, self.fixed);
    }

    /// Warm start and one solve pass (the fixed contacts again at its end), batched or
    /// scalar, on a copy of the bodies; returns their velocities' sum of bits (to compare
    /// the two and keep the work from being optimised away). The batches keep their
    /// impulses from run to run ([`pack`](Self::pack) resets them).
    pub fn run(&mut self, batched: bool) -> u64 {
        use crate::step::solve::{solve_listed, solve_steps, warm_start_listed, warm_start_steps};
        let mut bodies = self.bodies.clone();
        let mut constraints = self.constraints.clone();
        let (h, n) = (self.h, self.batches.steps.len());
        if batched {
            let batches = &mut self.batches;
            warm_start_steps(&mut bodies, &constraints, batches, 0..n);
            let fixed = batches.fixed_steps;
            solve_steps(&mut bodies, &mut constraints, batches, 0..n, &[], h, true);
            solve_steps(
                &mut bodies,
                &mut constraints,
                batches,
                0..fixed,
                &[],
                h,
                true,
            );
        } else {
            let all: Vec<u32> = (0..constraints.len() as u32).collect();
            warm_start_listed(&mut bodies, &constraints, &all);
            solve_listed(&mut bodies, &mut constraints, &all, &[], h, true);
            let fixed = &all[..self.fixed];
            solve_listed(&mut bodies, &mut constraints, fixed, &[], h, true);
        }
        let bits = |v: Vec3| v.to_array().iter().map(|x| x.to_bits() as u64).sum::<u64>();
        bodies.iter().map(|b| bits(b.v) + bits(b.w)).sum()
    }
}
