//! The free motion of a body that neither turns nor feels drag: constant acceleration.
//! Each integrator's n substeps then have a closed form, which gives the same result as
//! running them one by one (up to rounding) in a fixed number of operations. Most bodies
//! of a free-flight scene take this path.

use bevy::prelude::*;

use crate::settings::Integrator;

/// Position change and end velocity after `n` substeps of `h` from velocity `v0` under the
/// constant acceleration `a`, as `integrator` would compute them:
/// - semi-implicit Euler moves with the new velocities: h·Σₖ₌₁ⁿ vₖ = h·(n·v0 + a·h·n(n+1)/2);
/// - explicit Euler with the old ones: h·Σₖ₌₀ⁿ⁻¹ vₖ = h·(n·v0 + a·h·n(n−1)/2);
/// - RK4 is exact for constant acceleration: v0·t + ½·a·t².
pub fn ballistic(integrator: Integrator, v0: Vec3, a: Vec3, h: f32, n: u32) -> (Vec3, Vec3) {
    let nf = n as f32;
    let t = nf * h;
    let dp = match integrator {
        Integrator::SemiImplicitEuler => h * (nf * v0 + a * (h * nf * (nf + 1.0) * 0.5)),
        Integrator::ExplicitEuler => h * (nf * v0 + a * (h * nf * (nf - 1.0) * 0.5)),
        Integrator::Rk4 => v0 * t + a * (0.5 * t * t),
    };
    (dp, v0 + a * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RigidBody;
    use crate::math::ForceModel;
    use crate::math::{Inertial, free_substep};

    #[test]
    fn closed_form_matches_the_substeps_of_every_integrator() {
        let forces = ForceModel {
            accel: Vec3::new(0.3, -9.81, 1.2),
            ..default()
        };
        let body = Inertial {
            forces: &forces,
            inertia: Vec3::ONE,
            inv_inertia: Vec3::ONE,
            rotation_locked: false,
        };
        for integrator in Integrator::ALL {
            for n in [1, 4, 7] {
                let (h, v0) = (1.0 / 240.0, Vec3::new(3.0, 5.0, -2.0));
                let (mut dp, mut v) = (Vec3::ZERO, v0);
                for _ in 0..n {
                    let fs = free_substep(
                        integrator,
                        RigidBody::Dynamic,
                        body,
                        Quat::IDENTITY,
                        v,
                        Vec3::ZERO,
                        h,
                    );
                    dp += fs.dx;
                    v = fs.v;
                }
                let (dp2, v2) = ballistic(integrator, v0, forces.accel, h, n);
                assert!(
                    (dp - dp2).length() < 1e-6,
                    "{integrator:?} n={n}: {dp} vs {dp2}"
                );
                assert!(
                    (v - v2).length() < 1e-5,
                    "{integrator:?} n={n}: {v} vs {v2}"
                );
            }
        }
    }
}
