//! The heading while the magnetometer is lost: the yaw estimator of [`super::yaw_estimator`] is
//! fed with the IMU in the heading-free level frame and with every GNSS velocity. The filter
//! keeps its own yaw (held by the gyroscope, corrected through the GNSS velocity when the
//! vehicle accelerates); once the magnetometer has not been fused for `sensor_timeout_s`, a
//! yaw that disagrees with the estimator's converged heading beyond [`YAW_RESET_MIN_RAD`] and
//! three standard deviations is reset to it, as PX4 resets its yaw to its EKF-GSF
//! (docs/navigation_filter.md §18, eqs. (18.6)–(18.7)). In a hover the estimator stays
//! unconverged and nothing is reset.

use nalgebra::Vector2;

use crate::math::{wrap_pi, Vec3};

use super::covariance::uncorrelate;
use super::state::ERR_ATT;
use super::NavFilter;

/// Largest standard deviation of the estimator's heading that may reset the yaw [rad] (PX4
/// resets its yaw to its EKF-GSF below 15°).
pub const MAX_AID_YAW_STD_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;
/// Smallest disagreement that resets the yaw [rad]: below it the GNSS velocity fusion corrects.
pub const YAW_RESET_MIN_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// IMU increments since the last GNSS fix, for the yaw estimator.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct HeadingAidIncrements {
    /// Specific force integrated in the world frame [m/s].
    dvel_w: Vec3,
    /// Turn about the vertical [rad].
    dyaw: f64,
    /// Time covered [s].
    dt_s: f64,
}

impl HeadingAidIncrements {
    /// Adds one IMU interval of `dt_s` [s] with specific force `f_w` [m/s²], world NED, and rate
    /// `yaw_rate` [rad/s] about the vertical.
    pub(super) fn add(&mut self, f_w: &Vec3, yaw_rate: f64, dt_s: f64) {
        self.dvel_w += f_w * dt_s;
        self.dyaw += yaw_rate * dt_s;
        self.dt_s += dt_s;
    }
}

impl NavFilter {
    /// A GNSS velocity `vel_w` [m/s] of variance `vel_var` [m²/s²] arrived: the yaw estimator
    /// predicts over the increments, rotated into the level frame by the estimated yaw (18.6), and
    /// fuses it; while the magnetometer is lost a yaw far from its converged heading is reset to
    /// it (18.7).
    pub(super) fn aid_heading_from_gps(&mut self, vel_w: &Vec3, vel_var: f64) {
        let inc = std::mem::take(&mut self.heading_aid);
        let (_, _, yaw) = self.x.q_wb.euler_angles();
        let (s, c) = yaw.sin_cos();
        let level = Vector2::new(
            c * inc.dvel_w.x + s * inc.dvel_w.y,
            -s * inc.dvel_w.x + c * inc.dvel_w.y,
        );
        self.yaw_gsf.predict(level, inc.dyaw, inc.dt_s);
        self.yaw_gsf.fuse_velocity(vel_w.xy(), vel_var);
        let mag_lost = self
            .mag
            .last_fused_s
            .is_none_or(|t| self.t_s - t > self.params.sensor_timeout_s);
        let Some((gsf_yaw, gsf_var)) = self.yaw_gsf.yaw() else {
            return;
        };
        let disagreement = wrap_pi(gsf_yaw - yaw);
        let yaw_var = self.p[(ERR_ATT + 2, ERR_ATT + 2)];
        let reset = self.yaw_aligned
            && mag_lost
            && gsf_var.sqrt() < MAX_AID_YAW_STD_RAD
            && disagreement.abs() > YAW_RESET_MIN_RAD
            && disagreement.powi(2) > 9.0 * (gsf_var + yaw_var);
        if reset {
            self.turn_yaw(disagreement);
            uncorrelate(&mut self.p, ERR_ATT + 2, gsf_var);
        }
    }
}
