//! Boxes at rest: a flat landing, a tall stack, a 385-cube pyramid, and a heavy box on a
//! light one. Stability tests run with the default solver settings.
//!
//! Each resting height is checked on both sides against the soft contacts' sag
//! (src/step/5_solve/stiffness.rs, softness.rs): a contact carrying L kg sinks by
//! s = L·g/(m_eff·ω²), m_eff the pair's reduced mass (the body's own mass against the
//! ground). Between full faces of unit cubes each corner row adds 6·(rx² + rz²)/m = 3/m of
//! angular inverse mass per body, which exactly cancels the load's four-way split, so the
//! face as a whole sinks by L·g/(m_eff·ω²). ω = 2π·min(f_base·√r, f_max): f_base = 30 Hz
//! (60 Hz against the ground), r = max(heavy, L)/light, f_max a quarter of the substep rate.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::TAU;
use tumble::prelude::*;

/// The sag of a contact carrying `load` kg on top of `lower` (None: the static ground),
/// its upper body of mass `upper`, at `substeps` substeps per step.
fn contact_sag(load: f32, lower: Option<f32>, upper: f32, substeps: u32) -> f32 {
    let f_max = 0.25 * substeps as f32 / H;
    let (m_eff, light, heavy, base) = match lower {
        None => (upper, upper, upper, 60.0),
        Some(m) => (m * upper / (m + upper), m.min(upper), m.max(upper), 30.0),
    };
    let r = (heavy.max(load) / light).max(1.0);
    let omega = TAU * (base * r.sqrt()).min(f_max);
    load * G / (m_eff * omega * omega)
}

/// The stiffest contact's angular frequency at `substeps` (a quarter of the substep rate).
fn omega_max(substeps: u32) -> f32 {
    TAU * 0.25 * substeps as f32 / H
}

/// Relative tolerance on a sag when the upper box sits up to `shift` m off its support:
/// the corner arms shorten from 0.5 to 0.5 − shift, lowering each row's inverse mass
/// 2 + 6·Σ(rx² + rz²) = 8 (two unit cubes) by at most 12·(0.5² − (0.5 − shift)²)/8.
fn arm_tol(shift: f32) -> f32 {
    12.0 * (0.25 - (0.5 - shift).powi(2)) / 8.0
}

/// How far a body's local +Y leans from world +Y: sin of the tilt. (`tilt` goes through
/// acos, which cannot resolve angles below ~3e-4 rad in f32.)
fn lean(app: &App, e: Entity) -> f32 {
    (rot(app, e) * Vec3::Y).xz().length()
}

/// At rest within ±`tol` of its height: a body held there by contact springs no stiffer
/// than `omega` moves at most omega·tol, and turns at most omega·tol / 0.5 m (its corners).
#[track_caller]
fn assert_resting(app: &App, e: Entity, omega: f32, tol: f32, what: &str) {
    let v = vel(app, e);
    assert!(
        v.linear.length() <= omega * tol && v.angular.length() <= omega * tol / 0.5,
        "{what}: still moving, v = {} m/s, w = {} rad/s (bounds {}, {})",
        v.linear,
        v.angular,
        omega * tol,
        omega * tol / 0.5
    );
}

#[test]
fn box_dropped_flat_lands_flat_without_drifting() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 4.0, 0.0));
    app.world_mut().entity_mut(b).insert(Friction(0.3));
    step(&mut app, 90);
    let p = pos(&app, b);
    // s = g/ω² = 0.069 mm. It lands at 0.85 s; 0.65 s later the over-damped contact
    // (ζ = 10, slow mode ω/2ζ ≈ 19/s) has relaxed to e^-12 of its transient, and only f32
    // round-off (6e-8 m at 0.5 m) is left: a tenth of the sag is ample.
    let s = contact_sag(1.0, None, 1.0, 4);
    let tol = 0.1 * s;
    assert_near(p.y, 0.5 - s, tol, "resting height");
    // Every corner is between 0 and s + tol below its nominal height: across the 1 m base
    // that is a lean of at most (s + tol)/1 m = 7.6e-5 rad.
    assert!(lean(&app, b) <= s + tol, "lean {}", lean(&app, b));
    assert_resting(&app, b, omega_max(4), tol, "flat box");
    assert!(p.x.abs() < 0.02 && p.z.abs() < 0.02, "drifted to {p}");
}

