//! Shared helpers for the headless integration tests: an app that runs exactly one
//! 60 Hz physics step per `update()`.
#![allow(dead_code)]

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use tumble::prelude::*;

pub const H: f32 = 1.0 / 60.0;

/// MinimalPlugins + TransformPlugin + TumblePlugin, one fixed step per update, with
/// sleeping off so that it hides nothing.
pub fn app() -> App {
    let mut app = app_with_sleeping();
    app.world_mut().resource_mut::<Effects>().sleeping = false;
    app
}

/// The same with the default settings, sleeping on.
pub fn app_with_sleeping() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()))
        .insert_resource(TimeUpdateStrategy::FixedTimesteps(1));
    app.update(); // The first update only starts the clock: 0 steps.
    app
}

pub fn app_without_gravity() -> App {
    let mut app = app();
    app.insert_resource(Gravity(Vec3::ZERO));
    app
}

/// Runs `n` physics steps.
pub fn step(app: &mut App, n: usize) {
    for _ in 0..n {
        app.update();
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

/// Tilt of a body's local +Y away from world +Y, radians.
pub fn tilt(app: &App, e: Entity) -> f32 {
    (rot(app, e) * Vec3::Y).angle_between(Vec3::Y)
}
