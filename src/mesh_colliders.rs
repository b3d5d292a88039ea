//! Colliders from Bevy meshes (feature `mesh`): a triangle mesh or a convex hull from a
//! `Mesh`'s positions, and components that build them for entities with a `Mesh3d` once
//! the mesh has loaded — one entity ([`ColliderConstructor`]) or a whole spawned scene,
//! such as a glTF level ([`ColliderConstructorHierarchy`], after avian3d's).

use bevy::asset::Assets;
use bevy::mesh::{Indices, Mesh, Mesh3d, PrimitiveTopology};
use bevy::prelude::*;

use crate::collider::Collider;

impl Collider {
    /// A triangle mesh of `mesh`'s triangles (positions in the mesh's frame, m). Fails on
    /// a mesh that is not a triangle list, has no positions (or its data went to the
    /// render world only), or has no triangles.
    pub fn trimesh_from_mesh(mesh: &Mesh) -> Result<Self, String> {
        let positions = positions(mesh)?;
        if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
            return Err(format!(
                "a {:?} mesh, not a triangle list",
                mesh.primitive_topology()
            ));
        }
        let triangles: Vec<[u32; 3]> = match mesh.try_indices().ok() {
            Some(Indices::U16(i)) => i
                .chunks_exact(3)
                .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
                .collect(),
            Some(Indices::U32(i)) => i.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            // Unindexed: every three positions are a triangle.
            None => (0..positions.len() as u32 / 3)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect(),
        };
        Collider::trimesh(positions, triangles)
    }

    /// The convex hull of `mesh`'s positions (m, the mesh's frame).
    pub fn convex_hull_from_mesh(mesh: &Mesh) -> Result<Self, String> {
        Collider::convex_hull(&positions(mesh)?).ok_or_else(|| "its points span no volume".into())
    }
}

/// A mesh's vertex positions.
fn positions(mesh: &Mesh) -> Result<Vec<Vec3>, String> {
    let values = mesh
        .try_attribute(Mesh::ATTRIBUTE_POSITION)
        .map_err(|e| format!("no vertex positions ({e})"))?;
    let points = values.as_float3().ok_or("positions are not three floats")?;
    Ok(points.iter().map(|&p| Vec3::from(p)).collect())
}

/// Which collider to build from a mesh.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub enum ColliderConstructor {
    /// Its triangles: for static (and kinematic) level geometry.
    #[default]
    TriMesh,
    /// The convex hull of its points: for anything, dynamic bodies included.
    ConvexHull,
}

impl ColliderConstructor {
    fn build(self, mesh: &Mesh) -> Result<Collider, String> {
        match self {
            ColliderConstructor::TriMesh => Collider::trimesh_from_mesh(mesh),
            ColliderConstructor::ConvexHull => Collider::convex_hull_from_mesh(mesh),
        }
    }
}

/// On a scene's root (a glTF `SceneRoot`, say): every descendant with a `Mesh3d` and no
/// `Collider` gets one built from its mesh once the scene has spawned and its meshes have
/// loaded; then this component removes itself. The colliders sit on the mesh entities,
/// placed by their transforms: static, or parts of a `RigidBody` above them.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub struct ColliderConstructorHierarchy(pub ColliderConstructor);

/// Builds the colliders [`ColliderConstructor`] and [`ColliderConstructorHierarchy`] ask
/// for, as their meshes load. A mesh that can't make one is reported once by entity, and
/// left without.
pub fn construct_colliders(
    mut commands: Commands,
    meshes: Option<Res<Assets<Mesh>>>,
    singles: Query<(Entity, &ColliderConstructor, &Mesh3d), Without<Collider>>,
    roots: Query<(Entity, &ColliderConstructorHierarchy)>,
    children: Query<&Children>,
    with_mesh: Query<&Mesh3d, Without<Collider>>,
) {
    let Some(meshes) = meshes else { return };
    for (entity, constructor, handle) in &singles {
        if build(&mut commands, &meshes, entity, *constructor, handle) {
            commands.entity(entity).remove::<ColliderConstructor>();
        }
    }
    for (root, hierarchy) in &roots {
        // A scene spawns its entities some frames after its root: wait for meshes.
        let (mut found, mut waiting) = (false, false);
        for entity in std::iter::once(root).chain(children.iter_descendants(root)) {
            if let Ok(handle) = with_mesh.get(entity) {
                found = true;
                waiting |= !build(&mut commands, &meshes, entity, hierarchy.0, handle);
            }
        }
        if found && !waiting {
            commands
                .entity(root)
                .remove::<ColliderConstructorHierarchy>();
        }
    }
}

/// Builds `entity`'s collider if its mesh has loaded; returns whether it had.
fn build(
    commands: &mut Commands,
    meshes: &Assets<Mesh>,
    entity: Entity,
    constructor: ColliderConstructor,
    handle: &Mesh3d,
) -> bool {
    let Some(mesh) = meshes.get(&handle.0) else {
        return false;
    };
    match constructor.build(mesh) {
        Ok(collider) => {
            commands.entity(entity).insert(collider);
        }
        Err(why) => warn!("tumble: no {constructor:?} collider for mesh entity {entity}: {why}"),
    }
    true
}
