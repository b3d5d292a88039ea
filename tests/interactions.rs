//! The interaction matrix: ordinary game interactions, each with its target awake and
//! asleep, under 30, 60 and 240 Hz render pacing (frames of 2, 1 and 0-or-1 fixed steps),
//! with the plugin's defaults (sleeping on). Each case asserts the analytic outcome (the
//! 1-D impact formulas, momentum, free fall) and that awake and asleep agree.
//!
//! A sleeping body stands in the fixed set as a static collider, so an impact on it used
//! to be solved as on a wall: the arriving ball bounced back and the sleeper woke at rest.
//! The sleepers an awake body is about to reach now wake before the step that reaches
//! them, and are solved as dynamic bodies in it.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// The render rates every case runs under.
const RENDERS: [Pacing; 3] = [
    Pacing::Render(30.0),
    Pacing::Render(60.0),
    Pacing::Render(240.0),
];

/// Momentum and the impact formulas hold to 1 % of the approach speed: the soft contact
/// and the substep error stay well inside it, a wall-like sleeper is off by 100 %.
const IMPACT_TOL: f32 = 0.01;

/// Runs `case` for the target awake and asleep under each render rate, and returns the
/// outcomes (`[awake, asleep]` per pacing) for the caller to compare.
fn matrix<T>(case: impl Fn(&mut App, bool, Pacing) -> T) -> Vec<[T; 2]> {
    RENDERS
        .iter()
        .map(|&pacing| {
            let run = |target_asleep: bool| {
                let mut app = paced_app(pacing, true);
                case(&mut app, target_asleep, pacing)
            };
            [run(false), run(true)]
        })
        .collect()
}

/// Steps until every one of `bodies` sleeps (at most 3 s), and fails if they don't.
fn sleep_until_still(app: &mut App, bodies: &[Entity], what: &str) {
    for _ in 0..180 {
        if bodies.iter().all(|&b| asleep(app, b)) {
            return;
        }
        step(app, 1);
    }
    panic!("{what}: the target never fell asleep");
}

fn frictionless(app: &mut App, e: Entity, restitution: f32) {
    app.world_mut()
        .entity_mut(e)
        .insert((Restitution(restitution), Friction(0.0)));
}

/// Two balls in zero g, the target resting, the other arriving at `v`: the 1-D formulas
/// for masses m1 (arriving) and m2 and restitution e.
fn ball_hits_ball(m1: f32, m2: f32, e: f32) {
    let v = 3.0;
    let outcomes = matrix(|app, target_asleep, pacing| {
        app.insert_resource(Gravity(Vec3::ZERO));
        let target = ball(app, 0.25, m2, Vec3::ZERO, Vec3::ZERO);
        frictionless(app, target, e);
        if target_asleep {
            sleep_until_still(app, &[target], &format!("{pacing:?}"));
        }
        // 0.5 m apart: reached in a sixth of a second, before an awake target sleeps.
        let arriving = ball(app, 0.25, m1, Vec3::new(-1.0, 0.0, 0.0), Vec3::X * v);
        frictionless(app, arriving, e);
        step(app, 30);
        let (u1, u2) = (vel(app, arriving).linear, vel(app, target).linear);
        let what = format!("{pacing:?}, target asleep {target_asleep}, m {m1}:{m2}, e {e}");
        let expect1 = (m1 - e * m2) * v / (m1 + m2);
        let expect2 = (1.0 + e) * m1 * v / (m1 + m2);
        assert_near(
            u1.x,
            expect1,
            IMPACT_TOL * v,
            &format!("{what}: arriving ball"),
        );
        assert_near(u2.x, expect2, IMPACT_TOL * v, &format!("{what}: target"));
        let p = m1 * u1 + m2 * u2;
        assert_near(
            p.x,
            m1 * v,
            IMPACT_TOL * m1 * v,
            &format!("{what}: momentum"),
        );
        (u1.x, u2.x)
    });
    for [awake, asleep] in outcomes {
        assert_near(
            asleep.0,
            awake.0,
            IMPACT_TOL * v,
            "arriving ball, awake vs asleep",
        );
        assert_near(asleep.1, awake.1, IMPACT_TOL * v, "target, awake vs asleep");
    }
}

#[test]
fn elastic_ball_hits_an_equal_ball() {
    ball_hits_ball(1.0, 1.0, 1.0);
}

#[test]
fn elastic_ball_hits_a_heavier_ball() {
    ball_hits_ball(1.0, 3.0, 1.0);
}

#[test]
fn inelastic_ball_hits_an_equal_ball() {
    ball_hits_ball(1.0, 1.0, 0.0);
}

#[test]
fn half_elastic_ball_hits_a_lighter_ball() {
    ball_hits_ball(2.0, 1.0, 0.5);
}

