//! Joints: a [`Joint`] component, on an entity of its own, holds two bodies (or a body
//! and the world) together in the same soft-step solver as the contacts: warm started,
//! solved and relaxed each substep. A scene without joints pays nothing for them.
//!
//! ```no_run
//! # use bevy::prelude::*;
//! # use tumble::prelude::*;
//! fn spawn_door(mut commands: Commands) {
//!     let frame = commands
//!         .spawn((RigidBody::Static, Collider::cuboid(0.1, 1.0, 0.1), Transform::default()))
//!         .id();
//!     let door = commands
//!         .spawn((RigidBody::Dynamic, Collider::cuboid(0.5, 1.0, 0.05), Transform::from_xyz(0.6, 0.0, 0.0)))
//!         .id();
//!     // A hinge along y at the frame's edge, swinging ±90°, braked by a motor holding 0 rad/s
//!     // with at most 5 N·m.
//!     commands.spawn(
//!         Joint::revolute(frame, door, Vec3::Y)
//!             .with_local_anchors(Vec3::new(0.1, 0.0, 0.0), Vec3::new(-0.5, 0.0, 0.0))
//!             .with_limits(-1.57, 1.57)
//!             .with_motor(0.0, 5.0),
//!     );
//! }
//! ```
//!
//! Names follow the peers where a Bevy user would look for them (avian3d's
//! `RevoluteJoint`, `SphericalJoint`, …; rapier's builders), as one component with a
//! [`JointKind`], so one query sees every joint. Angles are measured from the pose the
//! bodies had when the joint first stepped: a hinge's angle is 0 there, and a fixed joint
//! keeps that relative pose.

use bevy::prelude::*;

/// Joints in the physics step: the component, what it reads back, and its break event.
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[require(JointForces)]
pub struct Joint {
    /// The first body, or `None` for the world (then [`local_anchor1`](Self::local_anchor1)
    /// and [`local_axis1`](Self::local_axis1) are in world coordinates).
    pub body1: Option<Entity>,
    /// The second body.
    pub body2: Entity,
    /// What it constrains.
    pub kind: JointKind,
    /// Where the joint holds body 1, in body 1's frame (its `Transform`'s origin and
    /// axes), m.
    pub local_anchor1: Vec3,
    /// Where the joint holds body 2, in body 2's frame, m.
    pub local_anchor2: Vec3,
    /// The hinge axis of a revolute joint or the slide of a prismatic one, in body 1's
    /// frame (any length but zero).
    pub local_axis1: Vec3,
    /// Whether the two bodies still collide with each other (default: no, as in avian3d
    /// and rapier).
    pub collide_connected: bool,
    /// The force the joint can hold, N: beyond it, it breaks ([`JointBroken`]) and its
    /// `Joint` component is removed. Default: unbreakable (`f32::INFINITY`).
    pub break_force: f32,
}

/// What a [`Joint`] constrains.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub enum JointKind {
    /// No relative motion at all: a weld.
    Fixed,
    /// The anchors held together; the bodies turn about them: a ball joint, free or
    /// limited (a shoulder, a hip).
    Spherical {
        /// The most body 2's axis may lean from body 1's, rad (the axis is
        /// [`Joint::local_axis1`], and body 2's is where it was when the joint first
        /// stepped).
        cone: Option<f32>,
        /// The lowest and highest twist about body 1's axis, rad.
        twist: Option<(f32, f32)>,
    },
    /// The anchors held together and the bodies turned only about the axis: a hinge.
    Revolute {
        /// The lowest and highest angle, rad (from the pose when the joint first stepped).
        limits: Option<(f32, f32)>,
        /// A motor driving the angular speed about the axis.
        motor: Option<JointMotor>,
    },
    /// No relative turn; the anchors apart only along the axis: a slider.
    Prismatic {
        /// The lowest and highest offset of anchor 2 from anchor 1 along the axis, m.
        limits: Option<(f32, f32)>,
        /// A motor driving the speed along the axis.
        motor: Option<JointMotor>,
    },
    /// The anchors kept between `min` and `max` apart (both equal: a rigid rod; `min` 0:
    /// a rope), m; with a spring, pulled toward `rest`.
    Distance {
        /// The shortest the anchors may come, m.
        min: f32,
        /// The farthest they may part, m.
        max: f32,
        /// A spring toward `rest` between the limits.
        spring: Option<JointSpring>,
    },
}

