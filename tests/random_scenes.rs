//! Property tests on random scenes: spheres and boxes from 2 cm to 5 m, masses spanning
//! 1:1000, random overlaps at spawn and velocities to 50 m/s, stepped 10 s under a
//! random frame pacing.
//!
//! - In a closed box under gravity: every body stays finite, simulated and inside the
//!   box, and the total energy never rises above its start plus what overlap push-out
//!   may add. Two envelopes run in CI at a fixed seed: the full 50 m/s and 1:1000, and a
//!   gentler 20 m/s and 1:100. Over seeds 0–39 of both (`TUMBLE_PROPTEST_SEED`, 24
//!   scenes each: 1,920 scenes) 4 of the 80 runs fail on "inside", all at 1:1000 (seeds
//!   0, 18, 33, 34), each a body of 1.5–2.4 m a few millimetres past the sag bound below
//!   in a corner or on the floor: a heavier body closing on it sinks its wall contact by
//!   about v·√(M/m)/ω, which no stiffness rule asks for (a known limit, left open).
//!   The CI seed passes. The energy allowance, stated: each body that starts
//!   overlapping another may be given at most ½·m·v_push² of kinetic energy (v_push =
//!   `max_push_out`, the cap the share rule keeps every push below) and lifted by at
//!   most the largest size in the scene, m·g·d_max.
//! - In zero gravity without walls (sleeping off, since a body falling asleep drops its
//!   last few cm/s): total linear momentum is conserved to f32 round-off.

mod common;
use bevy::prelude::*;
use common::*;
use proptest::prelude::*;
use tumble::prelude::*;

const HALF_ROOM: f32 = 10.0;

/// The proptest seed: fixed (so CI is repeatable), or `TUMBLE_PROPTEST_SEED` to explore.
fn prop_seed() -> proptest::test_runner::RngSeed {
    let seed = std::env::var("TUMBLE_PROPTEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok());
    proptest::test_runner::RngSeed::Fixed(seed.unwrap_or(0x7475_6d62_6c65))
}

#[derive(Clone, Debug)]
struct BodySpec {
    sphere: bool,
    /// Radius or half extents, m.
    size: Vec3,
    mass: f32,
    pos: Vec3,
    vel: Vec3,
    spin: Vec3,
    restitution: f32,
    friction: f32,
}

/// Bodies with speeds up to `max_speed` m/s and masses spanning `decades` decades.
fn body_spec(max_speed: f32, decades: f32) -> impl Strategy<Value = BodySpec> {
    (
        any::<bool>(),
        (0.01f32..2.5, 0.01f32..2.5, 0.01f32..2.5),
        0.0f32..decades,
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        0.0f32..1.0,
        0.0f32..1.0,
    )
        .prop_map(move |(sphere, s, log_m, p, v, w, e, mu)| BodySpec {
            sphere,
            size: if sphere {
                Vec3::splat(s.0)
            } else {
                Vec3::new(s.0, s.1, s.2)
            },
            mass: 10f32.powf(log_m),
            pos: Vec3::new(p.0, p.1, p.2),
            vel: Vec3::new(v.0, v.1, v.2).normalize_or_zero() * max_speed * v.0.abs(),
            spin: Vec3::new(w.0, w.1, w.2) * 10.0,
            restitution: e,
            friction: mu,
        })
}

fn pacing() -> impl Strategy<Value = Pacing> {
    prop_oneof![
        Just(Pacing::OneStep),
        Just(Pacing::Render(240.0)),
        Just(Pacing::Render(144.0)),
        Just(Pacing::Render(30.0)),
    ]
}

fn collider(b: &BodySpec) -> Collider {
    if b.sphere {
        Collider::sphere(b.size.x)
    } else {
        Collider::cuboid(b.size.x, b.size.y, b.size.z)
    }
}

/// Spawns the bodies, placed so each fits inside a room of half size `room` (positions
/// are fractions of the free space), and returns them.
fn spawn(app: &mut App, specs: &[BodySpec], room: f32) -> Vec<Entity> {
    specs
        .iter()
        .map(|b| {
            let reach = b.size.length();
            let p = b.pos * (room - reach).max(0.0);
            app.world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    collider(b),
                    Mass(b.mass),
                    Transform::from_translation(p),
                    Velocity {
                        linear: b.vel,
                        angular: b.spin,
                    },
                    Restitution(b.restitution),
                    Friction(b.friction),
                ))
                .id()
        })
        .collect()
}

/// Kinetic energy (translation and rotation) plus potential energy in gravity g (up +y).
fn energy(app: &App, bodies: &[Entity], specs: &[BodySpec], g: f32) -> f32 {
    bodies
        .iter()
        .zip(specs)
        .map(|(&e, b)| {
            let (v, q, p) = (vel(app, e), rot(app, e), pos(app, e));
            let inertia = collider(b).shape.principal_inertia(b.mass);
            let w_body = q.inverse() * v.angular;
            0.5 * b.mass * v.linear.length_squared()
                + 0.5 * (inertia * w_body * w_body).element_sum()
                + b.mass * g * p.y
        })
        .sum()
}

/// Bodies whose bounding spheres overlap another's at spawn (a superset of those that
/// truly overlap).
fn overlapping(app: &App, bodies: &[Entity], specs: &[BodySpec]) -> Vec<usize> {
    (0..bodies.len())
        .filter(|&i| {
            (0..bodies.len()).any(|j| {
                j != i
                    && pos(app, bodies[i]).distance(pos(app, bodies[j]))
                        < specs[i].size.length() + specs[j].size.length()
            })
        })
        .collect()
}

