//! Joints in scene files: each names its bodies by their index among the scene's bodies
//! (groups expanded, in file order; `None` for the world), and a `Repeat` lays the same
//! joint along a row of bodies (a chain, a bridge, a cradle's strings).
//!
//! ```ron
//! joints: [
//!     // The first link hangs from the world at (0, 8, 0).
//!     Joint((body1: None, body2: 0, kind: Spherical, anchor1: (0.0, 8.0, 0.0), anchor2: (0.0, 0.1, 0.0))),
//!     // Each link to the next: bodies (0, 1), (1, 2), … (28, 29).
//!     Repeat(joint: (body1: Some(0), body2: 1, kind: Spherical, anchor1: (0.0, -0.1, 0.0), anchor2: (0.0, 0.1, 0.0)), count: 29),
//! ]
//! ```

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::joint::Joint;

/// One joint of a scene.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointDesc {
    /// The first body's index among the scene's bodies, or `None` for the world.
    #[serde(default)]
    pub body1: Option<usize>,
    /// The second body's index.
    pub body2: usize,
    /// What it constrains.
    pub kind: JointKindDesc,
    /// Where it holds body 1, in body 1's frame (the world's for `None`), m.
    #[serde(default)]
    pub anchor1: Vec3,
    /// Where it holds body 2, in body 2's frame, m.
    #[serde(default)]
    pub anchor2: Vec3,
    /// A hinge's or slider's axis, body 1's frame. Default +Z.
    #[serde(default = "default_axis")]
    pub axis: Vec3,
    /// A hinge's angle limits (rad), a slider's offset limits (m), a ball joint's twist
    /// limits (rad).
    #[serde(default)]
    pub limits: Option<(f32, f32)>,
    /// A ball joint's cone: the most body 2's axis leans from `axis`, rad.
    #[serde(default)]
    pub cone: Option<f32>,
    /// A motor: target speed (rad/s or m/s) and most torque or force (N·m or N).
    #[serde(default)]
    pub motor: Option<(f32, f32)>,
    /// Whether its two bodies still collide. Default no.
    #[serde(default)]
    pub collide: bool,
    /// The force it breaks at, N. Default never.
    #[serde(default)]
    pub break_force: Option<f32>,
}

fn default_axis() -> Vec3 {
    Vec3::Z
}

/// A scene joint's kind.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum JointKindDesc {
    /// A weld.
    Fixed,
    /// A ball joint.
    Spherical,
    /// A hinge about `axis`.
    Revolute,
    /// A slider along `axis`.
    Prismatic,
    /// A rigid rod of this length, m.
    Distance(f32),
    /// A rope of at most this length, m.
    Rope(f32),
    /// A spring: rest length (m), frequency (Hz), damping ratio.
    Spring(f32, f32, f32),
}

/// Joints as a scene lists them.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
pub enum JointGroup {
    /// One joint.
    Joint(JointDesc),
    /// `count` copies of `joint`, copy k between bodies `body1 + k` and `body2 + k`; when
    /// body 1 is the world, its anchor moves by `step` (m) from copy to copy.
    Repeat {
        /// The first copy.
        joint: JointDesc,
        /// How many.
        count: usize,
        /// The world anchor's shift per copy, m. Default none.
        #[serde(default)]
        step: Vec3,
    },
}

impl JointGroup {
    /// The joints it stands for.
    pub fn expand(&self) -> Vec<JointDesc> {
        match self {
            JointGroup::Joint(j) => vec![j.clone()],
            JointGroup::Repeat { joint, count, step } => (0..*count)
                .map(|k| {
                    let mut j = joint.clone();
                    j.body2 += k;
                    match &mut j.body1 {
                        Some(b) => *b += k,
                        None => j.anchor1 += *step * k as f32,
                    }
                    j
                })
                .collect(),
        }
    }
}

impl JointDesc {
    /// The [`Joint`] between `bodies` (the scene's spawned bodies, in order), or why not
    /// (a body index past the end).
    pub fn joint(&self, bodies: &[Entity]) -> Result<Joint, String> {
        let body = |i: usize| {
            bodies.get(i).copied().ok_or_else(|| {
                format!("a joint names body {i}, but the scene has {}", bodies.len())
            })
        };
        let body1 = self.body1.map(body).transpose()?;
        let body2 = body(self.body2)?;
        let mut joint = match self.kind {
            JointKindDesc::Fixed => Joint::fixed(body1, body2),
            JointKindDesc::Spherical => Joint::spherical(body1, body2),
            JointKindDesc::Revolute => Joint::revolute(body1, body2, self.axis),
            JointKindDesc::Prismatic => Joint::prismatic(body1, body2, self.axis),
            JointKindDesc::Distance(l) => Joint::distance(body1, body2, l),
            JointKindDesc::Rope(l) => Joint::rope(body1, body2, l),
            JointKindDesc::Spring(rest, hz, zeta) => Joint::spring(body1, body2, rest, hz, zeta),
        }
        .with_local_anchors(self.anchor1, self.anchor2);
        if let Some((lo, hi)) = self.limits {
            joint = joint.with_limits(lo, hi);
        }
        if let Some(angle) = self.cone {
            joint = joint.with_cone_limit(self.axis, angle);
        }
        if let Some((speed, force)) = self.motor {
            joint = joint.with_motor(speed, force);
        }
        if self.collide {
            joint = joint.with_collisions();
        }
        if let Some(f) = self.break_force {
            joint = joint.with_break_force(f);
        }
        Ok(joint)
    }
}
