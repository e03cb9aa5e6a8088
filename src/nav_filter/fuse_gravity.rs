//! Gravity-vector fusion: while nothing aids the horizontal position or velocity, the normalised
//! specific force observes the direction of "up" in the body frame, a tilt aid in the manner of
//! a complementary filter (PX4's `EKF2_IMU_CTRL` bit 2) (docs/navigation_filter.md §20).

use crate::math::{hat, Mat3, UnitQuat, Vec3, GRAVITY_M_S2};

use super::covariance::{fuse_shaped, ScalarObservation};
use super::error_state::ErrorStateFilter;
use super::fusion::{Fusion, FusionOutcome, SkipReason};
use super::nav_params::{HeightSource, NavParams, IMU_CTRL_GRAVITY};
use super::state::{ErrorVector, ERR_ATT};

/// Decay time constant of the peak-holding filter on |f| whose value gates the fusion [s]
/// (PX4's `EKF2_ABL_TAU` default, 0.5 s) (docs/navigation_filter.md §20, eq. (20.2)).
const ACCEL_PEAK_TAU_S: f64 = 0.5;
/// Fused only while the filtered |f| / g is in this open interval [-] (docs/navigation_filter.md §20, eq. (20.2)).
const ACCEL_RATIO_RANGE: (f64, f64) = (0.9, 1.1);
/// Smallest unit-vector noise (1σ) taken from `EKF2_GRAV_NOISE` [-] (docs/navigation_filter.md §20, eq. (20.3)).
const MIN_NOISE: f64 = 0.01;
/// Innovation gate [SD] (docs/navigation_filter.md §20, eq. (20.3)).
const GATE_SD: f64 = 0.25;

/// Largest rate for the vehicle to count as at rest [rad/s] (rotorpilot's choice).
const REST_GYRO_RAD_S: f64 = 0.05;
/// Largest | |f| − g | for the vehicle to count as at rest [m/s²] (rotorpilot's choice).
const REST_ACCEL_M_S2: f64 = 0.5;
/// Time the rest conditions must hold [s] (rotorpilot's choice).
const REST_TIME_S: f64 = 1.0;

/// The peak-holding filter on the specific force's magnitude, and the IMU's rest detection.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct GravityAid {
    accel_peak_m_s2: Option<f64>,
    /// Time the rest conditions have held [s].
    rest_s: f64,
}

impl GravityAid {
    /// Takes one bias-corrected specific force `f_b` [m/s²] over `dt` [s]: the filtered
    /// magnitude is `max(|f|, (1 − dt/τ) · previous)` (docs/navigation_filter.md §20, eq. (20.2)).
    pub fn add(&mut self, f_b: &Vec3, dt: f64) {
        let beta = 1.0 - (dt / ACCEL_PEAK_TAU_S).clamp(0.0, 1.0);
        let prev = self.accel_peak_m_s2.unwrap_or(0.0);
        self.accel_peak_m_s2 = Some(f_b.norm().max(beta * prev));
    }

    /// Takes one bias-corrected rate `omega_b` [rad/s] and specific force `f_b` [m/s²] over `dt`
    /// [s] for the rest detection.
    pub fn add_rest(&mut self, omega_b: &Vec3, f_b: &Vec3, dt: f64) {
        let still = omega_b.norm() <= REST_GYRO_RAD_S && (f_b.norm() - GRAVITY_M_S2).abs() <= REST_ACCEL_M_S2;
        self.rest_s = if still { self.rest_s + dt } else { 0.0 };
    }

    /// Whether the IMU has seen the vehicle still for `REST_TIME_S` (PX4's "vehicle at rest").
    pub fn at_rest(&self) -> bool {
        self.rest_s >= REST_TIME_S
    }

    /// Filtered |f| / g [-], `None` before the first sample.
    pub fn accel_ratio(&self) -> Option<f64> {
        self.accel_peak_m_s2.map(|f| f / GRAVITY_M_S2)
    }

