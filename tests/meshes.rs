//! Convex hulls, triangle meshes and heightfields (parry3d) against analytic answers: a
//! hull of a cube rests and slides like the box; a hull whose principal axes lie askew
//! keeps its angular momentum; a ball rolls on a mesh floor at the rolling speed, a box
//! slides over its internal edges without a bump (it jumps 13 cm without edge fixing), stays inside a mesh bowl, rests on a heightfield and
//! rolls down a sloped one at (5/7)·g·sinθ; a dynamic mesh is refused by name.

mod common;
use bevy::prelude::*;
use common::*;
use std::f32::consts::PI;
use tumble::prelude::*;

/// The eight corners of a box of half extents `h`, turned by `rot`, around `centre`.
fn box_corners(h: Vec3, rot: Quat, centre: Vec3) -> Vec<Vec3> {
    (0..8)
        .map(|i| {
            let s = Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            );
            centre + rot * (s * h)
        })
        .collect()
}

fn dynamic(app: &mut App, collider: Collider, p: Vec3) -> Entity {
    app.world_mut()
        .spawn((RigidBody::Dynamic, collider, Transform::from_translation(p)))
        .id()
}

fn fixed(app: &mut App, collider: Collider, p: Vec3) -> Entity {
    app.world_mut()
        .spawn((collider, Transform::from_translation(p)))
        .id()
}

/// A square floor of two triangles (an internal edge along its diagonal), facing up.
fn floor_mesh(half: f32) -> Collider {
    let v = vec![
        Vec3::new(-half, 0.0, -half),
        Vec3::new(half, 0.0, -half),
        Vec3::new(half, 0.0, half),
        Vec3::new(-half, 0.0, half),
    ];
    Collider::trimesh(v, vec![[0, 2, 1], [0, 3, 2]]).unwrap()
}

/// Soft contacts sag by design, at most `max_sag` of the smaller size.
fn sag(size: f32) -> f32 {
    SolverSettings::default().max_sag * size
}

#[test]
fn a_hull_of_a_cube_rests_and_slides_like_the_box() {
    let h = Vec3::new(0.4, 0.25, 0.3);
    let hull = Collider::convex_hull(&box_corners(h, Quat::IDENTITY, Vec3::ZERO)).unwrap();
    let v0 = 3.0;
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
        let a = dynamic(&mut app, hull.clone(), Vec3::new(0.0, h.y, 0.0));
        let b = dynamic(
            &mut app,
            Collider::cuboid(h.x, h.y, h.z),
            Vec3::new(0.0, h.y, 3.0),
        );
        step(&mut app, 30);
        let what = format!("{pacing:?}");
        assert_near(
            pos(&app, a).y,
            h.y,
            sag(2.0 * h.y),
            &format!("{what}: hull at rest"),
        );
        assert_near(
            pos(&app, a).y,
            pos(&app, b).y,
            1e-4,
            &format!("{what}: as high as the box"),
        );
        // Both pushed along x at 3 m/s: each stops after v²/(2μg), μ = 0.5.
        for e in [a, b] {
            app.world_mut().get_mut::<Velocity>(e).unwrap().linear = Vec3::X * v0;
        }
        step(&mut app, 90);
        let stop = v0 * v0 / (2.0 * 0.5 * G);
        // Semi-implicit Euler's substep error and the first step's start: ±1 cm.
        assert_near(pos(&app, a).x, stop, 0.01, &format!("{what}: hull's slide"));
        assert_near(
            pos(&app, a).x,
            pos(&app, b).x,
            1e-3,
            &format!("{what}: as far as the box"),
        );
        assert!(vel(&app, a).linear.length() < 1e-3, "{what}: stopped");
        assert!(tilt(&app, a) < 1e-3, "{what}: flat");
    }
}

