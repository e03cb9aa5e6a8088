//! Error-state covariance: discrete prediction from accumulated IMU increments, scalar
//! sequential updates with an innovation gate, and the resets (docs/navigation_filter.md §3–§5).

use nalgebra::Matrix3;

use crate::math::{hat, Mat3, Vec3};

use super::state::{
    Covariance, ErrorVector, ERR_ACCEL_BIAS, ERR_ATT, ERR_BARO_OFFSET, ERR_GYRO_BIAS, ERR_POS, ERR_VEL, STATE_DIM,
};

/// IMU increments accumulated between two covariance predictions
/// (docs/navigation_filter.md §2, eq. (2.3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Increments {
    /// Δt: time covered [s].
    pub dt_s: f64,
    /// Δv: ∫ R (f − b_a) dt, the specific-force velocity increment in world NED [m/s].
    pub dvel_w: Vec3,
    /// A: ∫ R dt [s].
    pub rot_dt: Mat3,
}

impl Default for Increments {
    fn default() -> Self {
        Self {
            dt_s: 0.0,
            dvel_w: Vec3::zeros(),
            rot_dt: Mat3::zeros(),
        }
    }
}

/// Process noise of one prediction (docs/navigation_filter.md §4, eq. (4.3)): each σ is PX4's
/// "per prediction period" value, so var = σ² T_p Δt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ProcessNoise {
    /// σ_a [m/s²].
    pub accel: f64,
    /// σ_g [rad/s].
    pub gyro: f64,
    /// σ_ba [m/s³].
    pub accel_bias: f64,
    /// σ_bg [rad/s²].
    pub gyro_bias: f64,
    /// σ_bh [m/s]; `None` while the barometer offset is frozen (docs/navigation_filter.md §9).
    pub baro_offset: Option<f64>,
    /// T_p [s].
    pub period_s: f64,
}

fn set_block(m: &mut Covariance, r: usize, c: usize, b: &Mat3) {
    m.fixed_view_mut::<3, 3>(r, c).copy_from(b);
}

/// Transition matrix Φ over the increments (docs/navigation_filter.md §4, eq. (4.1)).
pub(super) fn transition(inc: &Increments) -> Covariance {
    let dt = inc.dt_s;
    let s_dv = hat(&inc.dvel_w);
    let a = inc.rot_dt;
    let mut phi = Covariance::identity();
    set_block(&mut phi, ERR_POS, ERR_VEL, &(Matrix3::identity() * dt));
    set_block(&mut phi, ERR_POS, ERR_ATT, &(s_dv * (-0.5 * dt)));
    set_block(&mut phi, ERR_POS, ERR_ACCEL_BIAS, &(a * (-0.5 * dt)));
    set_block(&mut phi, ERR_VEL, ERR_ATT, &(-s_dv));
    set_block(&mut phi, ERR_VEL, ERR_ACCEL_BIAS, &(-a));
    set_block(&mut phi, ERR_VEL, ERR_GYRO_BIAS, &(s_dv * a * 0.5));
    set_block(&mut phi, ERR_ATT, ERR_GYRO_BIAS, &(-a));
    phi
}

/// P⁻ = Φ P Φᵀ + Q, then the variance limits (docs/navigation_filter.md §4, eqs. (4.2)–(4.5)).
pub(super) fn predict(p: &mut Covariance, inc: &Increments, noise: &ProcessNoise) {
    let phi = transition(inc);
    let dt = inc.dt_s;
    let mut next = phi * *p * phi.transpose();
    let var = |sigma: f64| sigma * sigma * noise.period_s * dt;
    let qv = var(noise.accel);
    for i in 0..3 {
        next[(ERR_POS + i, ERR_POS + i)] += qv * dt * dt / 3.0;
        next[(ERR_POS + i, ERR_VEL + i)] += qv * dt / 2.0;
        next[(ERR_VEL + i, ERR_POS + i)] += qv * dt / 2.0;
        next[(ERR_VEL + i, ERR_VEL + i)] += qv;
        next[(ERR_ATT + i, ERR_ATT + i)] += var(noise.gyro);
        next[(ERR_ACCEL_BIAS + i, ERR_ACCEL_BIAS + i)] += var(noise.accel_bias);
        next[(ERR_GYRO_BIAS + i, ERR_GYRO_BIAS + i)] += var(noise.gyro_bias);
    }
    if let Some(sigma) = noise.baro_offset {
        next[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)] += var(sigma);
    }
    *p = next;
    symmetrize(p);
    limit_variances(p);
}

