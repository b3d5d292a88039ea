//! The physics step, one stage per module (the file names carry the order of
//! [`PhysicsSystems::ORDER`](crate::PhysicsSystems::ORDER)). The ECS is touched only by
//! prepare (1) and writeback (6); stages 2–5 work on the slices in
//! [`PhysicsWorld`](crate::PhysicsWorld). Stages import the data layer (`crate::world`),
//! `crate::geometry` and `crate::math`, never each other.

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
