//! The scene in bevy_rapier3d 0.36, stepped in `FixedUpdate` with a fixed 1/60 s step:
//! the same bodies, masses and materials (restitution combined by max; rapier has no
//! geometric mean, so friction is the average), sleeping disabled on every body.

use bevy::prelude::*;
use bevy_rapier3d::prelude::*;
use tumble::scene::{SceneDesc, ShapeDesc};

use crate::avian::WALL;

pub fn app(scene: &SceneDesc) -> (App, Vec<Entity>) {
    let mut app = crate::headless_app();
    app.add_plugins(RapierPhysicsPlugin::<NoUserData>::default().in_fixed_schedule())
        .insert_resource(TimestepMode::Fixed {
            dt: 1.0 / 60.0,
            substeps: 1,
        });
    crate::start(&mut app);
    let gravity = scene.settings.gravity;
    let world = app.world_mut();
    let mut configs = world.query::<&mut RapierConfiguration>();
    for mut config in configs.iter_mut(world) {
        config.gravity = gravity;
    }
    for p in &scene.planes {
        let collider = match p.half_extents {
            Some(h) => Collider::cuboid(h.x, 0.5 * WALL, h.y),
            None => Collider::halfspace(Vec3::Y).expect("unit normal"),
        };
        world.spawn((
            RigidBody::Fixed,
            collider,
            Transform::from_translation(p.position).with_rotation(p.rotation()),
            Friction::coefficient(p.friction),
            restitution(p.restitution),
        ));
    }
    let bodies = scene
        .expanded_bodies()
        .iter()
        .map(|b| {
            let collider = match b.shape {
                ShapeDesc::Sphere(r) => Collider::ball(r),
                ShapeDesc::Cuboid(h) => Collider::cuboid(h.x, h.y, h.z),
                ShapeDesc::Capsule(r, h) => Collider::capsule_y(h, r),
                ShapeDesc::Cylinder(r, h) => Collider::cylinder(h, r),
                ShapeDesc::Cone(r, h) => Collider::cone(h, r),
                ShapeDesc::Rock(r, seed) => {
                    let points = tumble::scene::rock_points(r, seed);
                    Collider::convex_hull(&points).expect("a rock spans a volume")
                }
            };
            world
                .spawn((
                    RigidBody::Dynamic,
                    collider,
                    ColliderMassProperties::Mass(b.mass()),
                    Transform::from_translation(b.position).with_rotation(b.rotation()),
                    Velocity {
                        linear: b.velocity,
                        angular: b.angular_velocity,
                    },
                    Friction::coefficient(b.friction.unwrap_or(tumble::body::DEFAULT_FRICTION)),
                    restitution(b.restitution.unwrap_or(0.0)),
                    Sleeping::disabled(),
                ))
                .id()
        })
        .collect();
    (app, bodies)
}

fn restitution(e: f32) -> Restitution {
    Restitution {
        coefficient: e,
        combine_rule: CoefficientCombineRule::Max,
    }
}
