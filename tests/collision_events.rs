//! Collision messages: one CollisionStarted when a ball lands, one CollisionEnded when it
//! bounces off, and a resting body's contacts are readable from PhysicsWorld.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[derive(Resource, Default)]
struct Log(Vec<(bool, Entity, Entity)>);

fn record(
    mut log: ResMut<Log>,
    mut s: MessageReader<CollisionStarted>,
    mut e: MessageReader<CollisionEnded>,
) {
    log.0.extend(s.read().map(|m| (true, m.a, m.b)));
    log.0.extend(e.read().map(|m| (false, m.a, m.b)));
}

#[test]
fn bounce_starts_and_ends_one_collision() {
    let mut app = app();
    app.init_resource::<Log>()
        .add_systems(FixedUpdate, record.after(PhysicsSystems::Writeback));
    let g = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, 0.5, 1.0, Vec3::Y * 2.0, Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Restitution(0.9));
    // Falls 1.5 m in about 0.55 s, bounces to about 1.2 m: one contact in the first 0.9 s.
    step(&mut app, 54);
    let pair = (g.min(b), g.max(b));
    let log = &app.world().resource::<Log>().0;
    assert_eq!(
        log.as_slice(),
        &[(true, pair.0, pair.1), (false, pair.0, pair.1)],
        "{log:?}"
    );
}

#[test]
fn resting_box_reports_its_ground_contact() {
    let mut app = app();
    let g = ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.5), 2.0, Vec3::Y * 0.5);
    step(&mut app, 30);
    let world = app.world().resource::<PhysicsWorld>();
    let contacts: Vec<_> = world.contacts_of(b).collect();
    assert_eq!(contacts.len(), 1);
    assert_eq!(contacts[0].other, g);
    assert!(
        (contacts[0].normal - Vec3::NEG_Y).length() < 1e-5,
        "normal from the box towards the ground"
    );
    // The normal impulses carry the box's weight: Σλ per substep = m·g·h/substeps.
    let total: f32 = contacts[0]
        .manifold
        .points()
        .iter()
        .map(|p| p.normal_impulse)
        .sum();
    let expected = 2.0 * 9.81 * H / 4.0;
    assert!(
        (total - expected).abs() < 0.01 * expected,
        "{total} vs {expected}"
    );
}
