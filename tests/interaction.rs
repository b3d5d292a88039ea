//! The demo's interaction logic, headless: switching scenes, adding and removing bodies,
//! the push force, and the drag spring pulling a body to the cursor. (The keys' six push
//! directions are a unit test of the demo, behind the `viz` feature.)

mod common;
use bevy::prelude::*;
use common::*;
use tumble::interaction::*;
use tumble::prelude::*;
use tumble::scene::{SceneDesc, SceneEntity};
use tumble::settings::GlobalForce;

fn scene_entities(app: &mut App) -> Vec<Entity> {
    app.world_mut()
        .query_filtered::<Entity, With<SceneEntity>>()
        .iter(app.world())
        .collect()
}

#[test]
fn switching_scenes_replaces_every_scene_entity() {
    let mut app = app();
    let tower = SceneDesc::load("assets/scenes/2_box_tower.scene.ron").unwrap();
    let cradle = SceneDesc::load("assets/scenes/6_newtons_cradle.scene.ron").unwrap();
    let first = tower.spawn_into(app.world_mut());
    step(&mut app, 5);
    let old = scene_entities(&mut app);
    assert_eq!(old.len(), 10 + 1, "ten boxes and the ground");
    let mut commands = app.world_mut().commands();
    let new = switch_scene(&mut commands, &cradle, old.clone());
    app.world_mut().flush();
    step(&mut app, 5);
    assert_eq!(new.len(), 5);
    assert!(
        first.iter().all(|&e| app.world().get_entity(e).is_err()),
        "old bodies despawned"
    );
    assert_eq!(
        scene_entities(&mut app).len(),
        5 + 1 + 10,
        "five balls, the ground, ten strings"
    );
    assert_eq!(
        app.world().resource::<PhysicsWorld>().awake_bodies(),
        5,
        "the solver sees only the new scene"
    );
}

#[test]
fn added_body_falls_and_removed_body_leaves_the_simulation() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let e = app
        .world_mut()
        .spawn(added_body(Collider::cuboid(0.4, 0.4, 0.4), Vec3::Y * 3.0))
        .id();
    step(&mut app, 60);
    assert!(
        (pos(&app, e).y - 0.4).abs() < 0.01,
        "landed: {}",
        pos(&app, e)
    );
    app.world_mut().despawn(e);
    step(&mut app, 1);
    assert!(app.world().resource::<PhysicsWorld>().awake_bodies() == 0);
}

#[test]
fn the_push_pushes_by_its_force() {
    // A 2 kg ball pushed with 15 N along +x in zero gravity: a = 7.5 m/s².
    let mut app = app_without_gravity();
    let b = ball(&mut app, 0.5, 2.0, Vec3::ZERO, Vec3::ZERO);
    app.insert_resource(GlobalForce(Vec3::X * PUSH_FORCE));
    step(&mut app, 60);
    assert!(
        (vel(&app, b).linear.x - 7.5).abs() < 1e-3,
        "{}",
        vel(&app, b).linear
    );
}

#[test]
fn drag_spring_pulls_a_body_to_the_cursor_and_holds_it() {
    let mut app = app();
    app.add_plugins(DragPullPlugin);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.5), 3.0, Vec3::Y * 0.5);
    let target = Vec3::new(2.0, 2.5, 0.0);
    // Grabbed at the centre of its top face.
    app.world_mut().entity_mut(b).insert(Dragged {
        local_anchor: Vec3::Y * 0.5,
        target,
        plane_normal: Vec3::Z,
    });
    step(&mut app, 240);
    let anchor = app
        .world()
        .get::<Transform>(b)
        .unwrap()
        .transform_point(Vec3::Y * 0.5);
    // A 3 Hz spring holds the weight with a sag of g/ω² ≈ 2.8 cm.
    let sag = 9.81 / (std::f32::consts::TAU * PULL_HERTZ).powi(2);
    assert!(
        (anchor - target).length() < sag + 0.02,
        "anchor at {anchor}, target {target}"
    );
    assert!(
        vel(&app, b).linear.length() < 0.05,
        "settled: {:?}",
        vel(&app, b)
    );
}
