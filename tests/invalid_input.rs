//! The invalid-input matrix (after Box2D v3's `test_invalid_input.c`): NaN, ±∞, 0, −1,
//! 1e30 and a denormal (1e-40) into every public component, resource and scene field.
//! Each case states whether the value is valid; an invalid one must be refused with its
//! field named (a body is left out with `PhysicsRejected { field }`, a resource goes
//! back to its last good value, a scene file fails to load naming the field). In every
//! case: no panic, the step ends, and a reference ball resting elsewhere in the scene
//! moves less than 1 mm, unless the value is valid and acts on every body (gravity,
//! global force, wind), when it must at least stay finite and simulated.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::limits;
use tumble::prelude::*;
use tumble::scene::SceneDesc;
use tumble::settings::GlobalForce;

const VALUES: [f32; 7] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -1.0,
    1e30,
    1e-40,
];

fn name(v: f32) -> String {
    match v {
        v if v.is_nan() => "NaN".into(),
        v if v == f32::INFINITY => "inf".into(),
        v if v == f32::NEG_INFINITY => "-inf".into(),
        v => format!("{v:e}"),
    }
}

/// A floor, the reference ball resting at x = −20, and the test subject: a unit ball
/// resting at x = +20 (or whatever `subject` spawns). Returns (app, reference, subject).
fn scene(subject: impl FnOnce(&mut App) -> Entity) -> (App, Entity, Entity) {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let reference = ball(&mut app, 0.5, 1.0, Vec3::new(-20.0, 0.5, 0.0), Vec3::ZERO);
    step(&mut app, 20); // The reference settles onto the floor.
    let s = subject(&mut app);
    (app, reference, s)
}

/// Steps 30 times and checks the reference ball stayed put (< 1 mm) and finite.
fn assert_reference_unmoved(app: &mut App, reference: Entity, what: &str) {
    let before = pos(app, reference);
    step(app, 30);
    let moved = (pos(app, reference) - before).length();
    assert!(moved < 1e-3, "{what}: the reference ball moved {moved} m");
    assert!(
        rejected_field(app, reference).is_none(),
        "{what}: reference rejected"
    );
}

fn subject_ball(app: &mut App) -> Entity {
    ball(app, 0.5, 1.0, Vec3::new(20.0, 0.5, 0.0), Vec3::ZERO)
}

