//! Validation of scene-file fields as they are read: each checked field deserializes
//! through one of these functions, so a bad value (`hz: 0.0`, `radius: -1`, `mass: inf`)
//! fails the load with the file, line and column of the value and the field's name, the
//! way a syntax error does, and the running scene stays.

use bevy::prelude::*;
use serde::de::Error;
use serde::{Deserialize, Deserializer};

use crate::effects::Wind;
use crate::limits::{self, Invalid};

fn refuse<'de, D: Deserializer<'de>>(e: Invalid) -> D::Error {
    D::Error::custom(format!("invalid value: {e}"))
}

/// Fixed rate, Hz, within 1..=10000.
pub fn hz<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let hz = f64::deserialize(d)?;
    if limits::RATE_HZ.contains(&hz) {
        Ok(hz)
    } else {
        let (lo, hi) = (limits::RATE_HZ.start(), limits::RATE_HZ.end());
        Err(D::Error::custom(format!(
            "invalid value: hz = {hz}: must be within {lo}..={hi}"
        )))
    }
}

/// Substeps or iterations, within 1..=64.
pub fn count<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let n = u32::deserialize(d)?;
    if limits::SUBSTEPS.contains(&n) {
        Ok(n)
    } else {
        Err(D::Error::custom(format!(
            "invalid value: {n}: substeps and iterations must be within 1..=64"
        )))
    }
}

/// How many bodies one generated group may make.
pub const MAX_GROUP: u64 = 100_000;

/// A group's copy count, at most [`MAX_GROUP`].
pub fn group_count<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let n = u32::deserialize(d)?;
    if (n as u64) <= MAX_GROUP {
        Ok(n)
    } else {
        Err(D::Error::custom(format!(
            "invalid value: count = {n}: a group makes at most {MAX_GROUP} bodies"
        )))
    }
}

/// A pyramid's base: a 3-D pyramid of base b has about b³/3 bodies, so at most 66.
pub fn pyramid_base<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let n = u32::deserialize(d)?;
    // The flat pyramid (b(b+1)/2 bodies) could go higher, but the flag comes later.
    if n <= 66 || (n as u64 * (n as u64 + 1) / 2 <= MAX_GROUP && n <= 400) {
        Ok(n)
    } else {
        Err(D::Error::custom(format!(
            "invalid value: base = {n}: a pyramid's base is at most 400 (flat) or 66"
        )))
    }
}

/// A grid's counts, whose product is at most [`MAX_GROUP`].
pub fn grid_count<'de, D: Deserializer<'de>>(d: D) -> Result<UVec3, D::Error> {
    let n = UVec3::deserialize(d)?;
    if n.x as u64 * n.y as u64 * n.z as u64 <= MAX_GROUP {
        Ok(n)
    } else {
        Err(D::Error::custom(format!(
            "invalid value: count = {n}: a group makes at most {MAX_GROUP} bodies"
        )))
    }
}

/// Declares a checked `f32` or `Vec3` field reader.
macro_rules! checked {
    ($name:ident: $ty:ty, $field:literal, |$v:ident| $check:expr) => {
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<$ty, D::Error> {
            let $v = <$ty>::deserialize(d)?;
            let check: Result<(), Invalid> = $check;
            check.map_err(refuse::<D>)?;
            Ok($v)
        }
    };
}

checked!(gravity: Vec3, "gravity", |v| limits::vector("gravity", v, limits::MAX_ACCELERATION));
checked!(position: Vec3, "position", |v| limits::vector("position", v, 1.0e7));
checked!(angles: Vec3, "rotation_deg", |v| limits::vector("angles (degrees)", v, 1.0e6));
checked!(velocity: Vec3, "velocity", |v| limits::vector("velocity", v, limits::MAX_SPEED));
checked!(spin: Vec3, "angular_velocity", |v| limits::vector(
    "angular_velocity",
    v,
    limits::MAX_RATE
));
checked!(size: f32, "size", |v| limits::positive("size", v, limits::MAX_SIZE));
checked!(sizes: Vec3, "half extents", |v| {
    let ok = v.is_finite() && v.min_element() > 0.0 && v.max_element() <= limits::MAX_SIZE;
    if ok {
        Ok(())
    } else {
        Err(Invalid {
            field: "half extents",
            reason: format!("= {v}: each must be finite, > 0 and ≤ {}", limits::MAX_SIZE),
        })
    }
});
checked!(spacing: f32, "spacing", |v| limits::scalar("spacing", v, -1.0e6..=1.0e6));
checked!(friction: f32, "friction", |v| limits::scalar(
    "friction",
    v,
    0.0..=limits::MAX_COEFFICIENT
));
checked!(restitution: f32, "restitution", |v| limits::scalar("restitution", v, 0.0..=1.0));
checked!(normal: Vec3, "normal", |v| {
    if v.is_finite() && v.length() > 1e-6 && v.length() < 1e6 {
        Ok(())
    } else {
        Err(Invalid {
            field: "normal",
            reason: format!("= {v}: must be finite and non-zero"),
        })
    }
});
checked!(wind: Wind, "wind", |v| v.check().map_err(|e| Invalid {
    field: "wind",
    reason: e.to_string(),
}));

/// An optional positive quantity (mass, density).
pub fn opt_positive<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f32>, D::Error> {
    let v = Option::<f32>::deserialize(d)?;
    if let Some(x) = v {
        limits::positive("mass/density", x, limits::MAX_MASS).map_err(refuse::<D>)?;
    }
    Ok(v)
}

/// An optional friction.
pub fn opt_friction<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f32>, D::Error> {
    let v = Option::<f32>::deserialize(d)?;
    if let Some(x) = v {
        limits::scalar("friction", x, 0.0..=limits::MAX_COEFFICIENT).map_err(refuse::<D>)?;
    }
    Ok(v)
}

/// An optional restitution.
pub fn opt_restitution<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f32>, D::Error> {
    let v = Option::<f32>::deserialize(d)?;
    if let Some(x) = v {
        limits::scalar("restitution", x, 0.0..=1.0).map_err(refuse::<D>)?;
    }
    Ok(v)
}

/// An optional rectangle of half extents.
pub fn opt_rect<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec2>, D::Error> {
    let v = Option::<Vec2>::deserialize(d)?;
    if let Some(h) = v {
        let ok = h.is_finite() && h.min_element() > 0.0 && h.max_element() <= limits::MAX_SIZE;
        if !ok {
            return Err(refuse::<D>(Invalid {
                field: "half_extents",
                reason: format!("= {h}: each must be finite, > 0 and ≤ {}", limits::MAX_SIZE),
            }));
        }
    }
    Ok(v)
}
