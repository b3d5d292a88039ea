//! Spatial queries answer from the last step's index. Under a 240 Hz render three frames
//! in four run no physics step, and in those frames every query kind still returned a
//! wall and a crate despawned since, until the next step; a game that called
//! `commands.entity(hit.entity)` on the answer panicked. A query now never returns a
//! collider that is gone, or that lost its `Collider`, whatever the pacing.

mod common;

use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// Every query kind, aimed at the spot where the wall (x = 2) and the crate (x = 0) are.
fn everything_found(app: &mut App) -> Vec<Entity> {
    query(app, |q| {
        let f = SpatialQueryFilter::default();
        let mut found = Vec::new();
        let from = Vec3::new(-3.0, 0.5, 0.0);
        found.extend(q.cast_ray(from, Dir3::X, 10.0, true, &f).map(|h| h.entity));
        found.extend(
            q.ray_hits(from, Dir3::X, 10.0, 8, true, &f)
                .iter()
                .map(|h| h.entity),
        );
        let ball = Collider::sphere(0.1);
        found.extend(
            q.cast_shape(&ball, from, Quat::IDENTITY, Dir3::X, 10.0, &f)
                .map(|h| h.entity),
        );
        for at in [Vec3::new(0.0, 0.5, 0.0), Vec3::new(2.0, 0.5, 0.0)] {
            found.extend(q.point_intersections(at, &f));
            found.extend(q.shape_intersections(&ball, at, Quat::IDENTITY, &f));
            found.extend(q.project_point(at, true, &f).map(|p| p.entity));
        }
        let (lo, hi) = (Vec3::new(-1.0, 0.2, -1.0), Vec3::new(3.0, 0.8, 1.0));
        found.extend(q.aabb_intersections(lo, hi, &f));
        found
    })
}

#[test]
fn no_query_returns_a_despawned_collider() {
    for crate_asleep in [false, true] {
        let mut app = paced_app(Pacing::Render(240.0), true);
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let wall = app
            .world_mut()
            .spawn((
                Collider::cuboid(0.1, 1.0, 1.0),
                Transform::from_xyz(2.0, 1.0, 0.0),
            ))
            .id();
        let crate_ = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.5, 0.0));
        step(&mut app, if crate_asleep { 60 } else { 5 });
        assert_eq!(asleep(&app, crate_), crate_asleep);
        let before = everything_found(&mut app);
        assert!(
            before.contains(&wall) && before.contains(&crate_),
            "both found at first"
        );
        // Despawned just after a step: the next frames run no step.
        app.world_mut().despawn(wall);
        app.world_mut().despawn(crate_);
        for frame in 0..4 {
            let found = everything_found(&mut app);
            assert!(
                !found.contains(&wall) && !found.contains(&crate_),
                "crate asleep {crate_asleep}, frame {frame}: a query returned a despawned \
                 entity: {found:?}"
            );
            frames(&mut app, 1);
        }
    }
}

#[test]
fn no_query_returns_a_collider_that_was_removed() {
    let mut app = paced_app(Pacing::Render(240.0), true);
    let wall = app
        .world_mut()
        .spawn((
            Collider::cuboid(0.1, 1.0, 1.0),
            Transform::from_xyz(2.0, 1.0, 0.0),
        ))
        .id();
    step(&mut app, 2);
    assert!(everything_found(&mut app).contains(&wall));
    app.world_mut().entity_mut(wall).remove::<Collider>();
    let found = everything_found(&mut app);
    assert!(
        !found.contains(&wall),
        "removed collider still found: {found:?}"
    );
}
