//! Principal axes of an inertia tensor, and the tensor of a body made of parts.
//!
//! A compound body's inertia about its centre of mass is a full symmetric matrix in the
//! body's frame. The solver keeps diagonal (principal) inertia, so the body is simulated
//! in the frame of its principal axes: [`principal_axes`] finds them by cyclic Jacobi
//! rotations (each zeroes one off-diagonal term; a few sweeps converge to f32 precision
//! for a 3×3 matrix).

use bevy::prelude::*;

/// Sweeps of the Jacobi method; 3×3 converges in 4–6.
const SWEEPS: usize = 12;

/// The principal moments (kg·m²) of a symmetric inertia tensor and the rotation of its
/// principal frame: `tensor = R · diag(moments) · Rᵀ` with `R = Mat3::from_quat(frame)`.
/// The frame is a proper rotation (no reflection).
pub fn principal_axes(tensor: Mat3) -> (Vec3, Quat) {
    let mut a = tensor.to_cols_array_2d(); // a[col][row]; symmetric, so a[i][j] = a[j][i]
    let mut v = Mat3::IDENTITY.to_cols_array_2d();
    for _ in 0..SWEEPS {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-9 * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation in the (p, q) plane that zeroes a[p][q].
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // v[row][col] was built as rows: its columns are the eigenvectors.
    let mut r = Mat3::from_cols_array_2d(&v).transpose();
    if r.determinant() < 0.0 {
        r.z_axis = -r.z_axis;
    }
    let moments = Vec3::new(a[0][0], a[1][1], a[2][2]);
    (moments, Quat::from_mat3(&r).normalize())
}

/// The inertia tensor (kg·m², body frame) of a part of mass `m` whose principal moments
/// are `moments` in a frame turned by `rot`, about a point `d` away from its centre
/// (the parallel-axis theorem: + m·(|d|²·1 − d·dᵀ)).
pub fn part_tensor(moments: Vec3, rot: Quat, m: f32, d: Vec3) -> Mat3 {
    let r = Mat3::from_quat(rot);
    let own = r * Mat3::from_diagonal(moments) * r.transpose();
    let shift = Mat3::from_diagonal(Vec3::splat(d.length_squared())) - outer(d, d);
    own + shift * m
}

fn outer(a: Vec3, b: Vec3) -> Mat3 {
    Mat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rebuild(moments: Vec3, frame: Quat) -> Mat3 {
        let r = Mat3::from_quat(frame);
        r * Mat3::from_diagonal(moments) * r.transpose()
    }

    fn close(a: Mat3, b: Mat3, tol: f32) -> bool {
        (a - b).to_cols_array().iter().all(|x| x.abs() <= tol)
    }

    #[test]
    fn a_diagonal_tensor_is_its_own_principal_frame() {
        let t = Mat3::from_diagonal(Vec3::new(1.0, 2.0, 3.0));
        let (m, f) = principal_axes(t);
        assert!(close(rebuild(m, f), t, 1e-6));
        assert!(f.angle_between(Quat::IDENTITY) < 1e-6);
    }

    #[test]
    fn a_turned_tensor_gives_back_its_moments_and_axes() {
        let moments = Vec3::new(0.5, 2.0, 7.0);
        let turn = Quat::from_euler(EulerRot::XYZ, 0.3, -1.1, 0.7);
        let t = rebuild(moments, turn);
        let (m, f) = principal_axes(t);
        assert!(close(rebuild(m, f), t, 1e-5 * 7.0), "{m} {f}");
        let mut sorted = m.to_array();
        sorted.sort_by(f32::total_cmp);
        for (a, b) in sorted.iter().zip(moments.to_array()) {
            assert!((a - b).abs() < 1e-5 * 7.0, "{m}");
        }
        assert!((Mat3::from_quat(f).determinant() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_parallel_axis_theorem_for_a_point_mass() {
        // A 2 kg point 3 m along x: 18 kg·m² about y and z, none about x.
        let t = part_tensor(Vec3::ZERO, Quat::IDENTITY, 2.0, Vec3::X * 3.0);
        assert!(close(
            t,
            Mat3::from_diagonal(Vec3::new(0.0, 18.0, 18.0)),
            1e-6
        ));
    }
}
