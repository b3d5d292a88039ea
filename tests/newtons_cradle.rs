//! The cradle scene (`6_newtons_cradle`): five elastic balls on pairs of strings
//! (distance joints), 6 cm apart. The first, let go from 40° (0.446 m up), hits the row
//! at √(2gh) = 2.96 m/s; each ball hands the momentum to the next across its gap, the
//! three middle ones end where they hung, and the last swings out to nearly the first's
//! height. The strings hold their length throughout.
//!
//! Why gaps: touching balls are one contact group to the soft step, which shares an
//! impact among all of them at once (measured with touching balls: the far ball rose
//! 0.075 m of 0.446, three balls left together). A gap wider than one step's travel
//! (2.96 m/s × 1/60 s = 4.9 cm) makes every impact a pair's.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::scene::SceneDesc;

#[test]
fn the_far_ball_swings_out_and_the_middle_ones_stay() {
    let scene = SceneDesc::load("assets/scenes/6_newtons_cradle.scene.ron").unwrap();
    let mut app = app();
    let balls = scene.spawn_into(app.world_mut());
    assert_eq!(balls.len(), 5);
    let rest_y = 1.5921;
    let drop = pos(&app, balls[0]).y - rest_y;
    let impact = (2.0 * G * drop).sqrt();
    let rest_x: Vec<f32> = balls.iter().map(|&b| pos(&app, b).x).collect();
    let (mut highest, mut longest) = (0.0f32, 0.0f32);
    // Half a period of the 1.9 m pendulum is 1.38 s: the first ball's fall, the far
    // ball's rise.
    for _ in 0..90 {
        step(&mut app, 1);
        highest = highest.max(pos(&app, balls[4]).y - rest_y);
        for (k, &b) in balls.iter().enumerate() {
            for z in [-0.6, 0.6] {
                let anchor = Vec3::new(-1.0 + 0.56 * k as f32, 3.5, z);
                longest = longest.max(pos(&app, b).distance(anchor));
            }
        }
    }
    assert!(
        highest > 0.9 * drop,
        "the far ball rose {highest:.3} m of the first's {drop:.3} m"
    );
    // The first and the middle ones are back where they hung, nearly still: each passed
    // the momentum on across its gap.
    for (k, &b) in balls[..4].iter().enumerate() {
        let off = pos(&app, b).x - rest_x[k];
        let v = vel(&app, b).linear.length();
        let start = if k == 0 { -1.0 - rest_x[0] } else { 0.0 };
        assert!(
            (off - start).abs() < 0.02 && v < 0.1 * impact,
            "ball {k} is {off:.3} m from where it hung, at {v:.2} m/s"
        );
    }
    assert!(longest < 2.0 * 1.005, "a string stretched to {longest} m");
}
