//! Overlap at spawn: hundreds of boxes spawned into one point (a spawn bug in a game, an
//! editor paste) separate calmly. Were every pair to push at the full 3 m/s and, with
//! coincident centres, all in the same direction, the pile would squeeze out into a line
//! whose ends fly off at 73 m/s. So a coincident pair pushes in a direction hashed from
//! the pair, and each body's push-out is shared among its overlaps (the limit over k^0.6
//! for k overlaps), so the pile swells like a ball below the push-out limit. Each test
//! runs three spawn orders (other colliders spawned first shift every hashed direction).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

const N: usize = 200;
const HALF: f32 = 0.25;

fn pile(app: &mut App, at: Vec3, shift: usize) -> Vec<Entity> {
    for _ in 0..shift {
        let far = Transform::from_xyz(1000.0, 0.0, 0.0);
        app.world_mut().spawn((Collider::sphere(0.1), far));
    }
    (0..N)
        .map(|_| cuboid(app, Vec3::splat(HALF), 1.0, at))
        .collect()
}

const SHIFTS: [usize; 3] = [0, 7, 100];

/// Deepest overlap among this step's contacts, m (0 when none).
fn deepest(app: &App) -> f32 {
    app.world().resource::<PhysicsWorld>().deepest_overlap()
}

#[test]
fn two_hundred_boxes_at_one_point_in_zero_g_part_below_the_push_out_limit() {
    for shift in SHIFTS {
        let mut app = app_without_gravity();
        let limit = app.world().resource::<SolverSettings>().max_push_out;
        let boxes = pile(&mut app, Vec3::ZERO, shift);
        let mut peak = 0.0f32;
        for _ in 0..240 {
            step(&mut app, 1);
            for &b in &boxes {
                peak = peak.max(vel(&app, b).linear.length());
            }
        }
        assert!(
            peak <= limit,
            "order {shift}: peak speed {peak} m/s, limit {limit}"
        );
        let deep = deepest(&app);
        assert!(
            deep < 0.01,
            "order {shift}: still overlapping by {deep} m after 4 s"
        );
        // Momentum: every push is equal and opposite; f32 round-off over 200 bodies.
        let p: Vec3 = boxes.iter().map(|&b| vel(&app, b).linear).sum();
        assert!(
            p.length() < 1e-3 * N as f32,
            "order {shift}: net momentum {p}"
        );
    }
}

#[test]
fn two_hundred_boxes_at_one_point_on_a_floor_settle_without_leaving() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let limit = app.world().resource::<SolverSettings>().max_push_out;
    let boxes = pile(&mut app, Vec3::new(0.0, HALF, 0.0), 0);
    let (mut peak_up, mut lowest) = (0.0f32, f32::INFINITY);
    for _ in 0..480 {
        step(&mut app, 1);
        for &b in &boxes {
            peak_up = peak_up.max(vel(&app, b).linear.y);
            lowest = lowest.min(pos(&app, b).y);
        }
    }
    assert!(peak_up <= limit, "thrown up at {peak_up} m/s");
    // Nothing goes through the floor: no box's centre ever reaches it, even while the
    // whole pile presses on the bottom layer (measured: down to 0.16 m, a fifth of a box
    // into the floor, for the moments the pile's pushes press on it)...
    assert!(lowest > 0.0, "a box sank to y = {lowest}");
    // 200 boxes of 0.5 m cover 50 m² in one layer, a disc of radius 4.0 m: the pile
    // stays within twice that.
    for &b in &boxes {
        let p = pos(&app, b);
        assert!(p.xz().length() < 10.0, "box {b} left to {p}");
        assert!(
            vel(&app, b).linear.length() < 0.1,
            "box {b} still moving after 8 s"
        );
        // ...and at rest the floor holds every box to within the soft contact's sag:
        // g/ω² = 0.07 mm at 60 Hz (30 Hz doubled against a static body), 5 mm allowed
        // for boxes lying on tilted neighbours.
        assert!(
            pos(&app, b).y > HALF - 0.005,
            "box {b} rests in the floor: {}",
            pos(&app, b)
        );
    }
}