/// Variance bounds per state block [unit²] (docs/navigation_filter.md §4, eq. (4.5)).
const LIMITS: [(usize, usize, f64, f64); 6] = [
    (ERR_POS, 3, 1e-6, 1e6),
    (ERR_VEL, 3, 1e-6, 1e6),
    (ERR_ATT, 3, 0.0, 1.0),
    (ERR_ACCEL_BIAS, 3, 0.0, 0.981 * 0.981),
    (ERR_GYRO_BIAS, 3, 0.0, 1.0),
    (ERR_BARO_OFFSET, 1, 0.0, 1e6),
];

/// Keeps each variance within its bounds: a variance above the limit has its row and column
/// scaled (PSD kept), one below the floor is raised (docs/navigation_filter.md §4, eq. (4.5)).
pub(super) fn limit_variances(p: &mut Covariance) {
    for (start, n, min, max) in LIMITS {
        for i in start..start + n {
            let v = p[(i, i)];
            if v > max {
                let s = (max / v).sqrt();
                for j in 0..STATE_DIM {
                    p[(i, j)] *= s;
                    p[(j, i)] *= s;
                }
            } else if v < min {
                p[(i, i)] = min;
            }
        }
    }
}

/// P ← (P + Pᵀ) / 2.
pub(super) fn symmetrize(p: &mut Covariance) {
    for i in 0..STATE_DIM {
        for j in i + 1..STATE_DIM {
            let m = 0.5 * (p[(i, j)] + p[(j, i)]);
            p[(i, j)] = m;
            p[(j, i)] = m;
        }
    }
}

/// Clears the correlations of state `i` and sets its variance (a reset,
/// docs/navigation_filter.md §6, eq. (6.4)).
pub(super) fn uncorrelate(p: &mut Covariance, i: usize, variance: f64) {
    for j in 0..STATE_DIM {
        p[(i, j)] = 0.0;
        p[(j, i)] = 0.0;
    }
    p[(i, i)] = variance;
}

/// One scalar observation of the error state: `ν = H δx + n`, `n ~ N(0, r)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ScalarObservation {
    /// Measurement row H (as a column) [-].
    pub h: ErrorVector,
    /// Innovation against the nominal state before this group [measurement unit].
    pub innovation: f64,
    /// Measurement noise variance r [measurement unit²].
    pub variance: f64,
}

impl ScalarObservation {
    /// An observation of the single error state `i`.
    pub fn of_state(i: usize, innovation: f64, variance: f64) -> Self {
        let mut h = ErrorVector::zeros();
        h[i] = 1.0;
        Self {
            h,
            innovation,
            variance,
        }
    }
}

/// Outcome of a gated group of scalars.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GroupUpdate {
    /// Largest test ratio of the group against the prior P
    /// (docs/navigation_filter.md §5, eq. (5.3)).
    pub test_ratio: f64,
    /// Innovation variance of each scalar against the prior P (first three).
    pub innovation_variance: [f64; 3],
    /// The error estimate to inject, `None` when the group was rejected.
    pub dx: Option<ErrorVector>,
}

/// S = H P Hᵀ + r (docs/navigation_filter.md §5, eq. (5.2)).
pub(super) fn innovation_variance(p: &Covariance, obs: &ScalarObservation) -> f64 {
    (p * obs.h).dot(&obs.h) + obs.variance
}

