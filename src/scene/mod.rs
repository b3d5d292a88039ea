//! Scenes as data: the RON files in `assets/scenes/` describe settings, static planes and
//! bodies (single or generated: grids, stacks, pyramids, seeded random piles). The demo
//! loads them through the asset system; tests and benches parse the very same files and
//! spawn them with [`SceneDesc::spawn`], no asset server needed.

mod check;
mod desc;
mod generate;
mod joints;
#[cfg(feature = "viz")]
mod loader;

pub use desc::*;
pub use generate::{expand_group, group_size, rock_points};
pub use joints::{JointDesc, JointGroup, JointKindDesc};
#[cfg(feature = "viz")]
pub use loader::SceneLoader;

use bevy::prelude::*;

use crate::body::*;
use crate::collider::Collider;
use crate::settings::{Gravity, Integrator, SolverSettings};

/// The most bodies a scene file may generate.
pub const MAX_SCENE_BODIES: u64 = 1_000_000;

/// Marks an entity spawned from a scene, so a scene switch can despawn exactly those.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct SceneEntity;

/// Why a scene file could not be read: the file and, for syntax errors, line and column.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("could not read scene file: {0}")]
    Io(#[from] std::io::Error),
    /// The text is not a scene: a syntax error, a refused value, or more than
    /// [`MAX_SCENE_BODIES`] bodies.
    #[error("{path}:{line}:{col}: {message}")]
    Parse {
        /// The file, as named to [`SceneDesc::from_ron`].
        path: String,
        /// Line of the error, counting from 1.
        line: usize,
        /// Column of the error, counting from 1.
        col: usize,
        /// What is wrong.
        message: String,
    },
}

impl SceneDesc {
    /// Parses a scene from RON text; `path` names the file in errors.
    pub fn from_ron(text: &str, path: &str) -> Result<Self, SceneError> {
        let scene: Self =
            ron::from_str(text).map_err(|e: ron::error::SpannedError| SceneError::Parse {
                path: path.to_string(),
                line: e.span.start.line,
                col: e.span.start.col,
                message: e.code.to_string(),
            })?;
        let total: u64 = scene.bodies.iter().map(generate::group_size).sum();
        if total > MAX_SCENE_BODIES {
            return Err(SceneError::Parse {
                path: path.to_string(),
                line: 1,
                col: 1,
                message: format!(
                    "invalid value: bodies make {total} bodies, more than {MAX_SCENE_BODIES}"
                ),
            });
        }
        Ok(scene)
    }

    /// Reads and parses a scene file.
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Self, SceneError> {
        let path = path.as_ref();
        Self::from_ron(&std::fs::read_to_string(path)?, &path.display().to_string())
    }

    /// Every body the scene describes, with its groups expanded.
    pub fn expanded_bodies(&self) -> Vec<BodyDesc> {
        self.bodies.iter().flat_map(expand_group).collect()
    }

    /// Applies the scene's settings to the simulation resources.
    pub fn apply_settings(&self, commands: &mut Commands) {
        let s = self.settings;
        commands.insert_resource(Gravity(s.gravity));
        commands.insert_resource(s.integrator);
        // Files are checked on load; a scene built in code is clamped here.
        let (hz, why) = crate::limits::clamp_rate(s.hz);
        if let Some(why) = why {
            error!("tumble: scene {:?} settings.hz: {why}", self.name);
        }
        commands.insert_resource(Time::<Fixed>::from_hz(hz));
        let solver = SolverSettings {
            substeps: s.substeps,
            iterations: s.iterations,
            ..default()
        };
        commands.insert_resource(solver);
        commands.insert_resource(s.effects);
        commands.insert_resource(s.wind);
    }

    /// Spawns the scene's settings, planes and bodies. Returns the body entities.
    pub fn spawn(&self, commands: &mut Commands) -> Vec<Entity> {
        self.apply_settings(commands);
        for plane in &self.planes {
            commands.spawn(plane_bundle(plane));
        }
        for mesh in &self.meshes {
            match mesh.collider() {
                Ok((collider, tf)) => {
                    commands.spawn((SceneEntity, Name::new("mesh"), collider, tf));
                }
                Err(why) => error!("tumble: scene {:?}: a mesh is left out: {why}", self.name),
            }
        }
        let bodies: Vec<Entity> = self
            .expanded_bodies()
            .iter()
            .map(|b| {
                let mut e = commands.spawn(body_bundle(b));
                // Only what a body asks for: a component no one needs costs the gather.
                if b.lock_rotation {
                    e.insert(crate::effects::LockRotation);
                }
                if b.force != Vec3::ZERO {
                    e.insert(ExternalForce::new(b.force));
                }
                if b.linear_damping != 0.0 {
                    e.insert(LinearDamping(b.linear_damping));
                }
                e.id()
            })
            .collect();
        for joint in self.joints.iter().flat_map(|g| g.expand()) {
            match joint.joint(&bodies) {
                Ok(j) => {
                    commands.spawn((SceneEntity, Name::new("joint"), j));
                }
                Err(why) => error!("tumble: scene {:?}: a joint is left out: {why}", self.name),
            }
        }
        bodies
    }

    /// Spawns into a `World` directly (tests, benches).
    pub fn spawn_into(&self, world: &mut World) -> Vec<Entity> {
        let ids = self.spawn(&mut world.commands());
        world.flush();
        ids
    }

    /// A headless app with this scene in it: MinimalPlugins, TransformPlugin and
    /// TumblePlugin, exactly one fixed step per `update()`, the plugin started (one
    /// update run) before the scene is spawned. Returns the app and the scene's bodies,
    /// in the file's order (the examples' and benches' one builder).
    pub fn headless_app(&self) -> (App, Vec<Entity>) {
        let mut app = App::new();
        app.add_plugins((
            MinimalPlugins,
            TransformPlugin,
            crate::TumblePlugin::default(),
        ))
        .insert_resource(bevy::time::TimeUpdateStrategy::FixedTimesteps(1));
        app.update();
        let bodies = self.spawn_into(app.world_mut());
        (app, bodies)
    }
}

fn plane_bundle(p: &PlaneDesc) -> impl Bundle {
    let collider = match p.half_extents {
        Some(h) => Collider::plane_rect(h.x, h.y),
        None => Collider::plane(),
    };
    (
        SceneEntity,
        Name::new("plane"),
        collider,
        Transform::from_translation(p.position).with_rotation(p.rotation()),
        Friction(p.friction),
        Restitution(p.restitution),
    )
}

fn body_bundle(b: &BodyDesc) -> impl Bundle {
    (
        SceneEntity,
        b.kind,
        b.collider(),
        Mass(b.mass()),
        Transform::from_translation(b.position).with_rotation(b.rotation()),
        Velocity {
            linear: b.velocity,
            angular: b.angular_velocity,
        },
        Friction(b.friction.unwrap_or(DEFAULT_FRICTION)),
        Restitution(b.restitution.unwrap_or(0.0)),
    )
}

/// The integrator names scene files use.
pub fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::ExplicitEuler => "explicit Euler",
        Integrator::SemiImplicitEuler => "semi-implicit Euler",
        Integrator::Rk4 => "RK4",
    }
}
