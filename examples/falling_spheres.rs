//! A few spheres fall onto a ground plane and bounce: the smallest tumble scene with a
//! window. Orbit with the left mouse button, pan with the right, zoom with the wheel.
//!
//! `cargo run --release --features viz --example falling_spheres`

use bevy::prelude::*;
use bevy_panorbit_camera::{PanOrbitCamera, PanOrbitCameraPlugin};
use tumble::prelude::*;

fn main() {
    App::new()
        .add_plugins((
            DefaultPlugins,
            PanOrbitCameraPlugin,
            TumblePlugin::default(),
        ))
        .add_systems(Startup, setup)
        .run();
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.spawn((
        PanOrbitCamera::default(),
        Transform::from_xyz(0.0, 6.0, 14.0).looking_at(Vec3::new(0.0, 2.0, 0.0), Vec3::Y),
    ));
    commands.spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            illuminance: 8000.0,
            ..default()
        },
        Transform::from_xyz(4.0, 10.0, 6.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Collider::plane(),
        Mesh3d(meshes.add(Plane3d::default().mesh().size(20.0, 20.0))),
        MeshMaterial3d(materials.add(Color::srgb(0.35, 0.38, 0.35))),
        Transform::default(),
    ));
    let ball = meshes.add(Sphere::new(0.5).mesh().uv(32, 16));
    for i in 0..12 {
        let (x, z) = ((i % 4) as f32 - 1.5, (i / 4) as f32 - 1.0);
        let e = 0.3 + 0.05 * i as f32;
        commands.spawn((
            RigidBody::Dynamic,
            Collider::sphere(0.5),
            Restitution(e),
            Mesh3d(ball.clone()),
            MeshMaterial3d(materials.add(Color::srgb(0.2 + e * 0.6, 0.4, 1.0 - e * 0.6))),
            Transform::from_xyz(x * 1.3, 2.0 + i as f32 * 0.6, z * 1.3),
        ));
    }
}
