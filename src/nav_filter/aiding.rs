//! Horizontal aiding, dead reckoning and the position hold used while nothing aids
//! (docs/navigation_filter.md §12, eqs. (12.1)–(12.2)).

use crate::math::Vec3;

use super::covariance::{fuse_group, ScalarObservation};
use super::params::IMU_CTRL_GRAVITY;
use super::state::ERR_POS;
use super::NavFilter;

/// Time without horizontal aiding after which the status reports dead reckoning [s]
/// (docs/navigation_filter.md §12).
pub const DEAD_RECKONING_AFTER_S: f64 = 1.0;
/// Period of the position-hold pseudo-measurement [s] (docs/navigation_filter.md §12, eq. (12.2)).
const HOLD_PERIOD_S: f64 = 0.2;

/// Times of the last horizontal aiding and the position hold.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Aiding {
    /// Last fused GNSS position or velocity [s].
    pub last_aiding_s: Option<f64>,
    /// Last fused (or reset) GNSS horizontal position [s].
    pub last_pos_s: Option<f64>,
    /// Last fused (or reset) GNSS velocity [s].
    pub last_vel_s: Option<f64>,
    /// Where the position is held while nothing aids (local NED [m]).
    pub hold_pos_w: Option<Vec3>,
    /// Last position-hold fusion [s].
    last_hold_s: Option<f64>,
}

impl Aiding {
    /// Whether `last` is missing or older than `timeout_s` [s] at `now_s` [s].
    pub fn timed_out(last: Option<f64>, now_s: f64, timeout_s: f64) -> bool {
        last.is_none_or(|t| now_s - t > timeout_s)
    }
}

impl NavFilter {
    /// While nothing has aided for `noaid_timeout_s` (or never), fuses the held horizontal
    /// position with noise `noaid_noise_m` every `HOLD_PERIOD_S`, which bounds the velocity and
    /// tilt errors (PX4's fake position fusion) (docs/navigation_filter.md §12, eq. (12.2)).
    /// With gravity-vector fusion on (`EKF2_IMU_CTRL` bit 2) the hold runs only while the vehicle
    /// is at rest: in motion the gravity vector levels the filter instead, as in PX4
    /// (docs/navigation_filter.md §20).
    pub(super) fn update_position_hold(&mut self) {
        let now = self.t_s;
        let gravity_levels = self.params.imu_ctrl & IMU_CTRL_GRAVITY != 0 && !self.gravity.at_rest();
        if gravity_levels || !Aiding::timed_out(self.aiding.last_aiding_s, now, self.params.noaid_timeout_s) {
            self.aiding.hold_pos_w = None;
            self.aiding.last_hold_s = None;
            return;
        }
        let hold = *self.aiding.hold_pos_w.get_or_insert(self.x.pos_w);
        if self.aiding.last_hold_s.is_some_and(|t| now - t < HOLD_PERIOD_S) {
            return;
        }
        self.aiding.last_hold_s = Some(now);
        let r = self.params.noaid_noise_m.powi(2);
        let group = [
            ScalarObservation::of_state(ERR_POS, hold.x - self.x.pos_w.x, r),
            ScalarObservation::of_state(ERR_POS + 1, hold.y - self.x.pos_w.y, r),
        ];
        if let Some(dx) = fuse_group(&mut self.p, &group, None).dx {
            self.apply(&dx);
        }
    }
}