type BodyCase = (&'static str, fn(&mut EntityWorldMut, f32), fn(f32) -> bool);

fn finite(v: f32) -> bool {
    v.is_finite()
}
fn positive(max: f32) -> impl Fn(f32) -> bool {
    move |v| v.is_finite() && v > 0.0 && v <= max
}
fn within(lo: f32, hi: f32) -> impl Fn(f32) -> bool {
    move |v| v.is_finite() && (lo..=hi).contains(&v)
}

#[test]
fn every_body_field_refuses_bad_values_and_names_them() {
    let cases: [BodyCase; 15] = [
        (
            "Transform.translation",
            |e, v| e.get_mut::<Transform>().unwrap().translation.y = v,
            finite,
        ),
        (
            "Transform.rotation",
            |e, v| e.get_mut::<Transform>().unwrap().rotation = Quat::from_xyzw(v, 0.0, 0.0, 1.0),
            |v| (v * v).is_finite(),
        ), // Normalisable: its squared length must not overflow.
        (
            "Velocity.linear",
            |e, v| e.get_mut::<Velocity>().unwrap().linear.x = v,
            |v| v.is_finite() && v.abs() <= limits::MAX_SPEED,
        ),
        (
            "Velocity.angular",
            |e, v| e.get_mut::<Velocity>().unwrap().angular.z = v,
            |v| v.is_finite() && v.abs() <= limits::MAX_RATE,
        ),
        // A denormal mass has no finite inverse.
        (
            "Mass",
            |e, v| {
                e.insert(Mass(v));
            },
            |v| positive(limits::MAX_MASS)(v) && v > 1e-30,
        ),
        // A denormal size gives no usable inertia.
        (
            "Collider",
            |e, v| {
                e.insert(Collider::sphere(v));
            },
            |v| positive(limits::MAX_SIZE)(v) && v > 1e-30,
        ),
        // A box that thin, with its Mass, is a plate: its inertia stays usable.
        (
            "Collider",
            |e, v| {
                e.insert(Collider::cuboid(0.5, v, 0.5));
            },
            |v| positive(limits::MAX_SIZE)(v),
        ),
        (
            "Restitution",
            |e, v| {
                e.insert(Restitution(v));
            },
            |v| within(0.0, 1.0)(v),
        ),
        (
            "Friction",
            |e, v| {
                e.insert(Friction(v));
            },
            |v| within(0.0, limits::MAX_COEFFICIENT)(v),
        ),
        (
            "LinearDamping",
            |e, v| {
                e.insert(LinearDamping(v));
            },
            |v| within(0.0, limits::MAX_RATE)(v),
        ),
        (
            "AngularDamping",
            |e, v| {
                e.insert(AngularDamping(v));
            },
            |v| within(0.0, limits::MAX_RATE)(v),
        ),
        (
            "GravityScale",
            |e, v| {
                e.insert(GravityScale(v));
            },
            |v| within(-limits::MAX_COEFFICIENT, limits::MAX_COEFFICIENT)(v),
        ),
        (
            "ExternalForce",
            |e, v| {
                e.insert(ExternalForce {
                    force: Vec3::new(v, 0.0, 0.0),
                    torque: Vec3::ZERO,
                });
            },
            |v| within(-limits::MAX_FORCE, limits::MAX_FORCE)(v),
        ),
        (
            "ExternalForce",
            |e, v| {
                e.insert(ExternalForce {
                    force: Vec3::ZERO,
                    torque: Vec3::new(0.0, v, 0.0),
                });
            },
            |v| within(-limits::MAX_FORCE, limits::MAX_FORCE)(v),
        ),
        // The same fields on a static collider: a bounded plane's size and material.
        (
            "Collider",
            |e, v| {
                e.remove::<RigidBody>().insert(Collider::plane_rect(v, 1.0));
            },
            |v| positive(limits::MAX_SIZE)(v),
        ),
    ];
    for (field, set, valid) in cases {
        for v in VALUES {
            let what = format!("{field} = {}", name(v));
            let (mut app, reference, subject) = scene(subject_ball);
            set(&mut app.world_mut().entity_mut(subject), v);
            assert_reference_unmoved(&mut app, reference, &what);
            let got = rejected_field(&app, subject);
            if valid(v) {
                assert_eq!(got, None, "{what} is valid but was refused");
                assert!(pos(&app, subject).is_finite(), "{what}");
            } else {
                assert_eq!(got, Some(field), "{what} must be refused naming {field}");
            }
        }
    }
}

type ResourceCase = (
    &'static str,
    fn(&mut App, f32),
    fn(&App) -> bool,
    fn(f32) -> bool,
    bool,
);

#[test]
fn every_resource_field_keeps_its_last_good_value() {
    // (what, set the field, is the field back at its default, valid, moves everything)
    let cases: [ResourceCase; 14] = [
        (
            "Gravity",
            |a, v| a.world_mut().resource_mut::<Gravity>().0.y = v,
            |a| *a.world().resource::<Gravity>() == Gravity::default(),
            |v| within(-limits::MAX_ACCELERATION, limits::MAX_ACCELERATION)(v),
            false,
        ),
        (
            "GlobalForce",
            |a, v| a.world_mut().resource_mut::<GlobalForce>().0.x = v,
            |a| *a.world().resource::<GlobalForce>() == GlobalForce::default(),
            |v| within(-limits::MAX_FORCE, limits::MAX_FORCE)(v),
            true,
        ),
        (
            "Wind.velocity",
            |a, v| a.world_mut().resource_mut::<Wind>().velocity.x = v,
            |a| *a.world().resource::<Wind>() == Wind::default(),
            |v| within(-limits::MAX_SPEED, limits::MAX_SPEED)(v),
            true,
        ),
        (
            "Wind.drag",
            |a, v| a.world_mut().resource_mut::<Wind>().drag = v,
            |a| *a.world().resource::<Wind>() == Wind::default(),
            |v| within(0.0, limits::MAX_RATE)(v),
            true,
        ),
        (
            "Wind.gust",
            |a, v| a.world_mut().resource_mut::<Wind>().gust = v,
            |a| *a.world().resource::<Wind>() == Wind::default(),
            |v| within(0.0, 10.0)(v),
            true,
        ),
        (
            "SolverSettings.contact_hertz",
            |a, v| a.world_mut().resource_mut::<SolverSettings>().contact_hertz = v,
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| within(0.1, limits::MAX_RATE)(v),
            false,
        ),
        (
            "SolverSettings.contact_damping_ratio",
            |a, v| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .contact_damping_ratio = v
            },
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| within(0.0, limits::MAX_COEFFICIENT)(v),
            false,
        ),
        (
            "SolverSettings.max_push_out",
            |a, v| a.world_mut().resource_mut::<SolverSettings>().max_push_out = v,
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| positive(limits::MAX_SPEED)(v),
            false,
        ),
        (
            "SolverSettings.restitution_threshold",
            |a, v| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .restitution_threshold = v
            },
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| within(0.0, limits::MAX_SPEED)(v),
            false,
        ),
        (
            "SolverSettings.speculative_margin",
            |a, v| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .speculative_margin = v
            },
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| within(0.0, limits::MAX_SIZE)(v),
            false,
        ),
        (
            "SolverSettings.max_linear_speed",
            |a, v| {
                a.world_mut()
                    .resource_mut::<SolverSettings>()
                    .max_linear_speed = v
            },
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| within(1.0, limits::MAX_SPEED)(v),
            false,
        ),
        (
            "SolverSettings.max_sag",
            |a, v| a.world_mut().resource_mut::<SolverSettings>().max_sag = v,
            |a| *a.world().resource::<SolverSettings>() == SolverSettings::default(),
            |v| positive(1.0)(v),
            false,
        ),
        (
            "SleepSettings.linear_threshold",
            |a, v| {
                a.world_mut()
                    .resource_mut::<SleepSettings>()
                    .linear_threshold = v
            },
            |a| *a.world().resource::<SleepSettings>() == SleepSettings::default(),
            |v| within(0.0, limits::MAX_SPEED)(v),
            false,
        ),
        (
            "SleepSettings.time_to_sleep",
            |a, v| a.world_mut().resource_mut::<SleepSettings>().time_to_sleep = v,
            |a| *a.world().resource::<SleepSettings>() == SleepSettings::default(),
            |v| within(0.0, 1e9)(v),
            false,
        ),
    ];
    for (field, set, is_default, valid, moves_everything) in cases {
        for v in VALUES {
            let what = format!("{field} = {}", name(v));
            let (mut app, reference, subject) = scene(subject_ball);
            if field.starts_with("Wind") {
                app.insert_resource(Effects {
                    wind: true,
                    sleeping: false,
                    ..Effects::ALL
                });
            }
            set(&mut app, v);
            if valid(v) {
                step(&mut app, 30);
                for b in [reference, subject] {
                    assert!(
                        rejected_field(&app, b).is_none(),
                        "{what}: a body was rejected"
                    );
                    assert!(pos(&app, b).is_finite(), "{what}");
                }
                if !moves_everything {
                    let p = pos(&app, reference);
                    assert!((p.y - 0.5).abs() < 2e-3, "{what}: reference at {p}");
                }
            } else {
                if moves_everything {
                    // The last good value (the default wind, or the push) moves the
                    // reference too, so only the revert and the bodies' health count.
                    step(&mut app, 30);
                } else {
                    assert_reference_unmoved(&mut app, reference, &what);
                }
                assert!(
                    is_default(&app),
                    "{what}: the last good value is not in force"
                );
                for b in [reference, subject] {
                    assert!(
                        rejected_field(&app, b).is_none(),
                        "{what}: a body was rejected"
                    );
                }
            }
        }
    }
}

