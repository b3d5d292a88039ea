//! Collision messages: one CollisionStart when a ball lands, one CollisionEnd when it
//! bounces off, and a resting body's contacts are readable from PhysicsWorld. The bodies
//! opt in with `CollisionEventsEnabled`. Each case
//! runs under every pacing of `Pacing::GAME`, with sleeping on and off. Messages are
//! double-buffered and kept until a frame that ran a step, so a reader sees each one
//! exactly once whether it reads every step (in `FixedUpdate`, twice a frame at a 30 Hz
//! render) or once a frame (in `Update`, most frames stepping nothing at 240 Hz).

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

type Log = Vec<(bool, Entity, Entity)>;

/// What the reader in `FixedUpdate` (after writeback, every step) saw.
#[derive(Resource, Default)]
struct StepLog(Log);

/// What the reader in `Update` (once a frame, as game code would read) saw.
#[derive(Resource, Default)]
struct FrameLog(Log);

fn read(s: &mut MessageReader<CollisionStart>, e: &mut MessageReader<CollisionEnd>) -> Log {
    let mut log: Log = s.read().map(|m| (true, m.collider1, m.collider2)).collect();
    log.extend(e.read().map(|m| (false, m.collider1, m.collider2)));
    log
}

fn record_per_step(
    mut log: ResMut<StepLog>,
    mut s: MessageReader<CollisionStart>,
    mut e: MessageReader<CollisionEnd>,
) {
    log.0.extend(read(&mut s, &mut e));
}

fn record_per_frame(
    mut log: ResMut<FrameLog>,
    mut s: MessageReader<CollisionStart>,
    mut e: MessageReader<CollisionEnd>,
) {
    log.0.extend(read(&mut s, &mut e));
}

#[test]
fn bounce_starts_and_ends_one_collision() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        app.init_resource::<StepLog>()
            .init_resource::<FrameLog>()
            .add_systems(
                FixedUpdate,
                record_per_step.after(PhysicsSystems::Writeback),
            )
            .add_systems(Update, record_per_frame);
        let g = ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = ball(app, 0.5, 1.0, Vec3::Y * 2.0, Vec3::ZERO);
        app.world_mut()
            .entity_mut(b)
            .insert((Restitution(0.9), CollisionEventsEnabled));
        // Falls 1.5 m in about 0.55 s, bounces to about 1.2 m: one contact in the first
        // 0.9 s.
        step(app, 54);
        // The last step's messages reach the frame reader on its frame (`Update` runs
        // after the fixed loop), so no extra frame is needed.
        let pair = (g.min(b), g.max(b));
        let expected = [(true, pair.0, pair.1), (false, pair.0, pair.1)];
        for (reader, log) in [
            ("per step", &app.world().resource::<StepLog>().0),
            ("per frame", &app.world().resource::<FrameLog>().0),
        ] {
            assert_eq!(
                log.as_slice(),
                &expected,
                "{pacing:?} sleeping {sleeping}, read {reader}: {log:?}"
            );
        }
    });
}

#[test]
fn resting_box_reports_its_ground_contact() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        let g = ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = cuboid(app, Vec3::splat(0.5), 2.0, Vec3::Y * 0.5);
        step(app, 30);
        let world = app.world().resource::<PhysicsWorld>();
        let contacts: Vec<_> = world.contacts_of(b).collect();
        assert_eq!(contacts.len(), 1, "{what}");
        assert_eq!(contacts[0].other, g, "{what}");
        assert!(
            (contacts[0].normal - Vec3::NEG_Y).length() < 1e-5,
            "{what}: normal from the box towards the ground"
        );
        // The normal force carries the box's weight: m·g.
        let total = contacts[0].normal_force;
        let expected = 2.0 * G;
        assert!(
            (total - expected).abs() < 0.01 * expected,
            "{what}: {total} vs {expected}"
        );
    });
}

/// The step each message was read on, from the per-step reader.
#[derive(Resource, Default)]
struct TimedLog(Vec<(u64, bool, Entity, Entity)>);

fn record_timed(
    mut log: ResMut<TimedLog>,
    world: Res<PhysicsWorld>,
    mut s: MessageReader<CollisionStart>,
    mut e: MessageReader<CollisionEnd>,
) {
    let step = world.step_count();
    log.0.extend(
        read(&mut s, &mut e)
            .into_iter()
            .map(|(k, a, b)| (step, k, a, b)),
    );
}