/// Gates a group of scalars against the prior P (rejected as a whole when any test ratio
/// exceeds 1; `gate_sd = None` fuses without a gate), then fuses them one after the other,
/// accumulating δx (docs/navigation_filter.md §5, eqs. (5.2)–(5.6)).
pub(super) fn fuse_group(p: &mut Covariance, group: &[ScalarObservation], gate_sd: Option<f64>) -> GroupUpdate {
    let mut test_ratio: f64 = 0.0;
    let mut innovation_variance_out = [0.0; 3];
    for (k, obs) in group.iter().enumerate() {
        let s = innovation_variance(p, obs);
        if k < 3 {
            innovation_variance_out[k] = s;
        }
        let ratio = match gate_sd {
            Some(g) if s > 0.0 => obs.innovation * obs.innovation / (g * g * s),
            Some(_) => f64::INFINITY,
            None => 0.0,
        };
        test_ratio = test_ratio.max(ratio);
    }
    let rejected = test_ratio.is_nan() || test_ratio > 1.0;
    if rejected {
        return GroupUpdate {
            test_ratio,
            innovation_variance: innovation_variance_out,
            dx: None,
        };
    }
    let mut dx = ErrorVector::zeros();
    for obs in group {
        let ph = *p * obs.h;
        let s = ph.dot(&obs.h) + obs.variance;
        if !(s.is_finite() && s > 0.0) {
            continue;
        }
        let residual = obs.innovation - obs.h.dot(&dx);
        dx.axpy(residual / s, &ph, 1.0);
        p.ger(-1.0 / s, &ph, &ph, 1.0);
    }
    symmetrize(p);
    for i in 0..STATE_DIM {
        if p[(i, i)].is_nan() || p[(i, i)] < 0.0 {
            p[(i, i)] = 0.0;
        }
    }
    GroupUpdate {
        test_ratio,
        innovation_variance: innovation_variance_out,
        dx: Some(dx),
    }
}

