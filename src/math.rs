//! Numeric types and small geometric helpers, chosen in one place.

/// Scalar type of the flight controller.
pub type Real = f64;
/// 3-vector.
pub type Vec3 = nalgebra::Vector3<Real>;
/// 3×3 matrix.
pub type Mat3 = nalgebra::Matrix3<Real>;
/// Unit quaternion.
pub type UnitQuat = nalgebra::UnitQuaternion<Real>;

/// Standard gravity [m/s²] (docs/model.md §1).
pub const GRAVITY_M_S2: Real = 9.81;

/// `e3 = [0, 0, 1]ᵀ`, down in NED.
pub fn e3() -> Vec3 {
    Vec3::new(0.0, 0.0, 1.0)
}

/// Skew matrix `S(v)` with `S(v) b = v × b` (docs/model.md §1, eq. (1.1)).
pub fn hat(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Inverse of [`hat`]: `vee(M) = [M32, M13, M21]ᵀ`.
pub fn vee(m: &Mat3) -> Vec3 {
    Vec3::new(m[(2, 1)], m[(0, 2)], m[(1, 0)])
}

/// Wraps an angle into (−π, π] [rad].
pub fn wrap_pi(a: Real) -> Real {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// Roll, pitch, yaw (ZYX) of `R_b` [rad] (docs/model.md §3, eq. (3.2)): `φ = atan2(R32, R33)`,
/// `θ = −asin(R31)`, `ψ = atan2(R21, R11)`.
pub fn euler_zyx(r: &Mat3) -> Vec3 {
    Vec3::new(
        r[(2, 1)].atan2(r[(2, 2)]),
        -r[(2, 0)].clamp(-1.0, 1.0).asin(),
        r[(1, 0)].atan2(r[(0, 0)]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hat_vee_round_trip_and_cross_product() {
        let a = Vec3::new(1.0, -2.0, 3.0);
        let b = Vec3::new(0.5, 0.25, -1.0);
        assert_eq!(vee(&hat(&a)), a);
        assert!((hat(&a) * b - a.cross(&b)).norm() < 1e-15);
    }

    #[test]
    fn euler_matches_nalgebra_zyx() {
        let q = UnitQuat::from_euler_angles(0.3, -0.4, 2.5);
        let e = euler_zyx(&q.to_rotation_matrix().into_inner());
        assert!((e - Vec3::new(0.3, -0.4, 2.5)).norm() < 1e-12);
    }

    #[test]
    fn wrap_into_half_open_interval() {
        assert!((wrap_pi(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_pi(-0.5) + 0.5).abs() < 1e-15);
    }
}
