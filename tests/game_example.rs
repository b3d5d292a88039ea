//! The game example (`examples/game/`) played headless at a 144 Hz render: the jump
//! collects the pickup, shots pass through their shooter and hit the target, the
//! platform carries its crate. The rules are the example's own `logic.rs`.

mod common;
#[path = "../examples/game/logic.rs"]
mod logic;

use bevy::prelude::*;
use common::*;
use logic::{Controls, Crate, Platform, Player, Projectile, Score};
use tumble::prelude::*;

#[derive(Resource, Default)]
struct PlayerHits(u32);

fn watch_player(
    mut hits: ResMut<PlayerHits>,
    mut starts: MessageReader<CollisionStart>,
    players: Query<(), With<Player>>,
    shots: Query<(), With<Projectile>>,
) {
    for s in starts.read() {
        let pair = [s.collider1, s.collider2];
        if pair.iter().any(|&e| players.contains(e)) && pair.iter().any(|&e| shots.contains(e)) {
            hits.0 += 1;
        }
    }
}

#[test]
fn the_game_plays_headless() {
    let mut app = paced_app_with(Pacing::Render(144.0), true, |app| {
        app.add_plugins((TransformInterpolationPlugin::default(), logic::plugin))
            .init_resource::<PlayerHits>()
            .add_systems(Update, watch_player);
    });
    step(&mut app, 30);
    let player = app
        .world_mut()
        .query_filtered::<Entity, With<Player>>()
        .single(app.world())
        .unwrap();
    // Jump: the pickup 2 m up is on the way (the player's top reaches 0.6 + v²/2g + 0.6).
    app.world_mut().resource_mut::<Controls>().jump = true;
    step(&mut app, 90);
    assert_eq!(
        app.world().resource::<Score>().pickups,
        1,
        "the jump collects the pickup"
    );
    assert_near(pos(&app, player).y, 0.6, 0.01, "landed again");
    // Fire three shots at the target 8 m away at 20 m/s.
    for _ in 0..3 {
        app.world_mut().resource_mut::<Controls>().fire = true;
        step(&mut app, 20);
    }
    step(&mut app, 30);
    let score = app.world().resource::<Score>();
    assert!(score.hits >= 1, "{score:?}");
    // A shot arrives at its speed (no gravity on it): the impact speed says so.
    assert_near(score.hardest_hit, logic::SHOT_SPEED, 0.5, "impact speed");
    assert_eq!(
        app.world().resource::<PlayerHits>().0,
        0,
        "shots never touch their shooter"
    );
    assert_near(
        vel(&app, player).linear.x,
        0.0,
        1e-3,
        "the player was not pushed",
    );
    // The platform swings 3 m (peak 1.6 m/s², below μ·g = 4.9): the crate rides it.
    let one = |app: &mut App, f: fn(&mut World) -> Entity| f(app.world_mut());
    let platform = one(&mut app, |w| {
        w.query_filtered::<Entity, With<Platform>>()
            .single(w)
            .unwrap()
    });
    let crate_ = one(&mut app, |w| {
        w.query_filtered::<Entity, With<Crate>>().single(w).unwrap()
    });
    let at = app
        .world()
        .resource::<PhysicsWorld>()
        .kinematic_pose(platform)
        .unwrap()
        .0;
    assert!(at.x > -5.0, "the platform moved: {at}");
    assert_near(
        pos(&app, crate_).x,
        at.x,
        0.02,
        "the crate rides the platform",
    );
    assert_near(pos(&app, crate_).y, at.y + 0.4, 0.01, "on top of it");
}
