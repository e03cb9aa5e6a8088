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
use super::error_state::{ErrorStateFilter, ImuInterval};
use super::nav_params::NavParams;
use super::state::ERR_ATT;
use super::yaw_estimator::YawEstimator;

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

/// The heading from GNSS velocity (docs/navigation_filter.md §18): the yaw estimator and the
/// IMU increments it has not seen yet.
#[derive(Debug, Clone, Default)]
pub(super) struct HeadingAid {
    /// The Gaussian sum of heading hypotheses (docs/navigation_filter.md §18, eqs. (18.1)–(18.5)).
    yaw_gsf: YawEstimator,
    /// IMU increments since the last GNSS fix, for `yaw_gsf`.
    increments: HeadingAidIncrements,
}

impl HeadingAid {
    /// Adds one integrated IMU interval (docs/navigation_filter.md §18, eq. (18.6)).
    pub fn add(&mut self, interval: &ImuInterval) {
        self.increments.add(&interval.f_w, interval.yaw_rate, interval.dt_s);
    }

    /// A GNSS velocity `vel_w` [m/s] of variance `vel_var` [m²/s²] arrived: the yaw estimator
    /// predicts over the increments, rotated into the level frame by the estimated yaw (18.6), and
    /// fuses it; when `may_reset` (the yaw was aligned and the magnetometer is lost) a yaw far
    /// from the estimator's converged heading is reset to it (18.7). True when the yaw was reset.
    pub fn aid(
        &mut self,
        vel_w: &Vec3,
        vel_var: f64,
        may_reset: bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
    ) -> bool {
        let inc = std::mem::take(&mut self.increments);
        let (_, _, yaw) = core.x.q_wb.euler_angles();
        let (s, c) = yaw.sin_cos();
        let level = Vector2::new(
            c * inc.dvel_w.x + s * inc.dvel_w.y,
            -s * inc.dvel_w.x + c * inc.dvel_w.y,
        );
        self.yaw_gsf.predict(level, inc.dyaw, inc.dt_s);
        self.yaw_gsf.fuse_velocity(vel_w.xy(), vel_var);
        let Some((gsf_yaw, gsf_var)) = self.yaw_gsf.yaw() else {
            return false;
        };
        let disagreement = wrap_pi(gsf_yaw - yaw);
        let yaw_var = core.p[(ERR_ATT + 2, ERR_ATT + 2)];
        let reset = may_reset
            && gsf_var.sqrt() < MAX_AID_YAW_STD_RAD
            && disagreement.abs() > YAW_RESET_MIN_RAD
            && disagreement.powi(2) > 9.0 * (gsf_var + yaw_var);
        if reset {
            core.turn_yaw(disagreement, params);
            uncorrelate(&mut core.p, ERR_ATT + 2, gsf_var);
        }
        reset
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::UnitQuat;
    use crate::nav_filter::alignment::initial_covariance;
    use crate::nav_filter::nav_params::HeightSource;
    use crate::nav_filter::state::Nominal;

    #[test]
    fn a_hover_never_resets_the_yaw() {
        let params = NavParams::default();
        let q = UnitQuat::from_euler_angles(0.0, 0.0, 1.0);
        let mut core = ErrorStateFilter::new();
        let x = Nominal {
            q_wb: q,
            ..Nominal::default()
        };
        core.restart(x, initial_covariance(&params, HeightSource::Gps, &q, 1.0));
        let mut aid = HeadingAid::default();
        let hover = ImuInterval {
            f_w: Vec3::new(0.0, 0.0, -crate::math::GRAVITY_M_S2),
            yaw_rate: 0.0,
            dt_s: 1e-3,
        };
        for _ in 0..300 {
            for _ in 0..100 {
                aid.add(&hover);
            }
            assert!(!aid.aid(&Vec3::zeros(), 0.09, true, &mut core, &params));
        }
        assert_eq!(core.x.q_wb, q, "every hypothesis predicts a hover equally well");
        assert_eq!(aid.increments, HeadingAidIncrements::default(), "taken at every fix");
    }
}
