//! The game's rules, without rendering: shared by `main.rs` (the window) and
//! `tests/game_example.rs` (driven headless). A player box on a floor and a moving
//! platform, a pickup (a sensor), a target crate, projectiles that ignore their shooter.

use bevy::prelude::*;
use tumble::prelude::*;

tumble::physics_layers! {
    /// What touches what: projectiles skip the player and pickups; pickups only sense
    /// the player.
    pub enum Layer { World, Player, Projectile, Pickup }
}

/// What the player asks for this frame (keys in the window, a script in the test).
#[derive(Resource, Default)]
pub struct Controls {
    /// −1 left, +1 right.
    pub walk: f32,
    pub jump: bool,
    pub fire: bool,
}

/// What happened: pickups collected, hits landed (and the hardest, m/s).
#[derive(Resource, Default, Debug)]
pub struct Score {
    pub pickups: u32,
    pub hits: u32,
    pub hardest_hit: f32,
}

#[derive(Component)]
pub struct Player;
#[derive(Component)]
pub struct Platform;
#[derive(Component)]
pub struct Projectile;
#[derive(Component)]
pub struct Crate;

pub const WALK_SPEED: f32 = 3.0;
pub const JUMP_SPEED: f32 = 5.0;
pub const SHOT_SPEED: f32 = 20.0;
const PLAYER_MASS: f32 = 60.0;

pub fn plugin(app: &mut App) {
    app.init_resource::<Controls>()
        .init_resource::<Score>()
        .add_systems(Startup, spawn_level)
        .add_systems(Update, steer_player)
        // Kinematic moves go in the fixed step, one per step: smooth whatever the render
        // rate (moved in `Update`, a platform's speed would follow the frame/step beat).
        .add_systems(FixedUpdate, move_platform.before(PhysicsSystems::Prepare));
}

pub fn spawn_level(mut commands: Commands) {
    let world = CollisionLayers::new(Layer::World, LayerMask::ALL);
    commands.spawn((
        Collider::cuboid(20.0, 0.5, 5.0),
        Transform::from_xyz(0.0, -0.5, 0.0),
        world,
    ));
    // A platform the game moves by its Transform every frame: it carries the crate on
    // it. Already smooth, so not interpolated (interpolation would take each move for
    // a teleport and fight it).
    commands.spawn((
        Platform,
        RigidBody::Kinematic,
        Collider::cuboid(1.5, 0.1, 1.5),
        Transform::from_xyz(-6.0, 1.0, 0.0),
        world,
    ));
    commands.spawn((
        Crate,
        RigidBody::Dynamic,
        Collider::cuboid(0.3, 0.3, 0.3),
        Mass(5.0),
        Transform::from_xyz(-6.0, 1.4, 0.0),
        world,
        TransformInterpolation,
    ));
    commands.spawn((
        Player,
        RigidBody::Dynamic,
        Collider::cuboid(0.3, 0.6, 0.3),
        Mass(PLAYER_MASS),
        LockRotation,
        Friction(0.0),
        Transform::from_xyz(0.0, 0.6, 0.0),
        CollisionLayers::new(Layer::Player, [Layer::World, Layer::Pickup]),
        TransformInterpolation,
    ));
    // The pickup floats above the player's start: a jump collects it.
    commands
        .spawn((
            Collider::sphere(0.3),
            Sensor,
            Transform::from_xyz(0.0, 2.0, 0.0),
            CollisionLayers::new(Layer::Pickup, Layer::Player),
            CollisionEventsEnabled,
        ))
        .observe(collect);
    // The target: it reports its own hits.
    commands
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(0.5, 0.5, 0.5),
            Mass(20.0),
            Transform::from_xyz(8.0, 0.5, 0.0),
            CollisionLayers::new(Layer::World, LayerMask::ALL),
            CollisionEventsEnabled,
            TransformInterpolation,
        ))
        .observe(take_hit);
}

/// The platform slides 3 m and back every 6 s, from rest (peak 1.6 m/s², well below
/// what friction holds: the crate rides it).
fn move_platform(time: Res<Time>, mut q: Query<&mut Transform, With<Platform>>) {
    let phase = time.elapsed_secs() * std::f32::consts::TAU / 6.0;
    for mut tf in &mut q {
        tf.translation.x = -6.0 + 1.5 * (1.0 - phase.cos());
    }
}

/// Walk by velocity, jump by impulse, shoot.
fn steer_player(
    mut commands: Commands,
    mut controls: ResMut<Controls>,
    mut q: Query<(Entity, &Transform, &mut Velocity), With<Player>>,
) {
    let Ok((player, tf, mut vel)) = q.single_mut() else {
        return;
    };
    // Written only when it changes: a write wakes a sleeping body.
    let walk = controls.walk * WALK_SPEED;
    if vel.linear.x != walk {
        vel.linear.x = walk;
    }
    if std::mem::take(&mut controls.jump) {
        let up = Vec3::Y * PLAYER_MASS * JUMP_SPEED;
        commands.entity(player).insert(ExternalImpulse::new(up));
    }
    if std::mem::take(&mut controls.fire) {
        // Spawned inside the player: its layers make it pass through its shooter.
        commands.spawn((
            Projectile,
            RigidBody::Dynamic,
            Collider::sphere(0.1),
            Mass(0.5),
            GravityScale(0.0),
            Transform::from_translation(tf.translation),
            Velocity::linear(Vec3::X * SHOT_SPEED),
            CollisionLayers::new(Layer::Projectile, Layer::World),
            CollisionEventsEnabled,
            TransformInterpolation,
        ));
    }
}

fn collect(
    hit: On<CollisionStart>,
    players: Query<(), With<Player>>,
    mut score: ResMut<Score>,
    mut commands: Commands,
) {
    if players.contains(hit.collider2) {
        score.pickups += 1;
        commands.entity(hit.collider1).despawn();
    }
}

fn take_hit(hit: On<CollisionStart>, shots: Query<(), With<Projectile>>, mut score: ResMut<Score>) {
    if shots.contains(hit.collider2) {
        score.hits += 1;
        score.hardest_hit = score.hardest_hit.max(hit.contact.impact_speed);
    }
}
