//! Every scene in assets/scenes parses, spawns headless (no asset server) and runs 600
//! steps without a body being rejected, sinking into a floor or wall beyond what its soft
//! contacts give, or the scene gaining energy (but from a motor); the box tower scene stands; a malformed file
//! names its line and column.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::TAU;
use tumble::prelude::*;
use tumble::scene::{BodyDesc, SceneDesc, SceneError, ShapeDesc};

fn scene_files() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".scene.ron"))
        .collect();
    files.sort();
    files
}

/// How far a body turned by `q` reaches from its centre along the unit vector `n`.
fn reach(shape: ShapeDesc, q: Quat, n: Vec3) -> f32 {
    match shape {
        ShapeDesc::Sphere(r) => r,
        ShapeDesc::Cuboid(h) => (0..3)
            .map(|i| h[i] * (q * Vec3::AXES[i]).dot(n).abs())
            .sum(),
        ShapeDesc::Rock(r, seed) => tumble::scene::rock_points(r, seed)
            .iter()
            .map(|p| (q * *p).dot(n))
            .fold(f32::MIN, f32::max),
        // Parry's support point along n (the cone's origin is midway up its axis).
        _ => {
            use parry3d::shape::SupportMap;
            let local = q.inverse() * n;
            match shape {
                ShapeDesc::Capsule(r, h) => parry3d::shape::Capsule::new_y(h, r)
                    .local_support_point(local)
                    .dot(local),
                ShapeDesc::Cylinder(r, h) => parry3d::shape::Cylinder::new(h, r)
                    .local_support_point(local)
                    .dot(local),
                ShapeDesc::Cone(r, h) => parry3d::shape::Cone::new(h, r)
                    .local_support_point(local)
                    .dot(local),
                _ => unreachable!(),
            }
        }
    }
}

/// A scene body's shape as parry's, for the pairs the hand-written overlaps don't cover.
fn parry_shape(shape: ShapeDesc) -> parry3d::shape::SharedShape {
    use parry3d::shape::SharedShape;
    match shape {
        ShapeDesc::Sphere(r) => SharedShape::ball(r),
        ShapeDesc::Cuboid(h) => SharedShape::cuboid(h.x, h.y, h.z),
        ShapeDesc::Capsule(r, h) => SharedShape::capsule_y(h, r),
        ShapeDesc::Cylinder(r, h) => SharedShape::cylinder(h, r),
        ShapeDesc::Cone(r, h) => SharedShape::cone(h, r),
        ShapeDesc::Rock(r, seed) => {
            SharedShape::convex_hull(&tumble::scene::rock_points(r, seed)).unwrap()
        }
    }
}

/// How deep two bodies overlap (the shortest push that separates them), 0 if they don't:
/// separating axes for two boxes, the closest point for a sphere and a box.
fn overlap(a: (ShapeDesc, Vec3, Quat), b: (ShapeDesc, Vec3, Quat)) -> f32 {
    let depth = match (a, b) {
        ((ShapeDesc::Sphere(ra), pa, _), (ShapeDesc::Sphere(rb), pb, _)) => {
            ra + rb - pa.distance(pb)
        }
        ((ShapeDesc::Cuboid(h), pc, q), (ShapeDesc::Sphere(r), ps, _))
        | ((ShapeDesc::Sphere(r), ps, _), (ShapeDesc::Cuboid(h), pc, q)) => {
            let local = q.inverse() * (ps - pc);
            let outside = (local.abs() - h).max(Vec3::ZERO).length();
            // Centre inside the box: its way out is through the nearest face.
            let inside = (h - local.abs()).min_element().max(0.0);
            r - outside + inside
        }
        ((ShapeDesc::Cuboid(ha), pa, qa), (ShapeDesc::Cuboid(hb), pb, qb)) => {
            let (ax, bx) = (Vec3::AXES.map(|v| qa * v), Vec3::AXES.map(|v| qb * v));
            let mut axes: Vec<Vec3> = ax.iter().chain(&bx).copied().collect();
            for u in ax {
                for v in bx {
                    let c = u.cross(v);
                    if c.length_squared() > 1e-6 {
                        axes.push(c.normalize());
                    }
                }
            }
            let t = pb - pa;
            axes.iter()
                .map(|&l| {
                    let ra: f32 = (0..3).map(|i| ha[i] * ax[i].dot(l).abs()).sum();
                    let rb: f32 = (0..3).map(|i| hb[i] * bx[i].dot(l).abs()).sum();
                    ra + rb - t.dot(l).abs()
                })
                .fold(f32::INFINITY, f32::min)
        }
        // Capsules, cylinders and cones: parry's contact depth.
        ((sa, pa, qa), (sb, pb, qb)) => {
            let pose = |p: Vec3, q: Quat| parry3d::math::Pose::from_parts(p, q.normalize());
            let (ga, gb) = (parry_shape(sa), parry_shape(sb));
            parry3d::query::contact(&pose(pa, qa), &*ga, &pose(pb, qb), &*gb, 0.0)
                .ok()
                .flatten()
                .map_or(0.0, |c| -c.dist)
        }
    };
    depth.max(0.0)
}

