//! Collision layers: pairs whose layers don't match never touch, from the first step
//! and from the step after a change, under every game pacing, sleeping on and off.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

tumble::physics_layers! {
    enum Layer { Ground, Player, Ghost }
}

/// A ball of radius 0.5 m resting on the floor at y = 0.
fn resting_ball(app: &mut App) -> Entity {
    ball(app, 0.5, 1.0, Vec3::Y * 0.5, Vec3::ZERO)
}

#[test]
fn a_ball_whose_layers_miss_the_floor_falls_through_it_freely() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        app.world_mut()
            .entity_mut(floor)
            .insert(CollisionLayers::new(Layer::Ground, LayerMask::ALL));
        // The ghost is in the floor's filter, but the floor is not in the ghost's.
        let ghost = ball(app, 0.5, 1.0, Vec3::new(-2.0, 0.5, 0.0), Vec3::ZERO);
        app.world_mut()
            .entity_mut(ghost)
            .insert(CollisionLayers::new(Layer::Ghost, Layer::Player));
        let player = ball(app, 0.5, 1.0, Vec3::new(2.0, 0.5, 0.0), Vec3::ZERO);
        app.world_mut()
            .entity_mut(player)
            .insert(CollisionLayers::new(
                Layer::Player,
                [Layer::Ground, Layer::Ghost],
            ));
        step(app, 30);
        assert_free_fall(0.5 - pos(app, ghost).y, 0.5, &format!("{what}: ghost"));
        assert_near(
            pos(app, player).y,
            0.5,
            1e-3,
            &format!("{what}: player rests"),
        );
        let contacts = app
            .world()
            .resource::<PhysicsWorld>()
            .contacts_of(ghost)
            .count();
        assert_eq!(contacts, 0, "{what}: a filtered pair has no manifold");
    });
}

#[test]
fn a_layer_change_acts_on_the_next_step() {
    // Changed on the ball, then (separately) on the floor: a resting ball (asleep when
    // sleeping is on) falls from the step after the change.
    for change_floor in [false, true] {
        under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
            let what = format!("{pacing:?} sleeping {sleeping} floor {change_floor}");
            let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
            let b = resting_ball(app);
            step(app, 120);
            assert_near(pos(app, b).y, 0.5, 1e-3, &format!("{what}: rests"));
            if sleeping {
                assert!(asleep(app, b), "{what}: asleep before the change");
            }
            let (target, layers) = if change_floor {
                (floor, CollisionLayers::new(Layer::Ground, Layer::Ghost))
            } else {
                (b, CollisionLayers::new(Layer::Player, Layer::Ghost))
            };
            app.world_mut().entity_mut(target).insert(layers);
            let y0 = pos(app, b).y;
            step(app, 30);
            assert_free_fall(y0 - pos(app, b).y, 0.5, &format!("{what}: falls"));
            // And back: the next change restores the contact.
            app.world_mut()
                .entity_mut(target)
                .insert(CollisionLayers::default());
            let v = vel(app, b).linear.y;
            step(app, 1);
            assert!(
                vel(app, b).linear.y > v,
                "{what}: stopped by the floor again ({} after {v})",
                vel(app, b).linear.y
            );
        });
    }
}

#[test]
fn filtered_pairs_cost_no_manifold_between_moving_bodies() {
    // Two stacks of boxes passing through each other in zero gravity: the ghosts fly on
    // untouched (momentum of each unchanged), the solid ones collide.
    let mut app = app_without_gravity();
    let ghost_layers = CollisionLayers::new(Layer::Ghost, Layer::Ground);
    let a = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(-2.0, 0.0, 0.0));
    let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(2.0, 0.0, 0.0));
    for (e, v) in [(a, 4.0), (b, -4.0)] {
        app.world_mut()
            .entity_mut(e)
            .insert((ghost_layers, Velocity::linear(Vec3::X * v)));
    }
    step(&mut app, 60);
    assert_near_vec(vel(&app, a).linear, Vec3::X * 4.0, 1e-6, "ghost a");
    assert_near_vec(vel(&app, b).linear, Vec3::X * -4.0, 1e-6, "ghost b");
    assert_near(pos(&app, a).x, 2.0, 1e-3, "ghost a passed through");
}