/// A joint motor: drives the relative speed toward `target_speed` with at most
/// `max_force`.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub struct JointMotor {
    /// rad/s for a revolute joint, m/s for a prismatic one.
    pub target_speed: f32,
    /// The most torque (N·m, revolute) or force (N, prismatic) it applies.
    pub max_force: f32,
}

/// A distance joint's spring.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub struct JointSpring {
    /// The length it pulls toward, m.
    pub rest: f32,
    /// Its stiffness as a frequency, Hz (how fast the two bodies would oscillate).
    pub hertz: f32,
    /// Its damping ratio: 1 critical, 0 none.
    pub damping_ratio: f32,
}

/// What a joint did in the last step, written after it (zero before its first step).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
pub struct JointForces {
    /// The force on body 2 from the joint, N, world frame (body 1 gets its opposite).
    pub force: Vec3,
    /// The torque on body 2 from the joint, N·m, world frame.
    pub torque: Vec3,
    /// The solver's state, kept between steps.
    #[reflect(ignore)]
    pub(crate) state: JointState,
}

/// The solver's memory of a joint: its accumulated impulses (warm starting) and the
/// relative pose its angles count from.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct JointState {
    /// Body 2's rotation relative to body 1 when the joint first stepped (`None` before).
    pub rest: Option<Quat>,
    /// Accumulated impulses of the last substep: linear (N·s, world), angular (N·m·s,
    /// world), and along the axis: motor, lower limit, upper limit (distance: the rigid
    /// or spring row in the motor's place).
    pub linear: Vec3,
    pub angular: Vec3,
    pub axial: [f32; 3],
    /// The substep they are per, s (0 before the first step).
    pub h: f32,
}

/// A joint broke: the force it held passed its [`Joint::break_force`]. A message, and an
/// entity event triggered on the joint's entity; its `Joint` component is removed.
#[derive(Message, EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct JointBroken {
    /// The joint's entity.
    pub entity: Entity,
    /// Its bodies (body 1 `None` for the world).
    pub body1: Option<Entity>,
    /// Its second body.
    pub body2: Entity,
    /// The force that broke it, N.
    pub force: f32,
}

impl Joint {
    fn new(body1: impl Into<Option<Entity>>, body2: Entity, kind: JointKind) -> Self {
        Self {
            body1: body1.into(),
            body2,
            kind,
            local_anchor1: Vec3::ZERO,
            local_anchor2: Vec3::ZERO,
            local_axis1: Vec3::X,
            collide_connected: false,
            break_force: f32::INFINITY,
        }
    }

    /// A weld: body 2 keeps its rotation relative to body 1 (`None`: the world) as when
    /// the joint first steps, and its anchor on body 1's (the anchors default to both
    /// origins: give [`with_local_anchors`](Self::with_local_anchors) to weld at an
    /// offset).
    pub fn fixed(body1: impl Into<Option<Entity>>, body2: Entity) -> Self {
        Self::new(body1, body2, JointKind::Fixed)
    }

    /// A ball joint at the anchors, free (see [`with_cone_limit`](Self::with_cone_limit)
    /// and [`with_twist_limits`](Self::with_twist_limits)).
    pub fn spherical(body1: impl Into<Option<Entity>>, body2: Entity) -> Self {
        let kind = JointKind::Spherical {
            cone: None,
            twist: None,
        };
        Self::new(body1, body2, kind)
    }

    /// A ball joint's cone: body 2's axis leans at most `max_angle` rad from body 1's
    /// axis (`local_axis1`, here set to `axis`). No effect on the other kinds.
    pub fn with_cone_limit(mut self, axis: Vec3, max_angle: f32) -> Self {
        if let JointKind::Spherical { cone, .. } = &mut self.kind {
            *cone = Some(max_angle);
            self.local_axis1 = axis;
        }
        self
    }

