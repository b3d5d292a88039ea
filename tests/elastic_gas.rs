//! 200 elastic, frictionless balls bouncing in a closed 10 m box without gravity keep
//! their kinetic energy: every collision is elastic, so only the solver's error may take
//! any. A fixed restitution threshold of 1 m/s made every slower collision inelastic,
//! and the gas kept only half its energy over 20 s; the threshold now follows what a
//! resting contact can reach (gravity's speed over a step), which is nothing in zero g.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn elastic_gas_keeps_nine_tenths_of_its_energy_over_20_s() {
    let mut app = app_with_sleeping();
    app.insert_resource(Gravity(Vec3::ZERO));
    closed_room(&mut app, 5.0);
    let mut rng = Rng::new(7);
    // 200 cells of a 6×6×6 grid 1.5 m apart, each ball sent off at up to 4 m/s a component.
    let balls: Vec<Entity> = (0..200)
        .map(|i| {
            let cell = Vec3::new((i / 36) as f32, (i / 6 % 6) as f32, (i % 6) as f32);
            let v = rng.vec3(Vec3::splat(-4.0), Vec3::splat(4.0));
            let b = ball(&mut app, 0.25, 1.0, cell * 1.5 - Vec3::splat(3.75), v);
            app.world_mut()
                .entity_mut(b)
                .insert((Restitution(1.0), Friction(0.0)));
            b
        })
        .collect();
    let energy = |app: &App| -> f32 {
        let e = balls
            .iter()
            .map(|&b| 0.5 * vel(app, b).linear.length_squared());
        e.sum()
    };
    step(&mut app, 1);
    let e0 = energy(&app);
    step(&mut app, 1200);
    let kept = energy(&app) / e0;
    assert!(kept >= 0.9, "kept {kept} of the kinetic energy in 20 s");
}
