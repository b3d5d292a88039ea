//! The gyroscopic solve for the Euler integrators: Euler's equations in the body frame,
//! I·(ω₂ − ω₁) + h·ω_m × (I·ω_m) = h·τ with ω_m = (ω₁ + ω₂)/2 (implicit midpoint).
//!
//! The midpoint rule conserves both |L| and kinetic energy of torque-free motion exactly
//! (up to the Newton tolerance), so a box spun near its intermediate axis flips on time.
//! Backward Euler (ω_m = ω₂) damps; the explicit term ω₁ × Iω₁ gains energy.

use bevy::prelude::*;

/// Solves for ω₂ (body frame) by two Newton iterations from ω₂ = ω₁, with the Jacobian
/// J = I + (h/2)·(skew(ω_m)·I − skew(I·ω_m)).
pub fn solve_gyroscopic_midpoint(inertia: Vec3, w1: Vec3, torque: Vec3, h: f32) -> Vec3 {
    // Isotropic inertia (a sphere): ω_m × I·ω_m = 0, and the solve is exact in one line.
    if is_isotropic_moments(inertia) {
        return w1 + h * torque / inertia.x;
    }
    let i = Mat3::from_diagonal(inertia);
    let mut w2 = w1;
    for _ in 0..2 {
        let wm = 0.5 * (w1 + w2);
        let iwm = inertia * wm;
        let f = inertia * (w2 - w1) + h * wm.cross(iwm) - h * torque;
        let j = i + 0.5 * h * (skew(wm) * i - skew(iwm));
        let det = j.determinant();
        if !det.is_finite() || det.abs() < f32::MIN_POSITIVE {
            break;
        }
        w2 -= j.inverse() * f;
    }
    w2
}

/// Whether principal moments are all equal (a sphere, a cube): then ω × Iω = 0 and every
/// frame is a principal one.
#[inline]
pub fn is_isotropic_moments(inertia: Vec3) -> bool {
    inertia.x == inertia.y && inertia.y == inertia.z
}

/// The cross-product matrix: skew(a)·b = a × b.
pub fn skew(a: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, a.z, -a.y),
        Vec3::new(-a.z, 0.0, a.x),
        Vec3::new(a.y, -a.x, 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross() {
        let (a, b) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(-4.0, 0.5, 2.0));
        assert!((skew(a) * b - a.cross(b)).length() < 1e-6);
    }

    #[test]
    fn midpoint_keeps_energy_and_momentum_of_a_tumbling_box() {
        // 1.0 × 0.1 × 0.4 m box, 1 kg, spun near its intermediate axis; 600 steps of 1/240 s.
        let inertia = Vec3::new(0.17, 1.16, 1.01) / 12.0;
        let mut w = Vec3::new(1.0, 0.0, 10.0);
        let (l0, e0) = ((inertia * w).length(), w.dot(inertia * w));
        for _ in 0..600 {
            w = solve_gyroscopic_midpoint(inertia, w, Vec3::ZERO, 1.0 / 240.0);
        }
        // In the body frame |L| and energy are invariants of the exact flow.
        assert!(((inertia * w).length() - l0).abs() / l0 < 1e-4);
        assert!((w.dot(inertia * w) - e0).abs() / e0 < 1e-4);
    }

    #[test]
    fn isotropic_shortcut_solves_the_same_equation() {
        // For a sphere the residual of the midpoint equation must vanish at the shortcut.
        let (inertia, w1, tau, h) = (Vec3::splat(0.4), Vec3::new(3.0, -1.0, 2.0), Vec3::X, 0.01);
        let w2 = solve_gyroscopic_midpoint(inertia, w1, tau, h);
        let wm = 0.5 * (w1 + w2);
        let residual = inertia * (w2 - w1) + h * wm.cross(inertia * wm) - h * tau;
        assert!(residual.length() < 1e-6, "{residual}");
        assert!((w2 - w1 - h * tau / 0.4).length() < 1e-6);
    }
}
