//! Constraints built in two halves (the second on the compute pool) against the one
//! run they stand for: on real scenes' manifolds, with rolling shapes (whose motions the
//! halves number on their own) and with the fixed contacts at the front running past the
//! first half, every constraint, rolling motion and finding must be the same bits.

use bevy::tasks::{ComputeTaskPool, TaskPoolBuilder};

use super::prepare_constraints;
use super::survey::{PerBody, survey_contacts};
use crate::scene::SceneDesc;
use crate::world::{ContactKey, ContactParams, PhysicsWorld};

fn params() -> ContactParams {
    ContactParams {
        friction: true,
        hertz: 30.0,
        max_hertz: 60.0,
        gravity: 9.81,
        damping_ratio: 10.0,
        h: 1.0 / 240.0,
        dt: 1.0 / 60.0,
        max_push_out: 3.0,
        max_sag: 0.01,
    }
}

/// Prepares the first `n` manifolds whole and split, and compares everything.
fn compare(world: &PhysicsWorld, per_body: &PerBody, n: usize, what: &str) -> usize {
    let m = &world.manifolds[..n];
    let (c, s, b) = (&world.colliders, &world.bodies, &world.solver_bodies);
    let counts = (&*per_body.overlaps, &*per_body.heaviest);
    let (mut one, mut two) = (Vec::new(), Vec::new());
    let (mut arms1, mut arms2) = (Vec::new(), Vec::new());
    let (mut keys1, mut keys2) = (Vec::new(), Vec::new());
    let out1 = (&mut one, &mut keys1);
    let f1 = prepare_constraints(m, c, s, b, params(), counts, out1, &mut arms1, false);
    let out2 = (&mut two, &mut keys2);
    let f2 = prepare_constraints(m, c, s, b, params(), counts, out2, &mut arms2, true);
    assert_eq!(f1, f2, "{what}: findings");
    assert_eq!(keys1, keys2, "{what}: keys");
    for (i, (c, k)) in one.iter().zip(&keys1).enumerate() {
        assert_eq!(ContactKey::of(c, b), *k, "{what}: key {i}");
    }
    assert_eq!(
        format!("{arms1:?}"),
        format!("{arms2:?}"),
        "{what}: rolling motions"
    );
    assert_eq!(one.len(), n, "{what}: one constraint a manifold");
    for (i, (x, y)) in one.iter().zip(&two).enumerate() {
        assert_eq!(format!("{x:?}"), format!("{y:?}"), "{what}: constraint {i}");
    }
    f1.fixed
}

#[test]
fn constraints_built_in_halves_are_the_same_bits() {
    ComputeTaskPool::get_or_init(|| TaskPoolBuilder::new().num_threads(2).build());
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut rolled = 0;
    for (file, steps) in [
        ("3_pyramid.scene.ron", 30),
        ("10_shapes.scene.ron", 90),
        ("15_ragdolls.scene.ron", 60),
    ] {
        let scene = SceneDesc::load(dir.join(file)).expect("scene file");
        let (mut app, _) = scene.headless_app();
        for _ in 0..steps {
            app.update();
        }
        let mut world = app.world_mut().resource_mut::<PhysicsWorld>();
        let world = &mut *world;
        let mut per_body = PerBody::default();
        survey_contacts(world, &params(), true, &mut per_body);
        let n = world.manifolds.len();
        assert!(n >= 8, "{file}: only {n} manifolds");
        let fixed = compare(world, &per_body, n, file);
        // The fixed contacts filling the whole first half: the second half's count on.
        let short = (fixed + 3).min(n);
        compare(world, &per_body, short, &format!("{file}, first {short}"));
        let mut arms = Vec::new();
        let (m, c, s, b) = (
            &world.manifolds,
            &world.colliders,
            &world.bodies,
            &world.solver_bodies,
        );
        let counts = (&*per_body.overlaps, &*per_body.heaviest);
        let out = (&mut Vec::new(), &mut Vec::new());
        prepare_constraints(m, c, s, b, params(), counts, out, &mut arms, false);
        rolled += arms.len();
    }
    assert!(rolled > 0, "no scene had a rolling shape in contact");
}
