//! Soft constraints: a contact is a stiff, heavily damped spring solved implicitly
//! (Box2D v3's soft step). Given a frequency f and damping ratio ζ over a substep h:
//! ω = 2πf, a₁ = 2ζ + hω, a₂ = hωa₁, a₃ = 1/(1 + a₂);
//! bias rate ω/a₁, mass scale a₂a₃, impulse scale a₃.
//! A soft contact under load L sinks by L/(m_eff·ω²), like the spring it is.

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Softness {
    pub bias_rate: f32,
    pub mass_scale: f32,
    pub impulse_scale: f32,
}

impl Softness {
    pub fn new(hertz: f32, damping_ratio: f32, h: f32) -> Self {
        if hertz <= 0.0 {
            return Self {
                bias_rate: 0.0,
                mass_scale: 1.0,
                impulse_scale: 0.0,
            };
        }
        let omega = std::f32::consts::TAU * hertz;
        let a1 = 2.0 * damping_ratio + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default `max_push_out`, m/s: the cap on a static contact's bias velocity.
    const MAX_PUSH: f32 = 3.0;

    /// One normal row as `iterate::solve` runs it, for a body of mass `m` on a static
    /// contact: separation `s` (negative when sunk in), normal velocity `v`, accumulated
    /// impulse `lambda`. `soft` is `Some` for the biased solve, `None` for the relax pass.
    fn row(s: f32, v: f32, lambda: f32, m: f32, h: f32, soft: Option<Softness>) -> (f32, f32) {
        let (bias, mass_scale, impulse_scale) = match soft {
            _ if s > 0.0 => (s / h, 1.0, 0.0),
            Some(soft) => (
                (soft.bias_rate * s).max(-MAX_PUSH),
                soft.mass_scale,
                soft.impulse_scale,
            ),
            None => (0.0, 1.0, 0.0),
        };
        let dl = -m * mass_scale * (v + bias) - impulse_scale * lambda;
        let new = (lambda + dl).max(0.0);
        (v + (new - lambda) / m, new)
    }

    /// The separation after `n` substeps of a body set down touching a static floor at
    /// rest, each substep as the solver stages run it: gravity, warm start with the
    /// accumulated impulse, the soft solve, s += h·v, the relax pass.
    fn settle(soft: Softness, m: f32, g: f32, h: f32, n: usize) -> f32 {
        let (mut s, mut v, mut lambda) = (0.0f32, 0.0f32, 0.0f32);
        for _ in 0..n {
            v -= g * h;
            v += lambda / m;
            (v, lambda) = row(s, v, lambda, m, h, Some(soft));
            s += h * v;
            (v, lambda) = row(s, v, lambda, m, h, None);
        }
        s
    }

    #[test]
    fn a_resting_body_settles_at_load_over_stiffness() {
        // The soft row is a spring of stiffness m·ω²: under its weight m·g a body settles
        // g/ω² deep whatever its mass and damping ratio. Default contact (30 Hz, ζ 10, four
        // substeps at 60 Hz), a heavy body, the stiffest default-rate contact at 16
        // substeps, and a soft, lightly damped one.
        let g = 9.81;
        for (hertz, zeta, h, m) in [
            (30.0, 10.0, 1.0 / 240.0, 1.0),
            (30.0, 10.0, 1.0 / 240.0, 1000.0),
            (60.0, 10.0, 1.0 / 960.0, 0.01),
            (5.0, 1.0, 1.0 / 240.0, 2.0),
        ] {
            let soft = Softness::new(hertz, zeta, h);
            let omega = std::f32::consts::TAU * hertz;
            let expected = -g / (omega * omega);
            // Transient: the slow mode of the damped spring decays by about
            // exp(−h·ω/(2ζ)) a substep for ζ ≥ 1 (≈ 0.96 for the default); 4000 substeps
            // leave at most exp(−78) of it here (60 Hz at h/16): nothing.
            let n = 4000;
            // Rounding: at the fixed point λ ≈ m·g·h and the solve's velocity must be too
            // small to move s by half an ulp, |v| < ulp(s)/(2h); v is the bias residual
            // (m_s·b·(s − s*), m_s·b = h·ω²/(1 + a₂)) plus the rounding of −g·h + λ/m, a
            // few ulps of g·h. So |s − s*| ≲ ε·|s*|·(1 + a₂)·(1/(2(hω)²) + 2); bounded
            // with a factor 4 margin: 3·10⁻⁵ relative for the default, 4·10⁻⁶ seen at
            // worst.
            let a2 = h * omega * (2.0 * zeta + h * omega);
            let tol = 4.0
                * f32::EPSILON
                * expected.abs()
                * (1.0 + a2)
                * (1.0 / (h * omega).powi(2) + 2.0);
            let s = settle(soft, m, g, h, n);
            let what = format!("{hertz} Hz, ζ {zeta}, h {h}, m {m}");
            assert!(
                (s - expected).abs() <= tol,
                "{what}: settled at {s} m, expected {expected} ± {tol}"
            );
            // Able to fail: the steady state is s = −g·h·impulse_scale/(bias_rate·
            // mass_scale), so half the bias rate settles twice as deep, off by |s*|,
            // thousands of tolerances.
            let halved = Softness {
                bias_rate: soft.bias_rate / 2.0,
                ..soft
            };
            let s_halved = settle(halved, m, g, h, n);
            assert!(
                (s_halved - expected).abs() > 1000.0 * tol,
                "{what}: half the bias rate settled at {s_halved} m, not distinguishable"
            );
            assert!(
                (s_halved - 2.0 * expected).abs() <= 2.0 * tol,
                "{what}: half the bias rate settled at {s_halved} m, not 2·{expected}"
            );
        }
    }
}
