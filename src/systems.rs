//! [`PhysicsSystems`]: the physics step's stages as system sets, in step order.

use bevy::prelude::*;

/// The stages of one physics step, chained in `FixedUpdate` in this order. Order your own
/// systems against them, e.g. `.after(PhysicsSystems::Writeback)` to read this step's
/// velocities or `.before(PhysicsSystems::Prepare)` to set forces for it.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhysicsSystems {
    /// ECS → contiguous solver arrays; invalid bodies are rejected here.
    Prepare,
    /// Gravity, drag, wind, the global push: one system per effect, each only when on.
    Forces,
    /// Free motion (forces, drag, rotation) with the chosen
    /// [`Integrator`](crate::settings::Integrator).
    Integrate,
    /// Candidate pairs from swept bounding boxes.
    BroadPhase,
    /// Contact manifolds for the candidate pairs.
    NarrowPhase,
    /// Contact impulses (substepped soft step, friction, restitution), then the sweep
    /// that stops bodies an impact drove into a fixed collider.
    Solve,
    /// Solver arrays → `Transform` / `Velocity`; collision messages.
    Writeback,
    /// Still islands fall asleep; touched sleepers wake.
    Sleep,
}

impl PhysicsSystems {
    /// Every stage in step order: the one place the order is written. The plugin chains
    /// the sets in this order, and [`StepTimings`](crate::timings::StepTimings) and the
    /// diagnostics name their stages from it. (The discriminants follow it too:
    /// `ORDER[i] as usize == i`.)
    pub const ORDER: [PhysicsSystems; 8] = [
        Self::Prepare,
        Self::Forces,
        Self::Integrate,
        Self::BroadPhase,
        Self::NarrowPhase,
        Self::Solve,
        Self::Writeback,
        Self::Sleep,
    ];

    /// The stage's name in timings and diagnostics (`physics/<name>`, spaces as `_`).
    pub const fn name(self) -> &'static str {
        match self {
            Self::Prepare => "prepare",
            Self::Forces => "forces",
            Self::Integrate => "integrate",
            Self::BroadPhase => "broad phase",
            Self::NarrowPhase => "narrow phase",
            Self::Solve => "solve",
            Self::Writeback => "writeback",
            Self::Sleep => "sleep",
        }
    }
}