#[test]
fn ten_box_stack_stands_for_ten_seconds() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let boxes: Vec<_> = (0..10)
        .map(|i| {
            let dx = if i % 2 == 0 { 0.01 } else { -0.01 };
            cuboid(
                &mut app,
                Vec3::splat(0.5),
                1.0,
                Vec3::new(dx, 0.5 + i as f32, 0.0),
            )
        })
        .collect();
    let top0 = pos(&app, boxes[9]);
    step(&mut app, 600);
    assert_eq!(
        app.world().resource::<PhysicsWorld>().substeps(),
        4,
        "unit cubes ask for no extra substeps"
    );
    let top = pos(&app, boxes[9]);
    assert!(
        (top - top0).xz().length() < 0.02,
        "top moved {}",
        (top - top0).xz().length()
    );
    // Box i sinks by the sags of every contact below it: the ground carries 10 kg, the
    // contact under box j ≥ 1 carries 10 − j kg. Total under the top box: 7.7 mm.
    // Tolerance: neighbours sit 2 cm apart, plus up to the 2 cm drift allowed above, so
    // corner arms shorten by up to 4 cm: 5.8 % of the sag.
    let tol = arm_tol(0.04);
    let mut drop = 0.0;
    for (i, &b) in boxes.iter().enumerate() {
        let load = (10 - i) as f32;
        drop += if i == 0 {
            contact_sag(load, None, 1.0, 4)
        } else {
            contact_sag(load, Some(1.0), 1.0, 4)
        };
        let p = pos(&app, b);
        assert_near(
            p.y,
            0.5 + i as f32 - drop,
            tol * drop,
            &format!("box {i} height"),
        );
        // Each contact below can tilt box i by at most its sag across the ≥ 0.96 m wide
        // contact patch.
        let max_lean = (1.0 + tol) * drop / 0.96;
        assert!(
            lean(&app, b) <= max_lean,
            "box {i} leans {} > {max_lean}",
            lean(&app, b)
        );
        assert_resting(&app, b, omega_max(4), tol * drop, &format!("box {i}"));
    }
}

#[test]
fn pyramid_of_385_cubes_holds_for_ten_seconds() {
    let mut app = app();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    // cubes[level][i][k]; level n = 10 − level cubes a side, each resting on four below.
    let mut cubes = Vec::new();
    for level in 0..10 {
        let n = 10 - level;
        let mut layer = vec![vec![(Entity::PLACEHOLDER, Vec3::ZERO); n]; n];
        for (i, row) in layer.iter_mut().enumerate() {
            for (k, cell) in row.iter_mut().enumerate() {
                let x = i as f32 - (n - 1) as f32 * 0.5;
                let z = k as f32 - (n - 1) as f32 * 0.5;
                let p = Vec3::new(x, 0.5 + level as f32, z);
                *cell = (cuboid(&mut app, Vec3::splat(0.5), 1.0, p), p);
            }
        }
        cubes.push(layer);
    }
    assert_eq!(cubes.iter().map(|l| l.len() * l.len()).sum::<usize>(), 385);
    step(&mut app, 600);

    // Expected sinking, equal-share model: each cube passes its load (itself plus a quarter
    // of each cube on it) in equal quarters to the four below. A ground contact is a full
    // face: L·g/ω². A cube on four others touches each with a quarter face whose corner arms
    // are 0 to 0.5 m instead of 0.5 m, so its rows' inverse masses are 2, 5, 5, 8 instead
    // of 8: its sag lies between ¼ and 1 times the full-face L·g/(m_eff·ω²). `hi` and `lo`
    // carry those two bounds up the pyramid.
    let mut load: Vec<Vec<Vec<f32>>> = (0..10).map(|l| vec![vec![1.0; 10 - l]; 10 - l]).collect();
    for level in (0..9).rev() {
        for i in 0..10 - level - 1 {
            for k in 0..10 - level - 1 {
                let share = load[level + 1][i][k] / 4.0;
                for (a, c) in [(i, k), (i + 1, k), (i, k + 1), (i + 1, k + 1)] {
                    load[level][a][c] += share;
                }
            }
        }
    }
    let mut hi = load.clone();
    let mut lo = load.clone();
    for level in 0..10 {
        for i in 0..10 - level {
            for k in 0..10 - level {
                if level == 0 {
                    let s = contact_sag(load[0][i][k], None, 1.0, 4);
                    (hi[0][i][k], lo[0][i][k]) = (s, s);
                    continue;
                }
                let share = load[level][i][k] / 4.0;
                let s = contact_sag(share, Some(1.0), 1.0, 4);
                let below = [(i, k), (i + 1, k), (i, k + 1), (i + 1, k + 1)];
                let mean = |d: &Vec<Vec<Vec<f32>>>| {
                    below.iter().map(|&(a, c)| d[level - 1][a][c]).sum::<f32>() / 4.0
                };
                hi[level][i][k] = mean(&hi) + s;
                lo[level][i][k] = mean(&lo) + 0.25 * s;
            }
        }
    }
    let hi_max = hi.iter().flatten().flatten().fold(0.0f32, |a, &b| a.max(b));
    let s1 = contact_sag(1.0, None, 1.0, 4);
    let omega = omega_max(4);
    for (level, layer) in cubes.iter().enumerate() {
        let drops: Vec<f32> = layer
            .iter()
            .flatten()
            .map(|&(e, p0)| p0.y - pos(&app, e).y)
            .collect();
        let mean = drops.iter().sum::<f32>() / drops.len() as f32;
        let avg = |d: &Vec<Vec<f32>>| d.iter().flatten().sum::<f32>() / drops.len() as f32;
        if level == 0 {
            // The ground carries all 385 cubes through full faces, so however the load is
            // shared the ground cubes sink by 385·g/ω² in total: 3.85·g/ω² on average.
            // Tolerance: 16 f32 ulps at 0.5 m.
            assert_near(mean, 3.85 * s1, 16.0 * 6e-8, "ground layer's mean sinking");
        } else {
            let (lo, hi) = (avg(&lo[level]), avg(&hi[level]));
            assert!(
                (lo..=hi).contains(&mean),
                "level {level} sank {mean} m on average, outside [{lo}, {hi}]"
            );
        }
        for (&(e, p0), &d) in layer.iter().flatten().zip(&drops) {
            // Every cube sinks at least by the sag of a ground contact carrying one cube,
            // and at most by the most any cube does in the full-face model (the top's
            // 3.75 mm).
            assert!(
                (s1 - 1e-6..=hi_max).contains(&d),
                "cube at {p0} sank {d} m, outside [{s1}, {hi_max}]"
            );
            // Its base leans at most that much across 1 m, and every base below it too, so
            // it slides at most its height times that lean.
            assert!(
                lean(&app, e) <= hi_max,
                "cube at {p0} leans {}",
                lean(&app, e)
            );
            let slid = (pos(&app, e) - p0).xz().length();
            assert!(slid <= p0.y * hi_max, "cube at {p0} slid {slid} m");
            // At rest: no faster than an oscillation as deep as the smallest sag, ω·g/ω².
            assert_resting(&app, e, omega, s1, &format!("cube at {p0}"));
        }
    }
}

