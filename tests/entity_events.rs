//! Per-entity collision events: observers on a collider see its own hits, with the
//! contact's data; events are opt-in, and never name a despawned entity. Under every
//! game pacing, sleeping on and off.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

/// Every event an observer saw: (step, start?, collider1, collider2, data).
#[derive(Resource, Default)]
struct Seen(Vec<(u64, bool, Entity, Entity, Option<CollisionStart>)>);

fn watch(app: &mut App, e: Entity) {
    app.world_mut()
        .entity_mut(e)
        .insert(CollisionEventsEnabled)
        .observe(
            |hit: On<CollisionStart>, world: Res<PhysicsWorld>, mut seen: ResMut<Seen>| {
                let h = *hit.event();
                seen.0
                    .push((world.step_count(), true, h.collider1, h.collider2, Some(h)));
            },
        )
        .observe(
            |end: On<CollisionEnd>, world: Res<PhysicsWorld>, mut seen: ResMut<Seen>| {
                let e = *end.event();
                seen.0
                    .push((world.step_count(), false, e.collider1, e.collider2, None));
            },
        );
}

/// Each step's vertical velocity of `body`, recorded after writeback.
#[derive(Resource)]
struct VelocityLog(Entity, Vec<(u64, f32)>);

fn log_velocity(mut log: ResMut<VelocityLog>, world: Res<PhysicsWorld>, q: Query<&Velocity>) {
    let v = q.get(log.0).map_or(f32::NAN, |v| v.linear.y);
    log.1.push((world.step_count(), v));
}

#[test]
fn an_observer_on_a_landing_ball_sees_its_own_hit_and_its_impulse() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.init_resource::<Seen>();
        let (r, m, h) = (0.25, 2.0, 1.2);
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = ball(app, r, m, Vec3::Y * (r + h), Vec3::ZERO);
        watch(app, b);
        app.insert_resource(VelocityLog(b, Vec::new()))
            .add_systems(FixedUpdate, log_velocity.after(PhysicsSystems::Writeback));
        step(app, 60);
        let seen = &app.world().resource::<Seen>().0;
        assert_eq!(seen.len(), 1, "{what}: one event, the landing: {seen:?}");
        let (k, start, c1, c2, data) = seen[0];
        let hit = data.unwrap();
        assert!(start && c1 == b && c2 == floor, "{what}: {seen:?}");
        assert_eq!(
            (hit.body1, hit.body2),
            (Some(b), None),
            "{what}: the floor has no body"
        );
        assert!(!hit.sensor);
        assert_near_vec(
            hit.contact.normal,
            Vec3::NEG_Y,
            1e-5,
            &format!("{what}: normal"),
        );
        // Impact speed: the fall's √(2gh), read at the start of the landing step, so up
        // to one step's g·h early.
        let v_fall = (2.0 * G * h).sqrt();
        assert_near(
            hit.contact.impact_speed,
            v_fall,
            G * H,
            &format!("{what}: impact speed"),
        );
        // The step's impulse balances the ball's momentum: J − m·g·h = m·(v_after − v_before).
        let log = &app.world().resource::<VelocityLog>().1;
        let v_at = |step: u64| log.iter().find(|(s, _)| *s == step).unwrap().1;
        let expected = m * (v_at(k) - v_at(k - 1)) + m * G * H;
        assert_near(
            hit.contact.normal_impulse,
            expected,
            1e-4 * m * v_fall,
            &format!("{what}: impulse over the landing step"),
        );
        assert!(hit.contact.len >= 1 && hit.contact.penetration >= 0.0);
        let p = hit.contact.points()[0];
        assert_near(
            p.x.hypot(p.z),
            0.0,
            1e-4,
            &format!("{what}: point under the ball"),
        );
    });
}

#[test]
fn each_side_that_opted_in_gets_its_own_event_and_the_others_none() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.init_resource::<Seen>();
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        let lower = cuboid(app, Vec3::splat(0.5), 1.0, Vec3::Y * 0.5);
        let upper = ball(app, 0.3, 1.0, Vec3::Y * 2.0, Vec3::ZERO);
        let quiet = ball(app, 0.3, 1.0, Vec3::new(3.0, 0.3, 0.0), Vec3::ZERO);
        watch(app, lower);
        watch(app, upper);
        step(app, 60);
        let seen = &app.world().resource::<Seen>().0;
        let starts: Vec<(Entity, Entity)> =
            seen.iter().filter(|s| s.1).map(|s| (s.2, s.3)).collect();
        for pair in [(lower, floor), (lower, upper), (upper, lower)] {
            let n = starts.iter().filter(|&&p| p == pair).count();
            assert_eq!(n, 1, "{what}: {pair:?} in {starts:?}");
        }
        assert_eq!(
            starts.len(),
            3,
            "{what}: nothing for the floor or {quiet}: {starts:?}"
        );
    });
}

