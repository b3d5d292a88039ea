//! Turning on the motor of a door whose body slept (editing its `Joint`) left it asleep
//! and still: nothing woke a sleeper for an edit of a joint that holds it. An edited
//! joint now wakes the sleepers at its ends before the next step, as Box2D and rapier do.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn turning_on_a_sleeping_doors_motor_turns_it() {
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, true);
        // A 1 m door, hinged to the world along y at its edge (x = 0).
        let door = cuboid(
            &mut app,
            Vec3::new(0.5, 1.0, 0.05),
            10.0,
            Vec3::new(0.5, 1.0, 0.0),
        );
        let hinge = Joint::revolute(None, door, Vec3::Y)
            .with_local_anchors(Vec3::ZERO, Vec3::new(-0.5, 0.0, 0.0));
        let joint = app.world_mut().spawn(hinge).id();
        for _ in 0..120 {
            if asleep(&app, door) {
                break;
            }
            step(&mut app, 1);
        }
        assert!(asleep(&app, door), "{pacing:?}: the door fell asleep");
        let speed = 1.0;
        let motor = Joint::revolute(None, door, Vec3::Y)
            .with_local_anchors(Vec3::ZERO, Vec3::new(-0.5, 0.0, 0.0))
            .with_motor(speed, 1000.0);
        app.world_mut().entity_mut(joint).insert(motor);
        step(&mut app, 60);
        let w = vel(&app, door).angular;
        assert!(!asleep(&app, door), "{pacing:?}: woken");
        assert_near(
            w.y,
            speed,
            0.01 * speed,
            &format!("{pacing:?}: door's turn rate"),
        );
        // Turned about the hinge: a second at 1 rad/s, less the spin-up.
        let turned = (rot(&app, door) * Vec3::X).angle_between(Vec3::X);
        assert!(
            turned > 0.9 && turned < 1.01,
            "{pacing:?}: turned {turned} rad"
        );
    }
}