    /// A ball joint's twist about its axis, between `min` and `max` rad. No effect on the
    /// other kinds.
    pub fn with_twist_limits(mut self, min: f32, max: f32) -> Self {
        if let JointKind::Spherical { twist, .. } = &mut self.kind {
            *twist = Some((min, max));
        }
        self
    }

    /// A hinge about `axis` (body 1's frame) through the anchors.
    pub fn revolute(body1: impl Into<Option<Entity>>, body2: Entity, axis: Vec3) -> Self {
        let kind = JointKind::Revolute {
            limits: None,
            motor: None,
        };
        Self {
            local_axis1: axis,
            ..Self::new(body1, body2, kind)
        }
    }

    /// A slider along `axis` (body 1's frame).
    pub fn prismatic(body1: impl Into<Option<Entity>>, body2: Entity, axis: Vec3) -> Self {
        let kind = JointKind::Prismatic {
            limits: None,
            motor: None,
        };
        Self {
            local_axis1: axis,
            ..Self::new(body1, body2, kind)
        }
    }

    /// A rigid rod of `length` m between the anchors.
    pub fn distance(body1: impl Into<Option<Entity>>, body2: Entity, length: f32) -> Self {
        let kind = JointKind::Distance {
            min: length,
            max: length,
            spring: None,
        };
        Self::new(body1, body2, kind)
    }

    /// A rope: the anchors at most `max_length` m apart, free to come closer.
    pub fn rope(body1: impl Into<Option<Entity>>, body2: Entity, max_length: f32) -> Self {
        let kind = JointKind::Distance {
            min: 0.0,
            max: max_length,
            spring: None,
        };
        Self::new(body1, body2, kind)
    }

    /// A spring of `rest` m between the anchors, at `hertz` Hz with `damping_ratio`, free
    /// of limits.
    pub fn spring(
        body1: impl Into<Option<Entity>>,
        body2: Entity,
        rest: f32,
        hertz: f32,
        damping_ratio: f32,
    ) -> Self {
        let spring = JointSpring {
            rest,
            hertz,
            damping_ratio,
        };
        let kind = JointKind::Distance {
            min: 0.0,
            max: f32::INFINITY,
            spring: Some(spring),
        };
        Self::new(body1, body2, kind)
    }

    /// The anchors in each body's frame, m.
    pub fn with_local_anchors(mut self, anchor1: Vec3, anchor2: Vec3) -> Self {
        (self.local_anchor1, self.local_anchor2) = (anchor1, anchor2);
        self
    }

    /// Angle limits of a revolute joint (rad), offset limits of a prismatic or distance
    /// joint (m), twist limits of a ball joint (rad). No effect on a weld.
    pub fn with_limits(mut self, min: f32, max: f32) -> Self {
        match &mut self.kind {
            JointKind::Revolute { limits, .. } | JointKind::Prismatic { limits, .. } => {
                *limits = Some((min, max));
            }
            JointKind::Distance {
                min: lo, max: hi, ..
            } => (*lo, *hi) = (min, max),
            JointKind::Spherical { twist, .. } => *twist = Some((min, max)),
            JointKind::Fixed => {}
        }
        self
    }

    /// A motor on a revolute (rad/s, N·m) or prismatic (m/s, N) joint. No effect on the
    /// other kinds.
    pub fn with_motor(mut self, target_speed: f32, max_force: f32) -> Self {
        if let JointKind::Revolute { motor, .. } | JointKind::Prismatic { motor, .. } =
            &mut self.kind
        {
            *motor = Some(JointMotor {
                target_speed,
                max_force,
            });
        }
        self
    }

    /// Breaks beyond `force` N ([`JointBroken`]).
    pub fn with_break_force(mut self, force: f32) -> Self {
        self.break_force = force;
        self
    }

    /// Lets the two bodies collide with each other.
    pub fn with_collisions(mut self) -> Self {
        self.collide_connected = true;
        self
    }
}