fn check_closed_room(
    specs: &[BodySpec],
    pacing: Pacing,
    sleeping: bool,
) -> Result<(), TestCaseError> {
    let mut app = paced_app(pacing, sleeping);
    closed_room(&mut app, HALF_ROOM);
    let bodies = spawn(&mut app, specs, HALF_ROOM);
    let push = app.world().resource::<SolverSettings>().max_push_out;
    let d_max = specs
        .iter()
        .map(|b| 2.0 * b.size.max_element())
        .fold(0.0, f32::max);
    let allowance: f32 = overlapping(&app, &bodies, specs)
        .iter()
        .map(|&i| specs[i].mass * (0.5 * push * push + G * d_max))
        .sum();
    // Resting sag at the stiffest the solver goes (a quarter of the substep rate at
    // `max_substeps`), under the heaviest load the scene can put on its lightest
    // body, on both of that body's contacts: 2·(m_max/m_min)·g/ω². Up to 8.6 mm for
    // a 1000:1 scene, a lot for a 2 cm box: the documented limit of the range.
    let settings = *app.world().resource::<SolverSettings>();
    let omega = std::f32::consts::TAU * 0.25 * 60.0 * settings.max_substeps as f32;
    let masses = specs.iter().map(|b| b.mass);
    let ratio = masses.clone().fold(0.0, f32::max) / masses.fold(f32::MAX, f32::min);
    let sag = 2.0 * ratio * G / (omega * omega);
    let e0 = energy(&app, &bodies, specs, G);
    // f32 round-off on energies of up to ~1e7 J.
    let slack = 1e-4 * e0.abs().max(1.0);
    for k in 0..600 {
        step(&mut app, 1);
        for (&e, b) in bodies.iter().zip(specs) {
            prop_assert!(
                rejected_field(&app, e).is_none(),
                "step {k}: body {e} rejected"
            );
            let p = pos(&app, e);
            prop_assert!(p.is_finite() && vel(&app, e).linear.is_finite());
            // Inside the room: the centre at least the smallest half size from
            // every wall, less the sag above and 1 cm (speculative slack, round-off).
            let inner = HALF_ROOM - b.size.min_element() + sag + 0.01;
            prop_assert!(
                p.abs().max_element() <= inner,
                "step {k}: body {e} at {p} ({b:?})"
            );
        }
        let e_now = energy(&app, &bodies, specs, G);
        prop_assert!(
            e_now <= e0 + allowance + slack,
            "step {k}: energy {e_now} J above {e0} J + {allowance} J push-out allowance"
        );
    }
    Ok(())
}

proptest! {
    // A fixed seed, so CI runs the same 24 scenes every time (see the module docs).
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: prop_seed(),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// A gentler envelope: speeds to 20 m/s, masses 1:100. Its failing seeds became
    /// `regress_turning_rod_inertia.rs` and `regress_bounce_into_wall.rs`.
    #[test]
    fn random_bodies_in_a_closed_room_stay_inside_and_gain_no_energy(
        specs in prop::collection::vec(body_spec(20.0, 2.0), 2..10),
        pacing in pacing(),
        sleeping in any::<bool>(),
    ) {
        check_closed_room(&specs, pacing, sleeping)?;
    }

    /// The full envelope: speeds to 50 m/s, masses 1:1000. The failures it has found are
    /// held as regressions in `regress_squeezed_box_restitution.rs` and `continuous.rs`.
    #[test]
    fn random_bodies_at_50_m_s_and_1000_to_1_stay_inside_and_gain_no_energy(
        specs in prop::collection::vec(body_spec(50.0, 3.0), 2..10),
        pacing in pacing(),
        sleeping in any::<bool>(),
    ) {
        check_closed_room(&specs, pacing, sleeping)?;
    }

    #[test]
    fn random_bodies_in_zero_gravity_conserve_momentum(
        specs in prop::collection::vec(body_spec(50.0, 3.0), 2..10),
        pacing in pacing(),
    ) {
        let mut app = paced_app(pacing, false);
        app.insert_resource(Gravity(Vec3::ZERO));
        // The speed cap (400 m/s by default) is a blow-up guard, not physics: a light body
        // squeezed out between two heavy ones can be thrown faster, and clamping it drops
        // momentum. Conservation is a property of the contacts, so raise the cap here.
        app.world_mut().resource_mut::<SolverSettings>().max_linear_speed = 1e5;
        let bodies = spawn(&mut app, &specs, 3.0);
        let momentum = |app: &App| -> Vec3 {
            bodies.iter().zip(&specs).map(|(&e, b)| b.mass * vel(app, e).linear).sum()
        };
        let scale: f32 = specs.iter().map(|b| b.mass * b.vel.length()).sum::<f32>() + 1.0;
        let p0 = momentum(&app);
        for k in 0..600 {
            step(&mut app, 1);
            let p = momentum(&app);
            // Equal and opposite impulses; f32 round-off over 600 steps × 4 substeps.
            prop_assert!(
                (p - p0).length() <= 1e-4 * scale,
                "step {k}: momentum {p} drifted from {p0} (scale {scale})"
            );
        }
    }
}