#[test]
fn heavy_box_on_light_box_holds_without_sinking_or_walking() {
    // Sleeping off: the test reads the equilibrium sag and the substeps the resting pair
    // asks for; it settles slower than the sleep time, and a sleeper keeps no contacts.
    let mut app = app_without_sleeping();
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let small = cuboid(&mut app, Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.5, 0.0));
    let big = cuboid(&mut app, Vec3::splat(0.5), 100.0, Vec3::new(0.0, 1.5, 0.0));
    step(&mut app, 600);
    // The 100:1 contact asks for the stiffness that holds its sag to max_sag of a 1 m box:
    // f = √(100·g/(0.002·1 m))/2π = 111.5 Hz, beyond a quarter of 240 Hz, so the step takes
    // ⌈4·f·dt⌉ = 8 substeps and contacts run at up to 120 Hz.
    let max_sag = SolverSettings::default().max_sag;
    let needed = (100.0 * G / (max_sag * 1.0)).sqrt() / TAU;
    let n = (4.0 * needed * H).ceil() as u32;
    assert_eq!(app.world().resource::<PhysicsWorld>().substeps(), n);
    // Ground under 101 kg: 1.74 mm; the 100 kg box on the 1 kg one: 1.74 mm more.
    // Tolerance: the 1 cm walk allowed below shortens corner arms by up to 1 cm: 1.5 %.
    let s_ground = contact_sag(101.0, None, 1.0, n);
    let s_pair = contact_sag(100.0, Some(1.0), 100.0, n);
    let tol = arm_tol(0.01);
    let (ps, pb) = (pos(&app, small), pos(&app, big));
    assert_near(ps.y, 0.5 - s_ground, tol * s_ground, "small box height");
    assert_near(
        pb.y - ps.y,
        1.0 - s_pair,
        tol * s_pair,
        "big box above small box",
    );
    assert!(
        pb.xz().length() < 0.01,
        "top box walked {}",
        pb.xz().length()
    );
    for (b, drop, what) in [
        (small, s_ground, "small box"),
        (big, s_ground + s_pair, "big box"),
    ] {
        assert!(
            lean(&app, b) <= (1.0 + tol) * drop,
            "{what} leans {}",
            lean(&app, b)
        );
        assert_resting(&app, b, omega_max(n), tol * drop, what);
    }
}