/// Free rotation conserves angular momentum L = R·I·Rᵀ·ω. A hull of a long box turned
/// 30° off its own axes spins about a tilted axis: the solver must work in the hull's
/// principal frame, or L drifts.
#[test]
fn a_hull_with_askew_axes_keeps_its_angular_momentum() {
    let h = Vec3::new(0.6, 0.1, 0.25);
    let askew = Quat::from_euler(EulerRot::XYZ, 0.5, 0.3, 0.2);
    let offset = Vec3::new(0.3, -0.1, 0.2);
    let hull = Collider::convex_hull(&box_corners(h, askew, offset)).unwrap();
    let mut app = app_without_gravity();
    let e = dynamic(&mut app, hull, Vec3::ZERO);
    app.world_mut().entity_mut(e).insert(Velocity {
        linear: Vec3::ZERO,
        angular: Vec3::new(0.3, 2.0, 0.5),
    });
    step(&mut app, 1);
    // The box's own inertia, at its own density (water), turned by `askew`.
    let mass = 1000.0 * 8.0 * h.x * h.y * h.z;
    let s = h * 2.0;
    let moments = Vec3::new(
        s.y * s.y + s.z * s.z,
        s.x * s.x + s.z * s.z,
        s.x * s.x + s.y * s.y,
    ) * (mass / 12.0);
    let momentum = |app: &App| {
        let r = Mat3::from_quat(rot(app, e) * askew);
        r * Mat3::from_diagonal(moments) * r.transpose() * vel(app, e).angular
    };
    let l0 = momentum(&app);
    // The centre of mass (the box's centre, `offset` from the origin) does not move.
    let centre = |app: &App| pos(app, e) + rot(app, e) * offset;
    let c0 = centre(&app);
    step(&mut app, 300);
    let l1 = momentum(&app);
    assert!((l1 - l0).length() < 2e-3 * l0.length(), "L {l0} → {l1}");
    assert_near_vec(centre(&app), c0, 1e-4, "centre of mass at rest");
}

/// A ball sliding across a mesh floor (over the diagonal between its two triangles)
/// stays on it and reaches the rolling speed (5/7)·v0, as on a plane.
#[test]
fn a_ball_rolls_across_a_mesh_floor_without_a_bump() {
    let r = 0.2;
    for pacing in Pacing::GAME {
        let mut app = paced_app(pacing, false);
        fixed(&mut app, floor_mesh(10.0), Vec3::ZERO);
        let b = ball(
            &mut app,
            r,
            1.0,
            Vec3::new(-4.0, r, -3.0),
            Vec3::new(2.0, 0.0, 1.5),
        );
        let mut highest: f32 = 0.0;
        for _ in 0..150 {
            step(&mut app, 1);
            highest = highest.max(pos(&app, b).y);
        }
        let what = format!("{pacing:?}");
        assert!(highest < r + 1e-3, "{what}: bumped up to {highest}");
        let v0 = Vec3::new(2.0, 0.0, 1.5).length();
        assert_near(
            vel(&app, b).linear.length(),
            5.0 / 7.0 * v0,
            0.01 * v0,
            &format!("{what}: rolling speed"),
        );
        assert_near(
            pos(&app, b).y,
            r,
            sag(2.0 * r),
            &format!("{what}: on the floor"),
        );
    }
}

/// A frictionless box sliding over a mesh floor's internal edges (a floor of many
/// triangles) keeps flat and level: without the mesh's edge fixing, the triangle edges
/// ahead of it push back on its leading face.
#[test]
fn a_box_slides_over_internal_edges_flat() {
    let n = 8;
    let (mut v, mut t) = (vec![], vec![]);
    for i in 0..=n {
        for j in 0..=n {
            v.push(Vec3::new(i as f32 - 4.0, 0.0, j as f32 - 4.0) * 2.0);
        }
    }
    let at = |i: u32, j: u32| i * (n + 1) + j;
    for i in 0..n {
        for j in 0..n {
            t.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    let mut app = app();
    fixed(&mut app, Collider::trimesh(v, t).unwrap(), Vec3::ZERO);
    let h = 0.2;
    let b = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(h, h, h),
            Friction(0.0),
            Transform::from_xyz(-6.0, h, -5.0),
            Velocity::linear(Vec3::new(4.0, 0.0, 3.0)),
        ))
        .id();
    let (mut highest, mut tilted): (f32, f32) = (0.0, 0.0);
    for _ in 0..150 {
        step(&mut app, 1);
        highest = highest.max(pos(&app, b).y);
        tilted = tilted.max(tilt(&app, b));
    }
    assert!(highest < h + 1e-3, "bumped up to {highest}");
    assert!(tilted < 1e-3, "tilted {tilted}");
    assert_near(
        vel(&app, b).linear.length(),
        5.0,
        0.01,
        "frictionless: the speed kept",
    );
}

