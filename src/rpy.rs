//! The RPY (ZYX) dynamic model of docs/model.md §3, used by the hierarchical and passivity
//! controllers and by the wrench estimator.
//!
//! `ω_b = Q(η) η̇`, `M(η) = Qᵀ I_b Q`, and the skew-consistent Coriolis matrix
//! `C = Qᵀ I_b Q̇ − Qᵀ S(I_b Q η̇) Q` (docs/model.md §3, eqs. (3.3)–(3.10); not the course's
//! form, docs/homework.md §3, E4), for which `Ṁ = C + Cᵀ`.

use crate::math::{hat, Mat3, Vec3};

/// `R_b(η) = Rz(ψ) Ry(θ) Rx(φ)`.
pub fn rotation(eta: &Vec3) -> Mat3 {
    let (sf, cf) = eta.x.sin_cos();
    let (st, ct) = eta.y.sin_cos();
    let (sp, cp) = eta.z.sin_cos();
    Mat3::new(
        ct * cp,
        sf * st * cp - cf * sp,
        cf * st * cp + sf * sp,
        ct * sp,
        sf * st * sp + cf * cp,
        cf * st * sp - sf * cp,
        -st,
        sf * ct,
        cf * ct,
    )
}

/// `Q(η)` with `ω_b = Q η̇`; singular at θ = ±π/2 (det Q = cos θ).
pub fn q_matrix(eta: &Vec3) -> Mat3 {
    let (sf, cf) = eta.x.sin_cos();
    let (st, ct) = eta.y.sin_cos();
    Mat3::new(1.0, 0.0, -st, 0.0, cf, ct * sf, 0.0, -sf, ct * cf)
}

/// `Q(η)⁻¹`, so that `η̇ = Q⁻¹ ω_b`; `None` when `|cos θ| < cos_theta_min` (near the
/// singularity at θ = ±π/2):
///
/// ```text
/// Q⁻¹ = [ 1   sφ tθ    cφ tθ  ]
///       [ 0   cφ      −sφ     ]
///       [ 0   sφ/cθ    cφ/cθ  ]
/// ```
pub fn q_inverse(eta: &Vec3, cos_theta_min: f64) -> Option<Mat3> {
    let (sf, cf) = eta.x.sin_cos();
    let (st, ct) = eta.y.sin_cos();
    if ct.abs() < cos_theta_min {
        return None;
    }
    let tt = st / ct;
    Some(Mat3::new(1.0, sf * tt, cf * tt, 0.0, cf, -sf, 0.0, sf / ct, cf / ct))
}

/// `Q̇(η, η̇)`.
pub fn q_dot(eta: &Vec3, eta_dot: &Vec3) -> Mat3 {
    let (sf, cf) = eta.x.sin_cos();
    let (st, ct) = eta.y.sin_cos();
    let (fd, td) = (eta_dot.x, eta_dot.y);
    Mat3::new(
        0.0,
        0.0,
        -ct * td,
        0.0,
        -sf * fd,
        -st * sf * td + ct * cf * fd,
        0.0,
        -cf * fd,
        -st * cf * td - ct * sf * fd,
    )
}

/// Inertia matrix in η coordinates, `M = Qᵀ I_b Q`.
pub fn mass_matrix(eta: &Vec3, inertia: &Mat3) -> Mat3 {
    let q = q_matrix(eta);
    q.transpose() * inertia * q
}

/// Skew-consistent Coriolis matrix `C = Qᵀ I_b Q̇ − Qᵀ S(I_b Q η̇) Q` (docs/model.md §3, eq. (3.9)).
pub fn coriolis(eta: &Vec3, eta_dot: &Vec3, inertia: &Mat3) -> Mat3 {
    let q = q_matrix(eta);
    let qt = q.transpose();
    qt * inertia * q_dot(eta, eta_dot) - qt * hat(&(inertia * q * eta_dot)) * q
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inertia() -> Mat3 {
        Mat3::from_diagonal(&Vec3::new(1.2416, 1.2416, 2.4832))
    }

    #[test]
    fn rotation_matches_nalgebra_and_q_maps_rates() {
        let eta = Vec3::new(0.3, -0.2, 1.1);
        let r = nalgebra::Rotation3::from_euler_angles(eta.x, eta.y, eta.z).into_inner();
        assert!((rotation(&eta) - r).norm() < 1e-14);
        // ω_b from Ṙ = R S(ω) by finite differences.
        let eta_dot = Vec3::new(0.4, 0.1, -0.3);
        let h = 1e-6;
        let rd = (rotation(&(eta + eta_dot * h)) - rotation(&(eta - eta_dot * h))) / (2.0 * h);
        let omega = crate::math::vee(&(r.transpose() * rd));
        assert!((omega - q_matrix(&eta) * eta_dot).norm() < 1e-8);
    }

    #[test]
    fn q_inverse_inverts_and_refuses_the_singularity() {
        let eta = Vec3::new(0.7, -1.2, 2.0);
        let inv = q_inverse(&eta, 1e-3).unwrap();
        assert!((inv * q_matrix(&eta) - Mat3::identity()).norm() < 1e-12);
        assert!(q_inverse(&Vec3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0), 1e-3).is_none());
    }

    #[test]
    fn q_dot_is_the_time_derivative() {
        let eta = Vec3::new(-0.4, 0.25, 0.7);
        let eta_dot = Vec3::new(0.5, -0.2, 0.9);
        let h = 1e-6;
        let fd = (q_matrix(&(eta + eta_dot * h)) - q_matrix(&(eta - eta_dot * h))) / (2.0 * h);
        assert!((fd - q_dot(&eta, &eta_dot)).norm() < 1e-8);
    }

    #[test]
    fn m_dot_minus_2c_is_skew_symmetric() {
        let eta = Vec3::new(0.2, -0.35, 2.0);
        let eta_dot = Vec3::new(-0.7, 0.4, 1.3);
        let i = inertia();
        let h = 1e-6;
        let m_dot = (mass_matrix(&(eta + eta_dot * h), &i) - mass_matrix(&(eta - eta_dot * h), &i)) / (2.0 * h);
        let c = coriolis(&eta, &eta_dot, &i);
        assert!((m_dot - c - c.transpose()).norm() < 1e-7);
        let n = m_dot - 2.0 * c;
        assert!((n + n.transpose()).norm() < 1e-7);
    }

    #[test]
    fn coriolis_term_matches_the_shortcut() {
        // Q⁻ᵀ C η̇ = ω × I ω + I Q̇ η̇.
        let eta = Vec3::new(0.1, 0.3, -0.5);
        let eta_dot = Vec3::new(0.6, -0.8, 0.2);
        let i = inertia();
        let q = q_matrix(&eta);
        let w = q * eta_dot;
        let lhs = q.transpose().try_inverse().unwrap() * coriolis(&eta, &eta_dot, &i) * eta_dot;
        let rhs = w.cross(&(i * w)) + i * q_dot(&eta, &eta_dot) * eta_dot;
        assert!((lhs - rhs).norm() < 1e-12);
    }
}
