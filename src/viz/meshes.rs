//! Meshes for bodies that have none, matched to their colliders and coloured by mass from
//! light blue (light) to red (heavy), as the 2015 engine did.

use bevy::prelude::*;

use crate::body::{Mass, RigidBody};
use crate::collider::{Collider, Shape};

/// Gives every body a mesh for its collider, coloured by its mass.
pub struct BodyMeshPlugin;

/// The mass range (kg) the colour scale spans, logarithmically.
#[derive(Resource, Clone, Copy, Debug)]
pub struct MassColors {
    /// Mass at the light end of the scale, kg.
    pub light: f32,
    /// Mass at the heavy end, kg.
    pub heavy: f32,
}

impl Default for MassColors {
    fn default() -> Self {
        Self {
            light: 0.5,
            heavy: 100.0,
        }
    }
}

/// Light blue at `light` kg to red at `heavy` kg: the hue turns from 200° to 0° on a log
/// scale of the mass.
pub fn mass_color(mass: f32, scale: &MassColors) -> Color {
    let t =
        ((mass.max(1e-6) / scale.light).ln() / (scale.heavy / scale.light).ln()).clamp(0.0, 1.0);
    Color::hsl(200.0 * (1.0 - t), 0.7, 0.68 - 0.22 * t)
}

impl Plugin for BodyMeshPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<MassColors>()
            .add_systems(PostUpdate, add_body_meshes);
    }
}

/// A body that just got a collider and has no mesh yet.
type NewBody = (
    Entity,
    &'static Collider,
    Option<&'static RigidBody>,
    Option<&'static Mass>,
);

fn add_body_meshes(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    colors: Res<MassColors>,
    q: Query<NewBody, (Added<Collider>, Without<Mesh3d>)>,
) {
    for (e, collider, kind, mass) in &q {
        let dynamic = kind.is_some_and(|k| *k != RigidBody::Static);
        let (mesh, color) = match collider.shape {
            Shape::Sphere { radius } => (Sphere::new(radius).mesh().ico(3).unwrap(), None),
            Shape::Cuboid { half_extents } => (Cuboid::from_size(half_extents * 2.0).into(), None),
            Shape::Capsule {
                radius,
                half_height,
            } => (Capsule3d::new(radius, 2.0 * half_height).into(), None),
            Shape::Cylinder {
                radius,
                half_height,
            } => (Cylinder::new(radius, 2.0 * half_height).into(), None),
            // Bevy's cone, like ours, has its tip up and its origin midway.
            Shape::Cone {
                radius,
                half_height,
            } => (Cone::new(radius, 2.0 * half_height).into(), None),
            Shape::ConvexHull(_) | Shape::TriMesh(_) | Shape::HeightField(_) => {
                let (v, t) = collider.shape.triangles().unwrap_or_default();
                let tint = (!dynamic).then(|| Color::srgb(0.45, 0.5, 0.4));
                (flat_mesh(&v, &t), tint)
            }
            Shape::Plane { half_extents } => {
                let h = half_extents.unwrap_or(Vec2::splat(40.0));
                let tint = if half_extents.is_some() {
                    Color::srgba(0.75, 0.75, 0.7, 0.35)
                } else {
                    Color::srgb(0.32, 0.34, 0.32)
                };
                (Plane3d::new(Vec3::Y, h).mesh().build(), Some(tint))
            }
        };
        let color = color.unwrap_or_else(|| {
            if dynamic {
                mass_color(mass.map_or(colors.light, |m| m.0), &colors)
            } else {
                Color::srgb(0.5, 0.5, 0.5)
            }
        });
        let material = StandardMaterial {
            base_color: color,
            perceptual_roughness: 0.6,
            alpha_mode: if color.alpha() < 1.0 {
                AlphaMode::Blend
            } else {
                AlphaMode::Opaque
            },
            double_sided: !dynamic,
            cull_mode: if dynamic {
                Some(bevy::render::render_resource::Face::Back)
            } else {
                None
            },
            ..default()
        };
        let mut entity = commands.entity(e);
        entity.insert((
            Mesh3d(meshes.add(mesh)),
            MeshMaterial3d(materials.add(material)),
        ));
        if !dynamic {
            entity.insert(Pickable::IGNORE);
        }
    }
}

/// A flat-shaded mesh of triangles (each its own three vertices and face normal).
fn flat_mesh(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Mesh {
    let mut positions = Vec::with_capacity(triangles.len() * 3);
    let mut normals = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let n = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for p in [a, b, c] {
            positions.push(p.to_array());
            normals.push(n.to_array());
        }
    }
    Mesh::new(
        bevy::mesh::PrimitiveTopology::TriangleList,
        bevy::asset::RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
}
