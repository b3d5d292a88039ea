//! Smooth motion at any frame rate: physics poses are kept as the last two fixed steps'
//! results and `Transform` is shown blended between them by the fixed clock's overstep.
//! Before the next fixed step the true pose goes back into `Transform`, so physics never
//! sees a blended pose. A `Transform` the user changed in between is kept as the truth.

use bevy::app::RunFixedMainLoopSystems;
use bevy::prelude::*;

use crate::PhysicsSystems;
use crate::body::RigidBody;

pub struct InterpolationPlugin;

/// The last two physics poses of a body, and the pose last shown.
#[derive(Component, Clone, Copy, Debug)]
pub struct PoseHistory {
    previous: Isometry3d,
    current: Isometry3d,
    shown: Option<Isometry3d>,
}

impl Plugin for InterpolationPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(FixedUpdate, record_poses.after(PhysicsSystems::Writeback))
            .add_systems(
                RunFixedMainLoop,
                (
                    restore_poses.in_set(RunFixedMainLoopSystems::BeforeFixedMainLoop),
                    blend_poses.in_set(RunFixedMainLoopSystems::AfterFixedMainLoop),
                ),
            );
    }
}

fn iso(t: &Transform) -> Isometry3d {
    Isometry3d::new(t.translation, t.rotation)
}

fn record_poses(
    mut commands: Commands,
    mut q: Query<(Entity, &Transform, Option<&mut PoseHistory>), With<RigidBody>>,
) {
    for (e, t, history) in &mut q {
        match history {
            Some(mut h) => {
                h.previous = h.current;
                h.current = iso(t);
                h.shown = None;
            }
            None => {
                commands.entity(e).insert(PoseHistory {
                    previous: iso(t),
                    current: iso(t),
                    shown: None,
                });
            }
        }
    }
}

fn restore_poses(mut q: Query<(&mut Transform, &mut PoseHistory)>) {
    for (mut t, mut h) in &mut q {
        match h.shown {
            Some(shown) if shown == iso(&t) => {
                // Only a real change is written: a still body (asleep, static) must not
                // look changed, or physics would take it for the user's move and wake it.
                let true_pose = Transform {
                    translation: h.current.translation.into(),
                    rotation: h.current.rotation,
                    ..*t
                };
                t.set_if_neq(true_pose);
            }
            Some(_) => {
                // Moved by the user since we drew it: that is the new truth.
                h.current = iso(&t);
                h.previous = h.current;
            }
            None => {}
        }
        h.shown = None;
    }
}

fn blend_poses(time: Res<Time<Fixed>>, mut q: Query<(&mut Transform, &mut PoseHistory)>) {
    let a = time.overstep_fraction();
    for (mut t, mut h) in &mut q {
        let blended = if h.previous == h.current {
            h.current
        } else {
            Isometry3d::new(
                Vec3::from(h.previous.translation).lerp(h.current.translation.into(), a),
                h.previous.rotation.slerp(h.current.rotation, a),
            )
        };
        let shown = Transform {
            translation: blended.translation.into(),
            rotation: blended.rotation,
            ..*t
        };
        t.set_if_neq(shown);
        h.shown = Some(iso(&t));
    }
}
