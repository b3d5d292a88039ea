//! Shared helpers for the headless integration tests: one app builder with a frame-pacing
//! parameter, `step` that counts physics steps (not frames), `assert_near`, one `G`,
//! one seeded RNG, and body spawners.
#![allow(dead_code)]

use std::time::Duration;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::prelude::*;

/// The fixed step, s (the plugin's default 60 Hz).
pub const H: f32 = 1.0 / 60.0;
/// Standard gravity, m/s² (the default `Gravity`).
pub const G: f32 = 9.81;

/// How frames relate to physics steps, as in a real game loop (physics at 60 Hz).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pacing {
    /// Exactly one fixed step per `update()` (`FixedTimesteps(1)`).
    OneStep,
    /// Rendering at this many frames per second: most frames run no fixed step (above
    /// 60 Hz) or several (below). Uses `ManualDuration(1/hz)`.
    Render(f64),
}

impl Pacing {
    /// The three pacings lifecycle tests run under: one step per update, a 240 Hz
    /// render (three frames in four run no step) and a 30 Hz render (two steps a frame).
    pub const GAME: [Pacing; 3] = [Pacing::OneStep, Pacing::Render(240.0), Pacing::Render(30.0)];
}

/// MinimalPlugins + TransformPlugin + TumblePlugin with its defaults (sleeping on, as
/// games run it), one fixed step per update.
pub fn app() -> App {
    paced_app(Pacing::OneStep, true)
}

/// The same; kept as a name for tests that are about sleeping.
pub fn app_with_sleeping() -> App {
    app()
}

/// The defaults but sleeping off: only for a test that measures a body over a long
/// still stretch that sleeping would freeze (a creep, a drift, a slow settling) and says
/// so where it calls this.
pub fn app_without_sleeping() -> App {
    paced_app(Pacing::OneStep, false)
}

pub fn app_without_gravity() -> App {
    let mut app = app();
    app.insert_resource(Gravity(Vec3::ZERO));
    app
}

/// The one app builder: physics at 60 Hz under `pacing`, sleeping on or off. More
/// plugins may still be added to it (their `finish` never runs: see [`paced_app_with`]).
pub fn paced_app(pacing: Pacing, sleeping: bool) -> App {
    build(pacing, sleeping, |_| {}, false)
}

/// The same, with plugins added by `setup` and then finished, as `App::run` does before
/// the first frame (bevy_transform_interpolation adds its easing systems in `finish`).
/// No plugin can be added after.
pub fn paced_app_with(pacing: Pacing, sleeping: bool, setup: impl FnOnce(&mut App)) -> App {
    build(pacing, sleeping, setup, true)
}

fn build(pacing: Pacing, sleeping: bool, setup: impl FnOnce(&mut App), finish: bool) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
        .insert_resource(strategy(pacing));
    setup(&mut app);
    if finish {
        app.finish();
        app.cleanup();
    }
    app.world_mut().resource_mut::<Effects>().sleeping = sleeping;
    app.insert_resource(PacingOf(pacing));
    app.update(); // The first update only starts the clock: 0 steps.
    app
}

#[derive(Resource, Clone, Copy)]
struct PacingOf(Pacing);

fn strategy(pacing: Pacing) -> TimeUpdateStrategy {
    match pacing {
        Pacing::OneStep => TimeUpdateStrategy::FixedTimesteps(1),
        Pacing::Render(hz) => TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / hz)),
    }
}

/// Physics steps taken so far.
pub fn steps_taken(app: &App) -> u64 {
    app.world().resource::<PhysicsWorld>().step_count()
}

/// Runs frames until exactly `n` more physics steps have run, whatever the pacing. Under
/// a slow render that would overshoot (two steps a frame, one left), the last frame is
/// shortened to one step, as a variable frame time would.
pub fn step(app: &mut App, n: usize) {
    let target = steps_taken(app) + n as u64;
    let pacing = app.world().resource::<PacingOf>().0;
    let mut frames = 0;
    while steps_taken(app) < target {
        let left = target - steps_taken(app);
        if let Pacing::Render(hz) = pacing {
            let per_frame = (60.0 / hz).floor() as u64;
            if per_frame > left {
                app.insert_resource(TimeUpdateStrategy::FixedTimesteps(left as u32));
                app.update();
                app.insert_resource(strategy(pacing));
                continue;
            }
        }
        app.update();
        frames += 1;
        assert!(frames < 100 * n + 100, "physics stopped stepping");
    }
    assert_eq!(steps_taken(app), target, "overshot the step count");
}