/// How deep a body at `p`, turned by `q`, is in each of the scene's planes: an infinite
/// plane is a half-space; a rectangle is a two-sided wall, counted where the centre is over
/// it. Positive is overlap.
fn depths<'a>(
    scene: &'a SceneDesc,
    d: &'a BodyDesc,
    p: Vec3,
    q: Quat,
) -> impl Iterator<Item = f32> + 'a {
    scene.planes.iter().filter_map(move |plane| {
        let turn = plane.rotation();
        let local = turn.inverse() * (p - plane.position);
        let distance = match plane.half_extents {
            None => local.y,
            Some(h) if local.x.abs() <= h.x && local.z.abs() <= h.y => local.y.abs(),
            Some(_) => return None,
        };
        // How far the body reaches toward the plane (from its side of a wall): not the
        // same both ways for a rock.
        let toward = if local.y >= 0.0 {
            -(turn * Vec3::Y)
        } else {
            turn * Vec3::Y
        };
        Some(reach(d.shape, q, toward) - distance)
    })
}

/// Kinetic plus potential energy of every body, less the work its constant force (a
/// scene's walker) has done since the start, J (f64 sums: 2,000 bodies).
fn energy(app: &App, bodies: &[Entity], descs: &[BodyDesc]) -> f64 {
    bodies
        .iter()
        .zip(descs)
        .map(|(&b, d)| {
            let (m, v, q) = (d.mass(), vel(app, b), rot(app, b));
            let shape = d.collider().shape;
            let inertia = shape.principal_inertia(m);
            // In the principal frame (turned for a hull), at the centre of mass.
            let w = (q * shape.principal_frame()).inverse() * v.angular;
            let centre = pos(app, b) + q * shape.center_of_mass();
            let work = d.force.dot(pos(app, b) - d.position);
            let e =
                0.5 * m * v.linear.length_squared() + 0.5 * w.dot(inertia * w) + m * G * centre.y
                    - work;
            e as f64
        })
        .sum()
}

