//! Bounded planes are walls and ledges of finite size: a ball resting on one stays, a ball
//! just beyond its edge falls past it, and a ball rolling over the edge tips off.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn ledge(app: &mut App) {
    app.world_mut()
        .spawn((Collider::plane_rect(1.0, 1.0), Transform::default()));
}

#[test]
fn ball_rests_on_a_ledge_and_misses_beyond_it() {
    let mut app = app();
    ledge(&mut app);
    let on = ball(&mut app, 0.25, 1.0, Vec3::new(0.5, 0.25, 0.0), Vec3::ZERO);
    let off = ball(&mut app, 0.25, 1.0, Vec3::new(1.5, 1.0, 0.0), Vec3::ZERO);
    step(&mut app, 60);
    assert!(
        (pos(&app, on).y - 0.25).abs() < 1e-3,
        "rests at {}",
        pos(&app, on)
    );
    // Free fall from 1.0 m for 1 s (semi-implicit, hs = 1/240): y = 1 − ½g(1 + 1/240).
    let expected = 1.0 - 0.5 * 9.81 * (1.0 + 1.0 / 240.0);
    assert!(
        (pos(&app, off).y - expected).abs() < 1e-4,
        "falls freely: {}",
        pos(&app, off)
    );
}

#[test]
fn ball_rolling_off_the_edge_tips_over_it() {
    let mut app = app();
    ledge(&mut app);
    let b = ball(
        &mut app,
        0.25,
        1.0,
        Vec3::new(0.0, 0.25, 0.0),
        Vec3::X * 2.0,
    );
    app.world_mut().entity_mut(b).insert(Velocity {
        linear: Vec3::X * 2.0,
        angular: Vec3::Z * -8.0,
    });
    step(&mut app, 120);
    let p = pos(&app, b);
    assert!(p.x > 1.0 && p.y < -1.0, "went over the edge: {p}");
}