/// A box sliding at 4 m/s on a frictionless floor into a resting 1 kg box, e = 0: both
/// go on together at 2 m/s.
#[test]
fn sliding_box_pushes_a_box_across_a_frictionless_floor() {
    let v = 4.0;
    let outcomes = matrix(|app, target_asleep, pacing| {
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        frictionless(app, floor, 0.0);
        let half = Vec3::splat(0.25);
        let target = cuboid(app, half, 1.0, Vec3::new(0.0, 0.25, 0.0));
        frictionless(app, target, 0.0);
        if target_asleep {
            sleep_until_still(app, &[target], &format!("{pacing:?}"));
        }
        let pusher = cuboid(app, half, 1.0, Vec3::new(-1.0, 0.25, 0.0));
        frictionless(app, pusher, 0.0);
        app.world_mut()
            .entity_mut(pusher)
            .insert(Velocity::linear(Vec3::X * v));
        step(app, 30);
        let what = format!("{pacing:?}, target asleep {target_asleep}");
        let (u1, u2) = (vel(app, pusher).linear.x, vel(app, target).linear.x);
        assert_near(u1 + u2, v, IMPACT_TOL * v, &format!("{what}: momentum"));
        assert_near(u2, v / 2.0, IMPACT_TOL * v, &format!("{what}: pushed box"));
        assert_near(u1, v / 2.0, IMPACT_TOL * v, &format!("{what}: pusher"));
        pos(app, target).x
    });
    for [awake, asleep] in outcomes {
        // Half a step's travel: where within a step the impact falls.
        assert_near(
            asleep,
            awake,
            v * H / 2.0,
            "pushed box's place, awake vs asleep",
        );
    }
}

/// A 1 kg ball at 6 m/s hits the top of a resting stack of three 1 kg boxes on a
/// frictionless floor: horizontal momentum is conserved through the whole stack.
#[test]
fn projectile_hits_a_resting_stack() {
    let v = 6.0;
    let outcomes = matrix(|app, target_asleep, pacing| {
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        frictionless(app, floor, 0.0);
        let half = Vec3::splat(0.25);
        let stack: Vec<_> = (0..3)
            .map(|i| cuboid(app, half, 1.0, Vec3::new(0.0, 0.25 + 0.5 * i as f32, 0.0)))
            .collect();
        if target_asleep {
            sleep_until_still(app, &stack, &format!("{pacing:?}"));
        } else {
            step(app, 10); // Settled on each other, not yet asleep.
        }
        let shot = ball(app, 0.1, 1.0, Vec3::new(-1.0, 1.25, 0.0), Vec3::X * v);
        app.world_mut().entity_mut(shot).insert(GravityScale(0.0));
        step(app, 20);
        let what = format!("{pacing:?}, stack asleep {target_asleep}");
        let p: f32 = stack
            .iter()
            .chain([&shot])
            .map(|&e| vel(app, e).linear.x)
            .sum();
        assert_near(
            p,
            v,
            IMPACT_TOL * v,
            &format!("{what}: horizontal momentum"),
        );
        let top = vel(app, stack[2]).linear.x;
        assert!(top > 0.5, "{what}: the top box was knocked on ({top} m/s)");
        stack.iter().map(|&e| vel(app, e).linear.x).sum::<f32>()
    });
    for [awake, asleep] in outcomes {
        assert_near(
            asleep,
            awake,
            IMPACT_TOL * v,
            "stack's momentum, awake vs asleep",
        );
    }
}

/// A box dropped from 1 m onto a resting box on the floor comes to rest on it: the
/// lower box neither sinks nor slides.
#[test]
fn box_lands_on_a_resting_box() {
    let outcomes = matrix(|app, target_asleep, pacing| {
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let half = Vec3::splat(0.25);
        let lower = cuboid(app, half, 1.0, Vec3::new(0.0, 0.25, 0.0));
        if target_asleep {
            sleep_until_still(app, &[lower], &format!("{pacing:?}"));
        }
        let falling = cuboid(app, half, 1.0, Vec3::new(0.0, 1.75, 0.0));
        // The fall from 1 m takes 0.45 s; the rest, half a second more.
        step(app, 60);
        let what = format!("{pacing:?}, lower box asleep {target_asleep}");
        assert_near_vec(pos(app, lower), Vec3::new(0.0, 0.25, 0.0), 2e-3, &what);
        assert_near(pos(app, falling).y, 0.75, 4e-3, &format!("{what}: on top"));
        assert!(vel(app, falling).linear.length() < 0.05, "{what}: at rest");
        pos(app, falling).y
    });
    for [awake, asleep] in outcomes {
        assert_near(asleep, awake, 2e-3, "resting height, awake vs asleep");
    }
}

/// A box resting on a static platform falls freely when the platform is despawned.
#[test]
fn support_is_removed() {
    let outcomes = matrix(|app, target_asleep, pacing| {
        let platform = app
            .world_mut()
            .spawn((
                Collider::cuboid(1.0, 0.1, 1.0),
                Transform::from_xyz(0.0, 0.9, 0.0),
            ))
            .id();
        let crate_ = cuboid(app, Vec3::splat(0.25), 1.0, Vec3::new(0.0, 1.25, 0.0));
        if target_asleep {
            sleep_until_still(app, &[crate_], &format!("{pacing:?}"));
        } else {
            step(app, 10);
        }
        let y0 = pos(app, crate_).y;
        app.world_mut().entity_mut(platform).despawn();
        step(app, 12);
        let what = format!("{pacing:?}, crate asleep {target_asleep}");
        let t = 12.0 * H;
        assert_free_fall(y0 - pos(app, crate_).y, t, &what);
        y0 - pos(app, crate_).y
    });
    for [awake, asleep] in outcomes {
        assert_near(asleep, awake, 1e-3, "drop, awake vs asleep");
    }
}