#[test]
fn solver_counts_and_the_fixed_rate_are_clamped() {
    for (substeps, iterations) in [(0, 0), (u32::MAX, u32::MAX), (65, 1)] {
        let (mut app, reference, _) = scene(subject_ball);
        let mut s = app.world_mut().resource_mut::<SolverSettings>();
        (s.substeps, s.iterations, s.max_substeps) = (substeps, iterations, substeps);
        assert_reference_unmoved(&mut app, reference, &format!("substeps {substeps}"));
        let s = *app.world().resource::<SolverSettings>();
        for n in [s.substeps, s.iterations, s.max_substeps] {
            assert!((1..=64).contains(&n), "{n} not clamped into 1..=64");
        }
    }
    // Bevy itself refuses a zero, negative or NaN timestep; tumble clamps what Bevy takes.
    for (seconds, hz) in [(1e-9, 10_000.0), (1e9, 1.0)] {
        let (mut app, reference, _) = scene(subject_ball);
        app.world_mut()
            .resource_mut::<Time<Fixed>>()
            .set_timestep_seconds(seconds);
        app.update();
        let got = 1.0
            / app
                .world()
                .resource::<Time<Fixed>>()
                .timestep()
                .as_secs_f64();
        assert!((got - hz).abs() < 1e-6 * hz, "{seconds} s step → {got} Hz");
        assert!(pos(&app, reference).is_finite());
    }
}

