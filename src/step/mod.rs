//! The physics step, one stage per module, in execution order (the file names carry the
//! order; sleeping comes last). Each stage is one system in [`PhysicsSystems`](crate::PhysicsSystems); the ECS is
//! touched only by prepare (1) and writeback (6). Stages 2–5 are plain functions over the
//! slices in [`PhysicsWorld`](crate::PhysicsWorld).

#[path = "1_prepare/mod.rs"]
pub mod prepare;

#[path = "1b_forces.rs"]
pub mod forces;

#[path = "2_integrate/mod.rs"]
pub mod integrate;

#[path = "3_broad_phase/mod.rs"]
pub mod broad_phase;

#[path = "4_narrow_phase/mod.rs"]
pub mod narrow_phase;

#[path = "5_solve/mod.rs"]
pub mod solve;

#[path = "6_writeback.rs"]
pub mod writeback;

#[path = "7_sleep.rs"]
pub mod sleep;
