//! The scene in avian3d 0.7: the same bodies, masses, materials and combine rules
//! (friction: geometric mean, restitution: max), sleeping disabled on every body.

use avian3d::prelude::*;
use bevy::prelude::*;
use tumble::scene::{SceneDesc, ShapeDesc};

/// Thickness of a bounded plane, which both peers model as a thin box.
pub const WALL: f32 = 0.01;

pub fn app(scene: &SceneDesc) -> (App, Vec<Entity>) {
    let mut app = crate::headless_app();
    app.add_plugins(PhysicsPlugins::default())
        .insert_resource(Gravity(scene.settings.gravity));
    crate::start(&mut app);
    let world = app.world_mut();
    for p in &scene.planes {
        let collider = match p.half_extents {
            Some(h) => Collider::cuboid(2.0 * h.x, WALL, 2.0 * h.y),
            None => Collider::half_space(Vec3::Y),
        };
        world.spawn((
            RigidBody::Static,
            collider,
            Transform::from_translation(p.position).with_rotation(p.rotation()),
            friction(p.friction),
            restitution(p.restitution),
        ));
    }
    let bodies = scene
        .expanded_bodies()
        .iter()
        .map(|b| {
            let collider = match b.shape {
                ShapeDesc::Sphere(r) => Collider::sphere(r),
                ShapeDesc::Cuboid(h) => Collider::cuboid(2.0 * h.x, 2.0 * h.y, 2.0 * h.z),
                // avian takes whole lengths where tumble takes halves.
                ShapeDesc::Capsule(r, h) => Collider::capsule(r, 2.0 * h),
                ShapeDesc::Cylinder(r, h) => Collider::cylinder(r, 2.0 * h),
                ShapeDesc::Cone(r, h) => Collider::cone(r, 2.0 * h),
                ShapeDesc::Rock(r, seed) => {
                    let points = tumble::scene::rock_points(r, seed);
                    Collider::convex_hull(points).expect("a rock spans a volume")
                }
            };
            world
                .spawn((
                    RigidBody::Dynamic,
                    collider,
                    Mass(b.mass()),
                    Transform::from_translation(b.position).with_rotation(b.rotation()),
                    LinearVelocity(b.velocity),
                    AngularVelocity(b.angular_velocity),
                    friction(b.friction.unwrap_or(tumble::body::DEFAULT_FRICTION)),
                    restitution(b.restitution.unwrap_or(0.0)),
                    SleepingDisabled,
                ))
                .id()
        })
        .collect();
    (app, bodies)
}

fn friction(mu: f32) -> Friction {
    Friction::new(mu).with_combine_rule(CoefficientCombine::GeometricMean)
}

fn restitution(e: f32) -> Restitution {
    Restitution::new(e).with_combine_rule(CoefficientCombine::Max)
}
