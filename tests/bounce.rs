//! A ball (e = 0.8) dropped 5 m onto a plane: the n-th apex is e^(2n)·h0.
//!
//! Error budget per bounce, relative to the apex height, for an impact at speed v with
//! substep hs = 1/240 s:
//! - restitution reverses the normal velocity recorded when the contact first pushes,
//!   up to one substep before the true impact: speed off by ≤ g·hs, height by ≤ 2·g·hs/v;
//! - semi-implicit Euler loses ½·g²·hs² of energy per substep of flight: over the 2v/g
//!   of a bounce's flight that is 2·g·hs/v of the apex height.
//!
//! So each apex ratio is e² within 4·g·hs/v (we allow 6·g·hs/v), and the n-th apex is
//! e^(2n)·h0 within the sum of those bounds.
//! Only bounces faster than the 1 m/s restitution threshold count.

mod common;
use bevy::prelude::*;
use common::*;
use tumble::prelude::*;

#[test]
fn apex_heights_follow_e_to_the_2n() {
    let mut app = app();
    let (r, h0, e) = (0.5, 5.0f32, 0.8f32);
    ground(&mut app, Vec3::ZERO, Quat::IDENTITY);
    let b = ball(&mut app, r, 1.0, Vec3::Y * (r + h0), Vec3::ZERO);
    app.world_mut().entity_mut(b).insert(Restitution(e));

    let mut apexes = Vec::new();
    let (mut prev_vy, mut top) = (0.0f32, 0.0f32);
    for _ in 0..60 * 12 {
        step(&mut app, 1);
        let (y, vy) = (pos(&app, b).y - r, vel(&app, b).linear.y);
        top = top.max(y);
        if prev_vy > 0.0 && vy <= 0.0 {
            apexes.push(top);
        }
        if vy > 0.0 && prev_vy <= 0.0 {
            top = y; // bounced: start looking for the next apex
        }
        prev_vy = vy;
    }
    // Bounces above 1 m/s: apex h with sqrt(2 g h) > 1 → h > 0.051 m.
    let checked: Vec<_> = apexes.iter().copied().take_while(|&h| h > 0.06).collect();
    assert!(checked.len() >= 5, "apexes {apexes:?}");
    eprintln!("apexes {checked:?}");
    let hs = 1.0 / 240.0;
    let (mut prev, mut tol_sum) = (h0, 0.0);
    for (n, &h) in checked.iter().enumerate() {
        let v = (2.0 * 9.81 * prev).sqrt();
        let tol = 6.0 * 9.81 * hs / v;
        let ratio = h / prev;
        assert!(
            (ratio - e * e).abs() < e * e * tol,
            "bounce {}: apex ratio {ratio}, expected {} ± {tol}",
            n + 1,
            e * e
        );
        tol_sum += tol;
        let expected = e.powi(2 * (n as i32 + 1)) * h0;
        assert!(
            (h - expected).abs() < expected * tol_sum,
            "bounce {}: apex {h}, expected {expected} (±{tol_sum})",
            n + 1
        );
        prev = h;
    }
}