#[test]
fn bounces_landings_and_a_removed_floor_give_the_same_messages_under_every_pacing() {
    // Three balls bounce on a floor (one lands on a box), settle (and fall asleep when
    // sleeping is on), then the floor is despawned. Every pair's messages must alternate
    // started/ended, starting with started; no message may name the floor once it is
    // gone (its pairs end silently: events never carry a dead entity); and the messages
    // must read the same per step and per frame and land on the same steps under every
    // pacing.
    for sleeping in [false, true] {
        let mut reference: Option<Vec<(u64, bool, Entity, Entity)>> = None;
        for pacing in Pacing::GAME {
            let what = format!("{pacing:?} sleeping {sleeping}");
            let mut app = paced_app(pacing, sleeping);
            app.init_resource::<TimedLog>()
                .init_resource::<FrameLog>()
                .add_systems(FixedUpdate, record_timed.after(PhysicsSystems::Writeback))
                .add_systems(Update, record_per_frame);
            let floor = app
                .world_mut()
                .spawn((
                    Collider::cuboid(5.0, 0.5, 5.0),
                    Transform::from_xyz(0.0, -0.5, 0.0),
                ))
                .id();
            let bx = cuboid(&mut app, Vec3::splat(0.5), 2.0, Vec3::new(2.0, 0.5, 0.0));
            let balls = [
                ball(&mut app, 0.5, 1.0, Vec3::new(-2.0, 2.0, 0.0), Vec3::ZERO),
                ball(&mut app, 0.3, 0.5, Vec3::new(0.0, 3.0, 1.0), Vec3::ZERO),
                ball(&mut app, 0.4, 1.0, Vec3::new(2.0, 3.0, 0.0), Vec3::ZERO),
            ];
            for &b in &balls {
                app.world_mut()
                    .entity_mut(b)
                    .insert((Restitution(0.6), CollisionEventsEnabled));
            }
            app.world_mut()
                .entity_mut(bx)
                .insert(CollisionEventsEnabled);
            step(&mut app, 240);
            if sleeping {
                assert!(
                    asleep(&app, bx),
                    "{what}: the box sleeps before the floor goes"
                );
            }
            app.world_mut().despawn(floor);
            let gone = app.world().resource::<PhysicsWorld>().step_count();
            step(&mut app, 30);

            let timed = app.world().resource::<TimedLog>().0.clone();
            // Both readers see every message exactly once. (Not in the same order: a frame
            // reader at 30 Hz reads two steps' starts, then their ends.)
            let mut per_frame = app.world().resource::<FrameLog>().0.clone();
            let mut untimed: Log = timed.iter().map(|&(_, k, a, b)| (k, a, b)).collect();
            per_frame.sort();
            untimed.sort();
            assert_eq!(untimed, per_frame, "{what}: per step vs per frame");
            // Each pair alternates started/ended, ends ended (nothing touches any more).
            let mut pairs: Vec<(Entity, Entity)> =
                timed.iter().map(|&(_, _, a, b)| (a, b)).collect();
            pairs.sort();
            pairs.dedup();
            for &p in &pairs {
                assert!(p.0 < p.1, "{what}: pair {p:?} not in entity order");
                let kinds: Vec<bool> = timed
                    .iter()
                    .filter(|&&(_, _, a, b)| (a, b) == p)
                    .map(|&(_, k, _, _)| k)
                    .collect();
                let alternating = kinds.iter().enumerate().all(|(i, &k)| k == (i % 2 == 0));
                assert!(
                    alternating,
                    "{what}: pair {p:?} got {kinds:?} (true = started)"
                );
            }
            let late: Vec<_> = timed
                .iter()
                .filter(|&&(k, _, a, b)| k > gone && (a == floor || b == floor))
                .collect();
            assert!(
                late.is_empty(),
                "{what}: messages name the despawned floor: {late:?}"
            );
            // The bodies the floor carried fell once it was gone: their pairs among
            // themselves, if any, are the ball riding the box down.
            assert!(pos(&app, bx).y < -0.5, "{what}: the box fell");
            // The floor and every body it carried, and the ball on the box.
            let touched = |e: Entity, f: Entity| pairs.contains(&(e.min(f), e.max(f)));
            assert!(touched(floor, bx), "{what}: {pairs:?}");
            assert!(touched(balls[0], floor), "{what}: {pairs:?}");
            assert!(touched(balls[1], floor), "{what}: {pairs:?}");
            assert!(touched(balls[2], bx), "{what}: {pairs:?}");
            match &reference {
                None => reference = Some(timed),
                Some(r) => assert_eq!(r, &timed, "{what} differs from one step per update"),
            }
        }
    }
}
