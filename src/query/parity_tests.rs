//! The indexed queries answer exactly what checking every collider answers, on random
//! scenes run through the real plugin: awake bodies of every shape, static colliders
//! (boxes, bounded and infinite planes), sleepers, sensors and layers; random rays (some
//! unbounded), shape casts, points, boxes and projections, each with random filters.

use bevy::ecs::system::SystemState;
use bevy::prelude::*;
use std::sync::atomic::Ordering;

use super::{SpatialQuery, SpatialQueryCache, SpatialQueryFilter};
use crate::TumblePlugin;
use crate::body::RigidBody;
use crate::collider::Collider;
use crate::effects::Effects;
use crate::layers::{CollisionLayers, LayerMask, Sensor};
use crate::rng::Rnd;

/// Random colliders of the convex kinds.
trait RandomCollider {
    fn collider(&mut self) -> Collider;
    fn rot_xyz(&mut self) -> Quat;
}

impl RandomCollider for Rnd {
    fn rot_xyz(&mut self) -> Quat {
        Quat::from_euler(
            EulerRot::XYZ,
            self.range(0.0, 6.3),
            self.range(0.0, 6.3),
            self.range(0.0, 6.3),
        )
    }
    fn collider(&mut self) -> Collider {
        let (a, b) = (self.range(0.1, 0.8), self.range(0.1, 0.8));
        match (self.unit() * 5.0) as u32 {
            0 => Collider::sphere(a),
            1 => Collider::cuboid(a, b, self.range(0.1, 0.8)),
            2 => Collider::capsule(a, b),
            3 => Collider::cylinder(a, b),
            _ => Collider::cone(a, b),
        }
    }
}

fn scene(seed: u64) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, TumblePlugin::default()));
    app.insert_resource(bevy::time::TimeUpdateStrategy::FixedTimesteps(1));
    app.world_mut().resource_mut::<Effects>().sleeping = true;
    let mut rnd = Rnd(seed | 1);
    let world = app.world_mut();
    world.spawn((Collider::plane(), Transform::default()));
    for i in 0..120 {
        let pos = rnd.vec(-15.0, 15.0).with_y(rnd.range(0.5, 12.0));
        let tf = Transform::from_translation(pos).with_rotation(rnd.rot_xyz());
        let layers = CollisionLayers::from_bits(1 << (i % 3), u32::MAX);
        let mut e = if rnd.unit() < 0.3 {
            let fixed = if rnd.unit() < 0.3 {
                Collider::plane_rect(rnd.range(0.5, 3.0), rnd.range(0.5, 3.0))
            } else {
                Collider::cuboid(
                    rnd.range(0.2, 4.0),
                    rnd.range(0.1, 1.0),
                    rnd.range(0.2, 4.0),
                )
            };
            world.spawn((fixed, tf, layers))
        } else {
            let c = rnd.collider();
            world.spawn((RigidBody::Dynamic, c, tf, layers))
        };
        if rnd.unit() < 0.1 {
            e.insert(Sensor);
        }
    }
    // Long enough that some fall asleep and enter the fixed set, and one step more so
    // the fixed set changed after the broad phase's last rebuild in some scenes.
    let steps = 30 + (seed % 200) as usize;
    for _ in 0..steps {
        app.update();
    }
    app
}

fn filter(rnd: &mut Rnd) -> SpatialQueryFilter {
    let mut f = SpatialQueryFilter::default();
    if rnd.unit() < 0.3 {
        f = f.with_mask(LayerMask((rnd.unit() * 7.0) as u32 + 1));
    }
    if rnd.unit() < 0.3 {
        f = f.without_sensors();
    }
    f
}

#[test]
fn indexed_queries_answer_what_brute_force_answers() {
    let mut compared = [0usize; 6];
    for seed in 1..=8u64 {
        let mut app = scene(seed * 7919);
        let world = app.world_mut();
        let mut state = SystemState::<SpatialQuery>::new(world);
        let mut rnd = Rnd(seed * 31 + 5);
        for _ in 0..150 {
            let origin = rnd.vec(-20.0, 20.0).with_y(rnd.range(-1.0, 14.0));
            let dir = Dir3::new(rnd.vec(-1.0, 1.0)).unwrap_or(Dir3::NEG_Y);
            let max = if rnd.unit() < 0.3 {
                f32::MAX
            } else {
                rnd.range(1.0, 40.0)
            };
            let solid = rnd.unit() < 0.5;
            let f = filter(&mut rnd);
            let shape = rnd.collider();
            let rot = rnd.rot_xyz();
            let lo = rnd.vec(-15.0, 15.0);
            let hi = lo + rnd.vec(0.0, 6.0);
            let mut ask = |world: &mut World, brute: bool| {
                let cache = world.resource::<SpatialQueryCache>();
                cache.brute_force.store(brute, Ordering::Relaxed);
                let q = state.get(world).unwrap();
                (
                    q.cast_ray(origin, dir, max, solid, &f),
                    q.ray_hits(origin, dir, max, usize::MAX, solid, &f),
                    q.cast_shape(&shape, origin, rot, dir, max.min(60.0), &f),
                    q.point_intersections(lo, &f),
                    (
                        q.aabb_intersections(lo, hi, &f),
                        q.shape_intersections(&shape, lo, rot, &f),
                    ),
                    q.project_point(origin, solid, &f),
                )
            };
            let indexed = ask(world, false);
            let reference = ask(world, true);
            assert_eq!(indexed.0, reference.0, "cast_ray seed {seed}");
            assert_eq!(indexed.1, reference.1, "ray_hits seed {seed}");
            assert_eq!(indexed.2, reference.2, "cast_shape seed {seed}");
            assert_eq!(indexed.3, reference.3, "point_intersections seed {seed}");
            assert_eq!(
                indexed.4, reference.4,
                "aabb / shape intersections seed {seed}"
            );
            assert_eq!(indexed.5, reference.5, "project_point seed {seed}");
            compared[0] += indexed.0.is_some() as usize;
            compared[1] += indexed.1.len();
            compared[2] += indexed.2.is_some() as usize;
            compared[3] += indexed.3.len();
            compared[4] += indexed.4.0.len() + indexed.4.1.len();
            compared[5] += indexed.5.is_some() as usize;
        }
    }
    // The comparisons were not all of empty answers.
    assert!(
        compared.iter().all(|&n| n > 20),
        "too few hits to compare: {compared:?}"
    );
}