    /// Fuses the direction of the bias-corrected specific force `f_b` [m/s²] as the body-frame up
    /// direction, one axis after the other, correcting the tilt only (never the yaw), while
    /// `EKF2_IMU_CTRL` bit 2 is set, nothing aids horizontally and the filtered |f| is between
    /// 0.9 g and 1.1 g (docs/navigation_filter.md §20, eqs. (20.1)–(20.3)); `horizontal_aiding`
    /// says whether GNSS aids now, `active_height` which height source the covariance
    /// prediction before the fusion works with.
    pub fn fuse(
        &self,
        f_b: &Vec3,
        horizontal_aiding: bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        active_height: HeightSource,
    ) -> Fusion {
        if params.imu_ctrl & IMU_CTRL_GRAVITY == 0 || horizontal_aiding {
            return Fusion::skipped(SkipReason::Inactive);
        }
        let (Some(ratio), Some(measured)) = (self.accel_ratio(), f_b.try_normalize(1e-6)) else {
            return Fusion::skipped(SkipReason::Invalid);
        };
        if !(ratio > ACCEL_RATIO_RANGE.0 && ratio < ACCEL_RATIO_RANGE.1) {
            return Fusion::skipped(SkipReason::Geometry);
        }
        core.flush_covariance(params, active_height);
        let variance = gravity_noise(params.gravity_noise_g).powi(2);
        let (up_b, jac) = predicted_up(&core.x.q_wb);
        let mut worst: f64 = 0.0;
        for axis in 0..3 {
            let row = jac.row(axis).transpose();
            let s = (core.p.fixed_view::<3, 3>(ERR_ATT, ERR_ATT) * row).dot(&row) + variance;
            worst = worst.max((measured[axis] - up_b[axis]).powi(2) / (GATE_SD * GATE_SD * s));
        }
        if worst.is_nan() || worst > 1.0 {
            return Fusion {
                outcome: FusionOutcome::Rejected,
                test_ratio: worst,
            };
        }
        let mut fused = 0;
        for axis in 0..3 {
            let (up_b, jac) = predicted_up(&core.x.q_wb);
            let mut h = ErrorVector::zeros();
            h.fixed_rows_mut::<3>(ERR_ATT).copy_from(&jac.row(axis).transpose());
            let obs = ScalarObservation {
                h,
                innovation: measured[axis] - up_b[axis],
                variance,
            };
            let update = fuse_shaped(&mut core.p, &obs, f64::INFINITY, |k| k[ERR_ATT + 2] = 0.0);
            if let Some(dx) = update.dx {
                core.apply(&dx, params);
                fused += 1;
            }
        }
        Fusion {
            outcome: if fused == 3 {
                FusionOutcome::Fused
            } else {
                FusionOutcome::Rejected
            },
            test_ratio: worst,
        }
    }
}

/// Unit-vector noise (1σ) for `EKF2_GRAV_NOISE` = `noise_g` [-]: `max(noise, 0.01)`
/// (docs/navigation_filter.md §20, eq. (20.3)).
pub(super) fn gravity_noise(noise_g: f64) -> f64 {
    noise_g.max(MIN_NOISE)
}

/// Predicted up direction in the body frame, `ĝ_b = R̂ᵀ u` with `u = (0, 0, −1)` NED, and its
/// Jacobian with respect to the world-frame attitude error, `R̂ᵀ [u]×`
/// (docs/navigation_filter.md §20, eq. (20.1)).
pub(super) fn predicted_up(q_wb: &UnitQuat) -> (Vec3, Mat3) {
    let up_w = Vec3::new(0.0, 0.0, -1.0);
    let rt = q_wb.to_rotation_matrix().into_inner().transpose();
    (rt * up_w, rt * hat(&up_w))
}

#[cfg(test)]
#[path = "fuse_gravity_tests.rs"]
mod tests;