#[derive(Resource, Default)]
struct Messages(usize);

fn count_messages(
    mut n: ResMut<Messages>,
    mut s: MessageReader<CollisionStart>,
    mut e: MessageReader<CollisionEnd>,
) {
    n.0 += s.read().count() + e.read().count();
}

#[test]
fn without_opting_in_nothing_is_sent_or_kept() {
    // Sleeping off: the test counts the resting balls' contacts, which sleepers drop.
    let mut app = app_without_sleeping();
    app.init_resource::<Messages>()
        .add_systems(Update, count_messages);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    for i in 0..10 {
        ball(
            &mut app,
            0.3,
            1.0,
            Vec3::new(i as f32, 1.0, 0.0),
            Vec3::ZERO,
        );
    }
    step(&mut app, 60);
    assert_eq!(app.world().resource::<Messages>().0, 0);
    assert!(app.world().resource::<PhysicsWorld>().reported_pairs() == 0);
    // The contacts are there, only unreported.
    assert_eq!(
        app.world().resource::<PhysicsWorld>().contact_manifolds(),
        10
    );
}

#[test]
fn a_despawned_collider_is_never_named() {
    under_every_pacing(&Pacing::GAME, &[false, true], |app, sleeping, pacing| {
        let what = format!("{pacing:?} sleeping {sleeping}");
        app.init_resource::<Seen>();
        ground(app, Vec3::ZERO, Quat::IDENTITY);
        let plate = cuboid(app, Vec3::new(1.0, 0.1, 1.0), 1.0, Vec3::Y * 0.1);
        let b = ball(app, 0.3, 1.0, Vec3::Y * 0.5, Vec3::ZERO);
        watch(app, plate);
        watch(app, b);
        step(app, 120);
        app.world_mut().despawn(plate);
        let gone = app.world().resource::<PhysicsWorld>().step_count();
        step(app, 60);
        let seen = &app.world().resource::<Seen>().0;
        let late: Vec<_> = seen.iter().filter(|s| s.0 > gone).collect();
        // The ball falls 0.2 m onto the ground: its one new event names the ground.
        assert!(
            late.iter().all(|s| s.2 != plate && s.3 != plate),
            "{what}: {late:?}"
        );
        assert_eq!(
            late.len(),
            1,
            "{what}: the ball lands on the ground: {late:?}"
        );
    });
}

/// The touching slop scales with the pair: a 1 cm marble (restitution 0.6, dropped 1 cm)
/// bounces 3.6 mm, a third of its size. That is a new collision: the landing, the end
/// as it leaves, the second landing one flight time 2·e·√(2gh)/g (54 ms) later. With a
/// fixed 5 mm slop the marble never stopped touching.
#[test]
fn a_marble_bouncing_a_third_of_its_size_ends_touching_and_lands_again() {
    under_every_pacing(&Pacing::GAME, &[false], |app, _, pacing| {
        let what = format!("{pacing:?}");
        app.init_resource::<Seen>();
        app.world_mut()
            .resource_mut::<SolverSettings>()
            .restitution_threshold = 0.1;
        let (r, m, h, e) = (0.005, 0.004, 0.01, 0.6);
        let floor = ground(app, Vec3::ZERO, Quat::IDENTITY);
        let b = ball(app, r, m, Vec3::Y * (r + h), Vec3::ZERO);
        app.world_mut().entity_mut(b).insert(Restitution(e));
        watch(app, b);
        step(app, 30);
        let seen = &app.world().resource::<Seen>().0;
        let kinds: Vec<bool> = seen.iter().take(3).map(|s| s.1).collect();
        assert_eq!(
            kinds,
            [true, false, true],
            "{what}: land, leave, land: {seen:?}"
        );
        assert!(seen.iter().all(|s| s.2 == b && s.3 == floor), "{what}");
        let flight = 2.0 * e * (2.0 * G * h).sqrt() / G;
        let steps = (seen[2].0 - seen[0].0) as f32;
        assert_near(
            steps * H,
            flight,
            H,
            &format!("{what}: time between landings"),
        );
    });
}