#[test]
fn every_scene_runs_600_steps_without_sinking_or_gaining_energy() {
    let files = scene_files();
    assert!(files.len() >= 9, "{files:?}");
    // A static contact runs at ≥ 60 Hz (a quarter of the substep rate at ≥ 4 substeps;
    // src/step/5_solve/stiffness.rs), and sinks by L·g/(m·ω²) under a load of L kg on a
    // body of mass m. No load exceeds the whole scene's mass M, and a box face's corner rows
    // add at most 3/4 to that sag (their angular terms: ≤ 7/m per corner against the 4/m
    // that a load shared by four corners needs), so at rest a body of mass m is no deeper in
    // any plane than 2·(M/m)·g/ω²: 1.4 mm for a tower cube, 2.9 cm for a 1 kg box under the
    // mass-ratio scene's 211 kg; loose only in the big piles (0.28 m in the 2,000 kg rain).
    let omega = TAU * 60.0;
    for file in files {
        let name = file.display().to_string();
        let scene = SceneDesc::load(&file).unwrap_or_else(|e| panic!("{e}"));
        let descs = scene.expanded_bodies();
        let mut app = app_with_sleeping();
        let bodies = scene.spawn_into(app.world_mut());
        assert!(!bodies.is_empty(), "{name}");
        assert_eq!(bodies.len(), descs.len(), "{name}");
        let masses: Vec<f32> = descs.iter().map(|d| d.mass()).collect();
        let total: f32 = masses.iter().sum();

        // Nothing adds energy: gravity is conservative, contacts are over-damped springs
        // (ζ = 10) with e ≤ 1. Only what starts buried is pushed out: that lifts a body by
        // at most its depth d, at no more than max_push_out: E ≤ E0 + Σ (m·g·d + ½·m·v²)
        // over the bodies buried in a plane or another body at spawn, plus f32 round-off of
        // the state (1e-6·E0).
        let push = SolverSettings::default().max_push_out;
        let start: Vec<(ShapeDesc, Vec3, Quat)> = bodies
            .iter()
            .zip(&descs)
            .map(|(&b, d)| (d.shape, pos(&app, b), rot(&app, b)))
            .collect();
        let mut depth: Vec<f32> = descs
            .iter()
            .zip(&start)
            .map(|(d, &(_, p, q))| depths(&scene, d, p, q).fold(0.0, f32::max))
            .collect();
        for i in 0..start.len() {
            for j in i + 1..start.len() {
                let d = overlap(start[i], start[j]);
                if d > 0.0 {
                    depth[i] = depth[i].max(d);
                    depth[j] = depth[j].max(d);
                }
            }
        }
        let buried: f64 = depth
            .iter()
            .zip(&masses)
            .filter(|&(&d, _)| d > 0.0)
            .map(|(&d, &m)| (m * G * d + 0.5 * m * push * push) as f64)
            .fold(0.0, |a, b| a + b);
        let e0 = energy(&app, &bodies, &descs);
        // Restitution reverses an approach as fast as free motion made it in the step
        // (see `iterate::solve`); a pendulum hitting a pendulum (the cradle) was also
        // sped up along the normal by gravity within that step, so each e = 1 impact may
        // return up to m·v·g·sin θ·dt more (15 mJ at the cradle's 2.96 m/s and 40°;
        // measured about 4 mJ). Only a scene with jointed bodies that bounce may gain so,
        // up to 1e-3 of its energy.
        let bounces = descs.iter().any(|d| d.restitution.is_some_and(|e| e > 0.0));
        let pendulums = if !scene.joints.is_empty() && bounces {
            1e-3 * e0.abs()
        } else {
            0.0
        };
        let allowed = e0 + buried + 1e-6 * e0.abs() + pendulums;
        // A motor turning at a speed (the windmill's) is a source: its work is not
        // counted, so its scene is held only to the rest (a brake at 0 rad/s is not).
        let driven = scene
            .joints
            .iter()
            .flat_map(|g| g.expand())
            .any(|j| j.motor.is_some_and(|(speed, _)| speed != 0.0));
        for k in 1..=600 {
            step(&mut app, 1);
            let e = energy(&app, &bodies, &descs);
            assert!(
                driven || e <= allowed,
                "{name}: step {k}: energy {e} J, above the start's {e0} J + {buried} J buried"
            );
        }

        for ((&b, d), &m) in bodies.iter().zip(&descs).zip(&masses) {
            let max_depth = 2.0 * (total / m) * G / (omega * omega);
            // A body that goes non-finite is frozen and tagged, not left NaN.
            assert!(
                app.world().get::<PhysicsRejected>(b).is_none(),
                "{name}: body {b} rejected"
            );
            let (p, q) = (pos(&app, b), rot(&app, b));
            assert!(p.y > -1.0, "{name}: body {b} fell through the floor: {p}");
            let deepest = depths(&scene, d, p, q).fold(f32::MIN, f32::max);
            assert!(
                deepest <= max_depth,
                "{name}: body {b} at {p} is {deepest} m into a plane (bound {max_depth} m)"
            );
        }
    }
}

#[test]
fn box_tower_scene_stands() {
    let scene = SceneDesc::load("assets/scenes/2_box_tower.scene.ron").unwrap();
    let mut app = app();
    let bodies = scene.spawn_into(app.world_mut());
    let top0 = pos(&app, bodies[9]);
    step(&mut app, 600);
    let moved = pos(&app, bodies[9]) - top0;
    assert!(
        moved.xz().length() < 0.02 && moved.y.abs() < 0.05,
        "top moved {moved}"
    );
}

#[test]
fn malformed_scene_names_line_and_column() {
    let text =
        "(\n    name: \"broken\",\n    bodies: [Single((shape: Sphere(0.5), mass: Some(1.0)),\n";
    match SceneDesc::from_ron(text, "broken.scene.ron") {
        Err(SceneError::Parse { path, line, .. }) => {
            assert_eq!(path, "broken.scene.ron");
            assert!(line >= 3, "line {line}");
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
    let unknown = "(name: \"x\", gravity_typo: 1.0)";
    let err = SceneDesc::from_ron(unknown, "typo.scene.ron")
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("typo.scene.ron:1:"), "{err}");
}