/// A bowl: a spherical cap of radius R meshed in rings, facing in. A ball let go on its
/// side rolls back and forth and never leaves it (its energy only falls).
#[test]
fn a_ball_stays_inside_a_mesh_bowl() {
    let (big, rings, sectors) = (3.0f32, 12, 24);
    let mut v = vec![Vec3::new(0.0, 0.0, 0.0)];
    for i in 1..=rings {
        let polar = (i as f32 / rings as f32) * 70f32.to_radians();
        for j in 0..sectors {
            let az = j as f32 / sectors as f32 * 2.0 * PI;
            v.push(
                Vec3::new(
                    polar.sin() * az.cos(),
                    1.0 - polar.cos(),
                    polar.sin() * az.sin(),
                ) * big,
            );
        }
    }
    let mut t = vec![];
    let at = |i: u32, j: u32| 1 + (i - 1) * sectors + j % sectors;
    for j in 0..sectors {
        t.push([0, at(1, j + 1), at(1, j)]);
    }
    for i in 1..rings {
        for j in 0..sectors {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
    }
    let bowl = Collider::trimesh(v, t).unwrap();
    let r = 0.25;
    let mut app = app();
    fixed(&mut app, bowl, Vec3::ZERO);
    // 45° up the side, on the surface: centre at distance R − r from the sphere's centre.
    let centre = Vec3::Y * big;
    let start =
        centre + (Vec3::new(45f32.to_radians().sin(), -45f32.to_radians().cos(), 0.0)) * (big - r);
    let b = ball(
        &mut app,
        r,
        1.0,
        start + Vec3::Y * 0.01,
        Vec3::new(0.0, 0.0, 1.0),
    );
    let energy = |app: &App| {
        let v = vel(app, b);
        G * pos(app, b).y
            + 0.5 * v.linear.length_squared()
            + 0.5 * 0.4 * r * r * v.angular.length_squared()
    };
    let e0 = energy(&app);
    for _ in 0..600 {
        step(&mut app, 1);
        let d = pos(&app, b).distance(centre);
        // Inside the sphere, never through the mesh (a facet's chord sags 2.5 cm below it).
        assert!(
            d < big - r + 1e-3 && d > big - r - 0.05,
            "left the bowl: {d}"
        );
        assert!(
            energy(&app) < e0 + 0.01,
            "gained energy: {} > {e0}",
            energy(&app)
        );
    }
}

/// A heightfield of constant height 0.5 m holds a ball at 0.5 + r; one rising along x
/// at slope tanθ makes a ball roll down at (5/7)·g·sinθ.
#[test]
fn balls_rest_on_a_heightfield_and_roll_down_its_slope() {
    let r = 0.3;
    let mut app = app();
    let flat = vec![vec![0.5; 9]; 9];
    fixed(
        &mut app,
        Collider::heightfield(&flat, Vec2::new(8.0, 8.0)).unwrap(),
        Vec3::ZERO,
    );
    let theta = 10f32.to_radians();
    // Rows along x, from −10 to 10 m: height (x + 10)·tanθ.
    let slope: Vec<Vec<f32>> = (0..21).map(|i| vec![i as f32 * theta.tan(); 5]).collect();
    fixed(
        &mut app,
        Collider::heightfield(&slope, Vec2::new(20.0, 8.0)).unwrap(),
        Vec3::new(0.0, 0.0, 20.0),
    );
    let resting = ball(
        &mut app,
        r,
        1.0,
        Vec3::new(1.0, 0.5 + r + 0.01, 0.0),
        Vec3::ZERO,
    );
    let normal = Vec3::new(-theta.sin(), theta.cos(), 0.0);
    let on_slope = |x: f32| Vec3::new(x, (x + 10.0) * theta.tan(), 20.0) + normal * r;
    let rolling = ball(&mut app, r, 1.0, on_slope(5.0), Vec3::ZERO);
    step(&mut app, 10);
    let down = Vec3::new(-theta.cos(), -theta.sin(), 0.0);
    let v0 = vel(&app, rolling).linear.dot(down);
    step(&mut app, 60);
    assert_near(
        pos(&app, resting).y,
        0.5 + r,
        sag(2.0 * r),
        "resting on the flat field",
    );
    let a = (vel(&app, rolling).linear.dot(down) - v0) / 1.0;
    let expected = 5.0 / 7.0 * G * theta.sin();
    assert_near(a, expected, 0.01 * expected, "rolling down the field");
    let p = pos(&app, rolling);
    assert_near(
        (p - on_slope(p.x) + normal * r).dot(normal),
        r,
        sag(2.0 * r),
        "on the slope",
    );
}

#[test]
fn a_dynamic_mesh_is_refused_by_name() {
    let mut app = app();
    let e = dynamic(&mut app, floor_mesh(1.0), Vec3::ZERO);
    let field = dynamic(
        &mut app,
        Collider::heightfield(&vec![vec![0.0; 2]; 2], Vec2::ONE).unwrap(),
        Vec3::X * 5.0,
    );
    step(&mut app, 1);
    assert_eq!(rejected_field(&app, e), Some("Collider"));
    assert_eq!(rejected_field(&app, field), Some("Collider"));
    // A kinematic mesh is fine: a moving platform.
    let platform = app
        .world_mut()
        .spawn((
            RigidBody::Kinematic,
            floor_mesh(1.0),
            Transform::from_xyz(0.0, 0.0, 10.0),
            Velocity::linear(Vec3::X),
        ))
        .id();
    step(&mut app, 10);
    assert_eq!(rejected_field(&app, platform), None);
    assert!(pos(&app, platform).x > 0.1);
}

/// Rays meet a hull, a mesh and a heightfield where their geometry is.
#[test]
fn rays_hit_hulls_meshes_and_heightfields() {
    let mut app = app();
    let hull =
        Collider::convex_hull(&box_corners(Vec3::splat(0.5), Quat::IDENTITY, Vec3::ZERO)).unwrap();
    let h = fixed(&mut app, hull, Vec3::new(0.0, 1.0, 0.0));
    let m = fixed(&mut app, floor_mesh(1.0), Vec3::new(5.0, 0.3, 0.0));
    let heights: Vec<Vec<f32>> = (0..5).map(|i| vec![i as f32 * 0.25; 5]).collect();
    let f = fixed(
        &mut app,
        Collider::heightfield(&heights, Vec2::new(4.0, 4.0)).unwrap(),
        Vec3::new(10.0, 0.0, 0.0),
    );
    step(&mut app, 1);
    let filter = SpatialQueryFilter::default();
    let down = |app: &mut App, x: f32| {
        query(app, |q| {
            q.cast_ray(Vec3::new(x, 10.0, 0.1), Dir3::NEG_Y, 100.0, true, &filter)
        })
        .unwrap()
    };
    let hit = down(&mut app, 0.0);
    assert_eq!(hit.entity, h);
    assert_near(hit.distance, 8.5, 1e-5, "hull top");
    let hit = down(&mut app, 5.2);
    assert_eq!(hit.entity, m);
    assert_near(hit.distance, 9.7, 1e-5, "mesh floor");
    assert_near_vec(hit.normal, Vec3::Y, 1e-5, "mesh normal");
    // The field rises 0.25 m per metre along x from x = 8: at x = 10.5, 0.625 m.
    let hit = down(&mut app, 10.5);
    assert_eq!(hit.entity, f);
    assert_near(hit.distance, 10.0 - 0.625, 1e-5, "heightfield");
    assert_near_vec(
        hit.normal,
        Vec3::new(-0.25, 1.0, 0.0).normalize(),
        1e-5,
        "slope normal",
    );
}