/// One scalar observation with a gain reshaped by `shape` (a Schmidt or "consider" update: the
/// states it leaves uncorrected still enter S and keep consistent covariances, since the
/// Joseph-form update holds for any gain) (docs/navigation_filter.md §5, eq. (5.8)).
pub(super) fn fuse_shaped(
    p: &mut Covariance,
    obs: &ScalarObservation,
    gate_sd: f64,
    shape: impl FnOnce(&mut ErrorVector),
) -> GroupUpdate {
    let ph = *p * obs.h;
    let s = ph.dot(&obs.h) + obs.variance;
    let test_ratio = if s > 0.0 {
        obs.innovation * obs.innovation / (gate_sd * gate_sd * s)
    } else {
        f64::INFINITY
    };
    let innovation_variance = [s, 0.0, 0.0];
    if test_ratio.is_nan() || test_ratio > 1.0 {
        return GroupUpdate {
            test_ratio,
            innovation_variance,
            dx: None,
        };
    }
    let mut k = ph / s;
    shape(&mut k);
    // P⁺ = (I − k h) P (I − k h)ᵀ + k r kᵀ = P − k (Ph)ᵀ − (Ph) kᵀ + S k kᵀ.
    p.ger(-1.0, &k, &ph, 1.0);
    p.ger(-1.0, &ph, &k, 1.0);
    p.ger(s, &k, &k, 1.0);
    symmetrize(p);
    GroupUpdate {
        test_ratio,
        innovation_variance,
        dx: Some(k * obs.innovation),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prior() -> Covariance {
        let mut p = Covariance::identity() * 0.01;
        for i in 0..3 {
            p[(ERR_POS + i, ERR_POS + i)] = 4.0;
        }
        p
    }

    #[test]
    fn scalar_update_is_the_textbook_kalman_update() {
        let mut p = prior();
        p[(ERR_POS, ERR_VEL)] = 0.1;
        p[(ERR_VEL, ERR_POS)] = 0.1;
        let obs = ScalarObservation::of_state(ERR_POS, 2.0, 1.0);
        let u = fuse_group(&mut p, &[obs], Some(5.0));
        let dx = u.dx.unwrap();
        // K = P Hᵀ / S with S = 4 + 1.
        assert!((dx[ERR_POS] - 2.0 * 4.0 / 5.0).abs() < 1e-12);
        assert!((dx[ERR_VEL] - 2.0 * 0.1 / 5.0).abs() < 1e-12);
        assert!((p[(ERR_POS, ERR_POS)] - (4.0 - 16.0 / 5.0)).abs() < 1e-12);
        assert!((u.test_ratio - 4.0 / (25.0 * 5.0)).abs() < 1e-12);
        assert!(p.symmetric_eigenvalues().min() > 0.0);
    }

    #[test]
    fn gate_rejects_the_whole_group_and_leaves_p_alone() {
        let mut p = prior();
        let before = p;
        let group = [
            ScalarObservation::of_state(ERR_POS, 0.1, 1.0),
            ScalarObservation::of_state(ERR_POS + 1, 50.0, 1.0),
        ];
        let u = fuse_group(&mut p, &group, Some(5.0));
        assert!(u.dx.is_none() && u.test_ratio > 1.0);
        assert_eq!(p, before);
    }

    #[test]
    fn sequential_scalars_equal_the_batch_update() {
        let mut p = prior();
        p[(ERR_POS, ERR_POS + 1)] = 1.0;
        p[(ERR_POS + 1, ERR_POS)] = 1.0;
        let mut seq = p;
        let group = [
            ScalarObservation::of_state(ERR_POS, 1.0, 0.5),
            ScalarObservation::of_state(ERR_POS + 1, -1.0, 0.5),
        ];
        let dx = fuse_group(&mut seq, &group, None).dx.unwrap();
        // Batch: K = P Hᵀ (H P Hᵀ + R)⁻¹ with H selecting the first two states.
        let h = nalgebra::SMatrix::<f64, 2, STATE_DIM>::from_fn(|r, c| if r == c { 1.0 } else { 0.0 });
        let s = h * p * h.transpose() + nalgebra::Matrix2::identity() * 0.5;
        let k = p * h.transpose() * s.try_inverse().unwrap();
        let batch_dx = k * nalgebra::Vector2::new(1.0, -1.0);
        let batch_p = (Covariance::identity() - k * h) * p;
        assert!((dx - batch_dx).norm() < 1e-12);
        assert!((seq - batch_p).norm() < 1e-12);
    }

    #[test]
    fn consider_update_with_every_state_is_the_kalman_update() {
        let mut p = prior();
        p[(ERR_POS, ERR_ATT)] = 0.05;
        p[(ERR_ATT, ERR_POS)] = 0.05;
        let mut q = p;
        let obs = ScalarObservation::of_state(ERR_POS, 1.5, 0.7);
        let a = fuse_group(&mut p, &[obs], Some(5.0)).dx.unwrap();
        let b = fuse_shaped(&mut q, &obs, 5.0, |_| {}).dx.unwrap();
        assert!((a - b).norm() < 1e-12 && (p - q).norm() < 1e-12);
        // Considering the attitude: it stays, the variance reduction is smaller, P stays PSD.
        let mut c = prior();
        c[(ERR_POS, ERR_ATT)] = 0.05;
        c[(ERR_ATT, ERR_POS)] = 0.05;
        let dx = fuse_shaped(&mut c, &obs, 5.0, |k| k[ERR_ATT] = 0.0).dx.unwrap();
        assert_eq!(dx[ERR_ATT], 0.0);
        assert!(c[(ERR_POS, ERR_POS)] >= p[(ERR_POS, ERR_POS)] - 1e-12);
        assert!(c.symmetric_eigenvalues().min() > 0.0);
    }

    #[test]
    fn variance_cap_keeps_psd() {
        let mut p = Covariance::identity();
        p[(ERR_ATT, ERR_ATT)] = 9.0;
        p[(ERR_ATT, ERR_GYRO_BIAS)] = 0.9;
        p[(ERR_GYRO_BIAS, ERR_ATT)] = 0.9;
        limit_variances(&mut p);
        assert!((p[(ERR_ATT, ERR_ATT)] - 1.0).abs() < 1e-12);
        assert!(p.symmetric_eigenvalues().min() >= 0.0);
    }
}
