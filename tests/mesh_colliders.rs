//! Colliders from Bevy meshes (feature `mesh`): a plane mesh's triangles hold a ball at
//! its radius; a cuboid mesh's hull weighs its volume and rests like the box; a scene
//! root with `ColliderConstructorHierarchy` gets colliders on the meshes below it once
//! they spawn and load, and a ball lands on them.

mod common;
use bevy::asset::AssetPlugin;
use bevy::mesh::{Mesh, Mesh3d};
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

fn with_assets(pacing: Pacing) -> App {
    paced_app_with(pacing, false, |app| {
        app.add_plugins(AssetPlugin::default()).init_asset::<Mesh>();
    })
}

fn add_mesh(app: &mut App, mesh: Mesh) -> Handle<Mesh> {
    app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh)
}

#[test]
fn meshes_make_trimeshes_and_hulls() {
    let mut app = with_assets(Pacing::OneStep);
    let floor = Mesh::from(Plane3d::new(Vec3::Y, Vec2::splat(5.0)));
    let floor = Collider::trimesh_from_mesh(&floor).unwrap();
    app.world_mut().spawn((floor, Transform::default()));
    let h = Vec3::new(0.4, 0.25, 0.3);
    let cuboid = Mesh::from(Cuboid::new(2.0 * h.x, 2.0 * h.y, 2.0 * h.z));
    let hull = Collider::convex_hull_from_mesh(&cuboid).unwrap();
    assert_near(
        hull.shape.volume(),
        8.0 * h.x * h.y * h.z,
        1e-5,
        "the hull's volume",
    );
    let b = ball(&mut app, 0.3, 1.0, Vec3::new(-2.0, 1.0, 0.0), Vec3::ZERO);
    let c = app
        .world_mut()
        .spawn((RigidBody::Dynamic, hull, Transform::from_xyz(2.0, 1.0, 0.0)))
        .id();
    step(&mut app, 120);
    let sag = |size: f32| SolverSettings::default().max_sag * size;
    assert_near(pos(&app, b).y, 0.3, sag(0.6), "ball on the plane mesh");
    assert_near(
        pos(&app, c).y,
        h.y,
        sag(2.0 * h.y),
        "hull of the cuboid mesh",
    );
    // A line strip has no triangles to make a mesh of.
    let strip = Mesh::new(bevy::mesh::PrimitiveTopology::LineStrip, default())
        .with_inserted_attribute(
            Mesh::ATTRIBUTE_POSITION,
            vec![[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0]],
        );
    assert!(Collider::trimesh_from_mesh(&strip).is_err());
}

/// The scene's meshes appear some frames after its root (as a glTF scene spawns), and
/// one mesh loads later still: the colliders follow, under every pacing.
#[test]
fn a_scene_root_gets_colliders_on_its_meshes() {
    for pacing in Pacing::GAME {
        let mut app = with_assets(pacing);
        let root = app
            .world_mut()
            .spawn((
                Transform::from_xyz(0.0, -1.0, 0.0),
                ColliderConstructorHierarchy::default(),
            ))
            .id();
        frames(&mut app, 3);
        let floor = add_mesh(
            &mut app,
            Mesh::from(Plane3d::new(Vec3::Y, Vec2::splat(5.0))),
        );
        // A ramp whose mesh is still loading.
        let ramp = app.world_mut().resource::<Assets<Mesh>>().reserve_handle();
        let floor_e = app
            .world_mut()
            .spawn((Mesh3d(floor), Transform::default(), ChildOf(root)))
            .id();
        let ramp_e = app
            .world_mut()
            .spawn((
                Mesh3d(ramp.clone()),
                Transform::from_xyz(3.0, 0.5, 0.0),
                ChildOf(root),
            ))
            .id();
        frames(&mut app, 2);
        let what = format!("{pacing:?}");
        assert!(
            app.world().get::<Collider>(floor_e).is_some(),
            "{what}: floor collider"
        );
        assert!(
            app.world().get::<Collider>(ramp_e).is_none(),
            "{what}: the ramp is not loaded"
        );
        assert!(
            app.world()
                .get::<ColliderConstructorHierarchy>(root)
                .is_some(),
            "{what}: still waiting"
        );
        let cube = Mesh::from(Cuboid::new(1.0, 1.0, 1.0));
        app.world_mut()
            .resource_mut::<Assets<Mesh>>()
            .insert(ramp.id(), cube)
            .unwrap();
        frames(&mut app, 2);
        assert!(
            app.world().get::<Collider>(ramp_e).is_some(),
            "{what}: ramp collider"
        );
        assert!(
            app.world()
                .get::<ColliderConstructorHierarchy>(root)
                .is_none(),
            "{what}: done"
        );
        // A ball dropped on the floor mesh lands at the root's height.
        let b = ball(&mut app, 0.25, 1.0, Vec3::new(-2.0, 1.0, 0.0), Vec3::ZERO);
        step(&mut app, 120);
        assert_near(
            pos(&app, b).y,
            -1.0 + 0.25,
            2e-3,
            &format!("{what}: landed on the mesh"),
        );
    }
}