/// Runs `case` under each pacing for each sleeping setting, and checks the final poses
/// and velocities are bit-identical across pacings (sleeping on and off are not compared
/// with each other: a sleeper is frozen).
pub fn under_every_pacing(
    pacings: &[Pacing],
    sleeping: &[bool],
    case: impl Fn(&mut App, bool, Pacing),
) {
    for &sleeping in sleeping {
        let mut reference = None;
        for &pacing in pacings {
            let mut app = paced_app(pacing, sleeping);
            case(&mut app, sleeping, pacing);
            let snap: Vec<_> = snapshot(&mut app).into_iter().map(|(_, s)| s).collect();
            match &reference {
                None => reference = Some(snap),
                Some(r) => assert!(
                    *r == snap,
                    "{pacing:?} (sleeping {sleeping}) differs from one step per update"
                ),
            }
        }
    }
}

/// The drop from rest in `t` s of free fall, within the semi-implicit substep error
/// (½·g·hs·t with hs = h/4, doubled) plus 1 mm for the start of the fall inside a step.
#[track_caller]
pub fn assert_free_fall(drop: f32, t: f32, what: &str) {
    assert_near(drop, 0.5 * G * t * t, G * (H / 4.0) * t + 1e-3, what);
}

/// Runs `frames` frames (any number of physics steps, including none).
pub fn frames(app: &mut App, frames: usize) {
    for _ in 0..frames {
        app.update();
    }
}

/// |actual − expected| ≤ tol, with both values and what they are in the message.
#[track_caller]
pub fn assert_near(actual: f32, expected: f32, tol: f32, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: {actual} but expected {expected} ± {tol} (off by {})",
        (actual - expected).abs()
    );
}

/// |actual − expected| ≤ tol for each component.
#[track_caller]
pub fn assert_near_vec(actual: Vec3, expected: Vec3, tol: f32, what: &str) {
    assert!(
        (actual - expected).abs().max_element() <= tol,
        "{what}: {actual} but expected {expected} ± {tol}"
    );
}

/// The tests' one seeded random source (SplitMix64): the same seed, the same numbers.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
    /// Log-uniform in [lo, hi): as likely 1–10 as 10–100.
    pub fn log_range(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    pub fn vec3(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }
}

pub fn pos(app: &App, e: Entity) -> Vec3 {
    app.world().get::<Transform>(e).unwrap().translation
}

pub fn rot(app: &App, e: Entity) -> Quat {
    app.world().get::<Transform>(e).unwrap().rotation
}

pub fn vel(app: &App, e: Entity) -> Velocity {
    *app.world().get::<Velocity>(e).unwrap()
}

pub fn asleep(app: &App, e: Entity) -> bool {
    app.world().get::<Sleeping>(e).is_some()
}

pub fn rejected_field(app: &App, e: Entity) -> Option<&'static str> {
    app.world().get::<PhysicsRejected>(e).map(|r| r.field)
}

/// A dynamic ball of radius `r` and mass `m` at `p` moving at `v`.
pub fn ball(app: &mut App, r: f32, m: f32, p: Vec3, v: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::sphere(r),
            Mass(m),
            Transform::from_translation(p),
            Velocity::linear(v),
        ))
        .id()
}

/// A static infinite plane through `p` whose normal is `rot`·Y.
pub fn ground(app: &mut App, p: Vec3, rot: Quat) -> Entity {
    app.world_mut()
        .spawn((
            Collider::plane(),
            Transform::from_translation(p).with_rotation(rot),
        ))
        .id()
}

/// A dynamic box with half extents `h`, mass `m` at `p`.
pub fn cuboid(app: &mut App, h: Vec3, m: f32, p: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(h.x, h.y, h.z),
            Mass(m),
            Transform::from_translation(p),
        ))
        .id()
}

/// Six inward-facing infinite planes: a closed room of half size `half` centred on 0.
pub fn closed_room(app: &mut App, half: f32) {
    for n in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        let rot = Quat::from_rotation_arc(Vec3::Y, n);
        let at = Transform::from_translation(-n * half).with_rotation(rot);
        app.world_mut().spawn((Collider::plane(), at));
    }
}

/// Tilt of a body's local +Y away from world +Y, radians.
pub fn tilt(app: &App, e: Entity) -> f32 {
    (rot(app, e) * Vec3::Y).angle_between(Vec3::Y)
}

/// Every dynamic body's pose and velocity as raw bits, in entity order.
pub fn snapshot(app: &mut App) -> Vec<(Entity, [u32; 13])> {
    let mut q = app
        .world_mut()
        .query_filtered::<(Entity, &Transform, &Velocity), With<RigidBody>>();
    let mut out: Vec<_> = q
        .iter(app.world())
        .map(|(e, t, v)| (e, tumble::state_hash::body_bits(t, v)))
        .collect();
    out.sort_by_key(|(e, _)| *e);
    out
}

/// Runs `f` with a [`SpatialQuery`] over the app's last step, as a system would.
pub fn query<R>(app: &mut App, f: impl FnOnce(&SpatialQuery) -> R) -> R {
    let mut state = bevy::ecs::system::SystemState::<SpatialQuery>::new(app.world_mut());
    let q = state.get(app.world()).unwrap();
    f(&q)
}
