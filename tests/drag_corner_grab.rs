//! Regression: the demo's drag spring used the body's mass at the grabbed point. Holding a
//! light box by a corner, its rotation answered the off-centre force several times faster
//! than the spring's frequency, the explicit damping overshot at 60 Hz, and the box spun
//! up until it flung the tower apart (seen in a real window with `scripts/drag_check.sh`).
//! The spring now acts through the point's effective mass, so the grabbed point behaves
//! like a unit oscillator wherever the body is held.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::interaction::{DragPullPlugin, Dragged, PULL_HERTZ};

#[test]
fn a_light_box_held_by_its_corner_settles_under_the_cursor() {
    let mut app = app();
    app.add_plugins(DragPullPlugin);
    let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::Y * 5.0);
    let corner = Vec3::splat(0.5);
    let target = Vec3::new(1.0, 6.0, 0.0);
    app.world_mut().entity_mut(b).insert(Dragged {
        local_anchor: corner,
        target,
        plane_normal: Vec3::Z,
    });
    let mut fastest = 0.0f32;
    for _ in 0..600 {
        step(&mut app, 1);
        let v = vel(&app, b);
        fastest = fastest.max(v.linear.length()).max(v.angular.length());
    }
    // The corner moves at most ~1.7 m at 3 Hz: nothing near 10 m/s or 10 rad/s.
    assert!(fastest < 10.0, "spun up to {fastest}");
    let anchor = app
        .world()
        .get::<Transform>(b)
        .unwrap()
        .transform_point(corner);
    // Hanging from the corner, the weight sags the anchor by g/ω².
    let sag = 9.81 / (std::f32::consts::TAU * PULL_HERTZ).powi(2);
    assert!(
        (anchor - target).length() < sag + 0.02,
        "corner at {anchor}, target {target}"
    );
    let v = vel(&app, b);
    assert!(
        v.linear.length() < 0.05 && v.angular.length() < 0.05,
        "still swinging: {v:?}"
    );
}
