//! What values tumble accepts, in one place: the ranges every global setting, per-body
//! input and scene-file field is checked against before the step uses it. Outside them a
//! value is refused with the field named (globals keep their last good value, bodies are
//! left out until fixed, scene files fail to load with `file:line:col`), or, where noted,
//! clamped.
//!
//! The ranges are wide: they exist to stop NaN, ∞, zero where zero divides, negative
//! sizes and absurd magnitudes (1e30) that would overflow f32 within a step — not to
//! second-guess a game.

use std::ops::RangeInclusive;

use bevy::prelude::*;

/// Fixed steps per second: 1 Hz to 10 kHz (clamped).
pub const RATE_HZ: RangeInclusive<f64> = 1.0..=10_000.0;
/// Substeps per step (clamped).
pub const SUBSTEPS: RangeInclusive<u32> = 1..=64;
/// Solver passes per substep (clamped).
pub const ITERATIONS: RangeInclusive<u32> = 1..=64;
/// Largest accepted acceleration component, m/s² (gravity): 1000 g.
pub const MAX_ACCELERATION: f32 = 1.0e4;
/// Largest accepted force or torque component, N or N·m.
pub const MAX_FORCE: f32 = 1.0e12;
/// Largest accepted speed component, m/s (velocities, wind).
pub const MAX_SPEED: f32 = 1.0e5;
/// Largest accepted size (radius, half extent), m.
pub const MAX_SIZE: f32 = 1.0e5;
/// Largest accepted mass, kg.
pub const MAX_MASS: f32 = 1.0e15;
/// Largest accepted drag or stiffness-like rate, 1/s or Hz.
pub const MAX_RATE: f32 = 1.0e5;
/// Largest accepted dimensionless coefficient (friction, gravity scale, damping ratio).
pub const MAX_COEFFICIENT: f32 = 1.0e4;

/// Candidate pairs the broad phase keeps per step (8 bytes each: 8 MiB). A pile of
/// thousands of bodies spawned into one point would otherwise ask for n²/2. Beyond it,
/// pairs are dropped for that step and a warning is logged; the pile still separates,
/// the dropped pairs are found again as it thins out.
pub const MAX_PAIRS_PER_STEP: usize = 1 << 20;
/// Contact manifolds (at most 4 points each) the narrow phase keeps per step: with their
/// solver constraints about 1 KiB each, so ~130 MiB at the cap. Beyond it, pairs are
/// skipped for that step and a warning is logged.
pub const MAX_MANIFOLDS_PER_STEP: usize = 1 << 17;

/// A refused value: which field and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Invalid {
    /// The refused field's name (`0` for a one-field tuple struct's value).
    pub field: &'static str,
    /// The value and the rule it breaks, e.g. `= NaN: must be finite, > 0 and ≤ 1`.
    pub reason: String,
}

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.field, self.reason)
    }
}

/// `x` is finite and in `range`.
pub(crate) fn scalar(
    field: &'static str,
    x: f32,
    range: RangeInclusive<f32>,
) -> Result<(), Invalid> {
    if x.is_finite() && range.contains(&x) {
        Ok(())
    } else {
        Err(Invalid {
            field,
            reason: format!(
                "= {x}: must be finite and within {}..={}",
                range.start(),
                range.end()
            ),
        })
    }
}

/// `x` is finite, > 0 and ≤ `max`.
pub(crate) fn positive(field: &'static str, x: f32, max: f32) -> Result<(), Invalid> {
    if x.is_finite() && x > 0.0 && x <= max {
        Ok(())
    } else {
        Err(Invalid {
            field,
            reason: format!("= {x}: must be finite, > 0 and ≤ {max}"),
        })
    }
}

/// Every component of `v` finite with magnitude ≤ `max`.
pub(crate) fn vector(field: &'static str, v: Vec3, max: f32) -> Result<(), Invalid> {
    if v.is_finite() && v.abs().max_element() <= max {
        Ok(())
    } else {
        Err(Invalid {
            field,
            reason: format!("= {v}: every component must be finite and within ±{max}"),
        })
    }
}

/// The fixed rate, Hz, clamped into [`RATE_HZ`]; a non-finite rate gives 60 Hz. Returns
/// the rate to use and, if it differs, why.
pub(crate) fn clamp_rate(hz: f64) -> (f64, Option<String>) {
    if !hz.is_finite() {
        return (
            60.0,
            Some(format!("rate {hz} Hz is not finite; using 60 Hz")),
        );
    }
    let clamped = hz.clamp(*RATE_HZ.start(), *RATE_HZ.end());
    if clamped == hz {
        (hz, None)
    } else {
        let (lo, hi) = (RATE_HZ.start(), RATE_HZ.end());
        (
            clamped,
            Some(format!(
                "rate {hz} Hz is outside {lo}..={hi} Hz; using {clamped} Hz"
            )),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_nan_infinity_and_out_of_range() {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.0, 2.0, 1e30] {
            assert!(scalar("x", bad, 0.0..=1.0).is_err(), "{bad}");
        }
        for good in [0.0, 1e-42, 0.5, 1.0] {
            assert!(scalar("x", good, 0.0..=1.0).is_ok(), "{good}");
        }
        assert!(positive("m", 0.0, 1.0).is_err() && positive("m", 1e-42, 1.0).is_ok());
        assert!(vector("g", Vec3::new(0.0, f32::NAN, 0.0), 10.0).is_err());
        assert!(vector("g", Vec3::new(0.0, -1e30, 0.0), 10.0).is_err());
        assert_eq!(vector("g", Vec3::new(0.0, -9.81, 0.0), 10.0), Ok(()));
    }

    #[test]
    fn rates_clamp_into_range() {
        assert_eq!(clamp_rate(60.0), (60.0, None));
        assert_eq!(clamp_rate(0.0).0, 1.0);
        assert_eq!(clamp_rate(-5.0).0, 1.0);
        assert_eq!(clamp_rate(1e9).0, 10_000.0);
        assert_eq!(clamp_rate(f64::NAN).0, 60.0);
        assert!(clamp_rate(0.0).1.is_some());
    }
}