#[test]
fn every_scene_field_is_checked_on_load() {
    // (field text with {} for the value, the name the error must contain, valid)
    type SceneCase = (&'static str, &'static str, fn(f32) -> bool);
    let cases: [SceneCase; 12] = [
        ("settings: (hz: {})", "hz", |v| {
            (1.0..=10_000.0).contains(&v)
        }),
        ("settings: (gravity: (0.0, {}, 0.0))", "gravity", |v| {
            within(-limits::MAX_ACCELERATION, limits::MAX_ACCELERATION)(v)
        }),
        ("settings: (wind: (drag: {}))", "drag", |v| {
            within(0.0, limits::MAX_RATE)(v)
        }),
        ("planes: [(position: ({}, 0.0, 0.0))]", "position", |v| {
            within(-1e7, 1e7)(v)
        }),
        ("planes: [(normal: (0.0, {}, 0.0))]", "normal", |v| {
            v.abs() > 1e-6 && v.abs() < 1e6
        }),
        ("planes: [(friction: {})]", "friction", |v| {
            within(0.0, limits::MAX_COEFFICIENT)(v)
        }),
        ("bodies: [Single((shape: Sphere({})))]", "size", |v| {
            positive(limits::MAX_SIZE)(v)
        }),
        (
            "bodies: [Single((shape: Cuboid((0.5, {}, 0.5))))]",
            "half extents",
            |v| positive(limits::MAX_SIZE)(v),
        ),
        ("bodies: [Single((mass: Some({})))]", "mass", |v| {
            positive(limits::MAX_MASS)(v)
        }),
        (
            "bodies: [Single((restitution: Some({})))]",
            "restitution",
            |v| within(0.0, 1.0)(v),
        ),
        (
            "bodies: [Single((velocity: ({}, 0.0, 0.0)))]",
            "velocity",
            |v| within(-limits::MAX_SPEED, limits::MAX_SPEED)(v),
        ),
        (
            "bodies: [Row(body: (), count: 3, spacing: {}, direction: (1.0, 0.0, 0.0))]",
            "spacing",
            |v| within(-1e6, 1e6)(v),
        ),
    ];
    for (field, name_in_error, valid) in cases {
        for v in VALUES {
            let text = format!("(name: \"m\", {})", field.replace("{}", &name(v)));
            let result = SceneDesc::from_ron(&text, "m.scene.ron");
            match (valid(v), result) {
                (true, Ok(scene)) => {
                    // A valid scene spawns and steps.
                    let mut app = app();
                    scene.spawn_into(app.world_mut());
                    step(&mut app, 5);
                }
                (true, Err(e)) => panic!("{text}: valid but refused: {e}"),
                (false, Ok(_)) => panic!("{text}: accepted"),
                (false, Err(e)) => {
                    let e = e.to_string();
                    assert!(e.starts_with("m.scene.ron:1:"), "{text}: {e}");
                    assert!(e.contains(name_in_error), "{text}: {e}");
                }
            }
        }
    }
}
