//! Contacts built in two halves (the second on the compute pool) against the one run
//! they stand for, and built straight into their lanes against the lanes packed from
//! their whole constraints: on real scenes' manifolds, with rolling shapes (whose motions
//! the halves number on their own) and with the fixed contacts at the front running past
//! the first half, every lane, kept constraint, rolling motion and finding must be the
//! same bits. And every contact built in lanes (`ContactLanes`, in each compiled copy)
//! against the scalar reference (`Builder::build`), bit for bit.

use bevy::tasks::{ComputeTaskPool, TaskPoolBuilder};

use super::contact::{Builder, Prepared};
use super::prepare_contacts::prepare_contacts;
use super::survey::{PerBody, survey_contacts};
use crate::scene::SceneDesc;
use crate::world::{
    ContactBatches, ContactConstraint, ContactKey, ContactParams, PhysicsWorld, RollingArms,
};

fn params() -> ContactParams {
    ContactParams {
        bounce_threshold: 1.0,
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

/// What one preparation made.
#[derive(Default)]
struct Made {
    constraints: Vec<ContactConstraint>,
    keys: Vec<ContactKey>,
    batches: ContactBatches,
    arms: Vec<RollingArms>,
}

impl Made {
    /// The batches, their lanes and the steps, as text to compare bit for bit.
    fn lanes(&self) -> String {
        let b = &self.batches;
        format!(
            "{:?}",
            (&b.batches, &b.points, &b.anchors, &b.friction, &b.steps)
        )
    }
}

/// The first `n` manifolds of `world` prepared (`split` on two threads; `keep_all`
/// keeps every constraint).
fn prepare(
    world: &PhysicsWorld,
    per_body: &PerBody,
    n: usize,
    split: bool,
    keep_all: bool,
) -> (Made, Prepared) {
    let m = &world.manifolds[..n];
    let scene = (&*world.colliders, &*world.bodies, &*world.solver_bodies);
    let counts = (&*per_body.overlaps, &*per_body.heaviest);
    let mut made = Made::default();
    let out = (&mut made.constraints, &mut made.keys);
    let lists = (&mut made.batches, &mut made.arms);
    let found = prepare_contacts(m, scene, params(), counts, out, lists, (split, keep_all));
    (made, found)
}

/// Prepares the first `n` manifolds whole and split, keeping every constraint and not,
/// and compares everything; and the lanes built straight from the manifolds against
/// those packed from the whole constraints.
/// Returns the fixed contacts and how many contacts were built in lanes.
fn compare(world: &PhysicsWorld, per_body: &PerBody, n: usize, what: &str) -> (usize, usize) {
    let b = &world.solver_bodies;
    let (one, f1) = prepare(world, per_body, n, false, true);
    assert_eq!(
        one.constraints.len(),
        n,
        "{what}: one constraint a manifold"
    );
    for (i, (c, k)) in one.constraints.iter().zip(&one.keys).enumerate() {
        assert_eq!(ContactKey::of(c, b), *k, "{what}: key {i}");
    }
    let mut packed = ContactBatches::default();
    packed.build(&one.constraints, b, f1.fixed);
    let packed = Made {
        batches: packed,
        ..Made::default()
    };
    assert_eq!(
        one.lanes(),
        packed.lanes(),
        "{what}: lanes built against packed"
    );
    // The lanes' arithmetic against the scalar reference, contact by contact.
    let counts = (&*per_body.overlaps, &*per_body.heaviest);
    let builder = Builder::new(&world.colliders, &world.bodies, b, params(), counts);
    let mut found = Prepared {
        ratio: 1.0,
        relax_ratio: 1.0,
        ..f1
    };
    let mut arms = Vec::new();
    for (i, c) in one.constraints.iter().enumerate() {
        let mut reference = ContactConstraint::default();
        builder.build(
            &mut reference,
            i,
            &world.manifolds[i],
            &mut arms,
            &mut found,
        );
        if !c.anchoring.rolls() {
            let (c, r) = (format!("{c:?}"), format!("{reference:?}"));
            assert_eq!(c, r, "{what}: constraint {i} against the scalar reference");
        }
    }
    assert_eq!(found, f1, "{what}: findings against the scalar reference");
    let lanes = one.batches.batches.iter().flat_map(|b| b.contact);
    let batched = lanes.filter(|&c| c != crate::world::NO_CONTACT).count();
    for (split, keep_all) in [(true, true), (false, false), (true, false)] {
        let what = format!("{what} (split {split}, keep all {keep_all})");
        let (two, f2) = prepare(world, per_body, n, split, keep_all);
        assert_eq!(f1, f2, "{what}: findings");
        assert_eq!(one.keys, two.keys, "{what}: keys");
        let (arms1, arms2) = (&one.arms, &two.arms);
        assert_eq!(
            format!("{arms1:?}"),
            format!("{arms2:?}"),
            "{what}: rolling motions"
        );
        assert_eq!(one.lanes(), two.lanes(), "{what}: lanes");
        let bounce = world.manifolds[..n].iter().any(|m| m.restitution > 0.0);
        let kept = |i: usize| {
            keep_all || bounce || i < f1.fixed || two.batches.scalar.contains(&(i as u32))
        };
        for (i, (x, y)) in one.constraints.iter().zip(&two.constraints).enumerate() {
            if kept(i) {
                assert_eq!(format!("{x:?}"), format!("{y:?}"), "{what}: constraint {i}");
            }
        }
    }
    (f1.fixed, batched)
}

#[test]
fn constraints_built_in_halves_are_the_same_bits() {
    ComputeTaskPool::get_or_init(|| TaskPoolBuilder::new().num_threads(2).build());
    // The plain copy of the lanes' build, then (on a CPU with AVX2) the AVX one.
    crate::math::lanes::in_each_copy(compare_scenes);
}

fn compare_scenes() {
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
        let (fixed, batched) = compare(world, &per_body, n, file);
        if file.contains("pyramid") {
            assert!(
                batched * 2 >= n,
                "{file}: only {batched} of {n} contacts built in lanes"
            );
        }
        // The fixed contacts filling the whole first half: the second half's count on.
        let short = (fixed + 3).min(n);
        compare(world, &per_body, short, &format!("{file}, first {short}"));
        let (made, _) = prepare(world, &per_body, n, false, false);
        rolled += made.arms.len();
    }
    assert!(rolled > 0, "no scene had a rolling shape in contact");
}
