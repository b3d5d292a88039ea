//! Soft constraints: a contact is a stiff, heavily damped spring solved implicitly
//! (Box2D v3's soft step). Given a frequency f and damping ratio ζ over a substep h:
//! ω = 2πf, a₁ = 2ζ + hω, a₂ = hωa₁, a₃ = 1/(1 + a₂);
//! bias rate ω/a₁, mass scale a₂a₃, impulse scale a₃.
//! A soft contact under load L sinks by L/(m_eff·ω²), like the spring it is.

#[derive(Clone, Copy, Debug, PartialEq)]
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

    #[test]
    fn steady_state_sag_is_load_over_stiffness() {
        // Steady state of the soft row: bias_rate·s·m·mass_scale = impulse_scale·λ, with
        // λ = m·g·h per substep, gives s = g/ω² whatever the damping.
        let (h, g) = (1.0 / 240.0, 9.81);
        let soft = Softness::new(30.0, 10.0, h);
        let s = soft.impulse_scale * g * h / (soft.bias_rate * soft.mass_scale);
        let omega = std::f32::consts::TAU * 30.0;
        assert!((s - g / (omega * omega)).abs() < 1e-7);
    }
}
