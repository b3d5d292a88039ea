//! Mouse interaction through bevy_picking: press on a body to select it, drag to pull it
//! with a critically damped spring towards the cursor on a plane facing the camera (the
//! body keeps colliding while dragged), release to throw. Needs a picking backend: the demo
//! uses tumble's own, [`PhysicsPickingPlugin`](crate::picking::PhysicsPickingPlugin). While a body is held, the orbit camera is paused. The spring itself
//! is [`crate::interaction::pull_dragged`], tested headless.

use bevy::prelude::*;
use bevy_panorbit_camera::PanOrbitCamera;

use crate::body::{ExternalForce, RigidBody, Sleeping};
pub use crate::interaction::{DragPullPlugin, Dragged, Selected};

/// Picking a body and dragging it with the mouse (a spring pulls it to the cursor).
pub struct DragBodiesPlugin;

impl Plugin for DragBodiesPlugin {
    fn build(&self, app: &mut App) {
        app.add_observer(grab_body)
            .add_observer(move_target)
            .add_observer(release_on_drag_end)
            .add_observer(release_on_release)
            .add_plugins(DragPullPlugin);
    }
}

fn grab_body(
    ev: On<Pointer<Press>>,
    mut commands: Commands,
    bodies: Query<(&GlobalTransform, &RigidBody)>,
    selected: Query<Entity, With<Selected>>,
    cameras: Query<&GlobalTransform, With<Camera3d>>,
    mut orbit: Query<&mut PanOrbitCamera>,
) {
    if ev.button != PointerButton::Primary {
        return;
    }
    let (Ok((tf, kind)), Some(hit)) = (bodies.get(ev.entity), ev.hit.position) else {
        return;
    };
    if *kind != RigidBody::Dynamic {
        return;
    }
    for e in &selected {
        commands.entity(e).remove::<Selected>();
    }
    let camera = cameras
        .get(ev.hit.camera)
        .map(|c| c.translation())
        .unwrap_or(Vec3::Z * 10.0);
    let local_anchor = tf.affine().inverse().transform_point3(hit);
    let plane_normal = (camera - hit).normalize_or(Vec3::Z);
    commands.entity(ev.entity).remove::<Sleeping>().insert((
        Selected,
        Dragged {
            local_anchor,
            target: hit,
            plane_normal,
        },
    ));
    for mut cam in &mut orbit {
        cam.enabled = false;
    }
}

fn move_target(
    ev: On<Pointer<Drag>>,
    mut dragged: Query<(&GlobalTransform, &mut Dragged)>,
    cameras: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
) {
    let Ok((tf, mut d)) = dragged.get_mut(ev.entity) else {
        return;
    };
    let Some((camera, cam_tf)) = cameras.iter().next() else {
        return;
    };
    let Ok(ray) = camera.viewport_to_world(cam_tf, ev.pointer_location.position) else {
        return;
    };
    let anchor = tf.transform_point(d.local_anchor);
    let Ok(normal) = Dir3::new(d.plane_normal) else {
        return;
    };
    if let Some(t) = ray.intersect_plane(anchor, InfinitePlane3d { normal }) {
        d.target = ray.get_point(t);
    }
}

/// The end of a drag is reported to the dragged body wherever the pointer is released
/// (`Release` only reaches an entity under the pointer, and after a fast drag that is often
/// none: the body stayed held, seen in a real window).
fn release_on_drag_end(ev: On<Pointer<DragEnd>>, release: ReleaseParams) {
    if ev.button == PointerButton::Primary {
        release_held(release);
    }
}

/// A press and release without a drag.
fn release_on_release(ev: On<Pointer<Release>>, release: ReleaseParams) {
    if ev.button == PointerButton::Primary {
        release_held(release);
    }
}

#[derive(bevy::ecs::system::SystemParam)]
struct ReleaseParams<'w, 's> {
    commands: Commands<'w, 's>,
    forces: Query<'w, 's, &'static mut ExternalForce, With<Dragged>>,
    all_dragged: Query<'w, 's, Entity, With<Dragged>>,
    orbit: Query<'w, 's, &'static mut PanOrbitCamera>,
}

/// Lets go of whatever is held: the force goes back to zero and the camera orbits again.
fn release_held(p: ReleaseParams) {
    let ReleaseParams {
        mut commands,
        mut forces,
        all_dragged,
        mut orbit,
    } = p;
    for e in &all_dragged {
        commands.entity(e).remove::<Dragged>();
        if let Ok(mut f) = forces.get_mut(e) {
            *f = ExternalForce::default();
        }
    }
    for mut cam in &mut orbit {
        cam.enabled = true;
    }
}
