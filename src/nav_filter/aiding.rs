//! Horizontal aiding, dead reckoning and the position hold used while nothing aids
//! (docs/navigation_filter.md §12, eqs. (12.1)–(12.2)).

use crate::math::Vec3;

use super::covariance::{fuse_group, ScalarObservation};
use super::error_state::ErrorStateFilter;
use super::fusion::Fusion;
use super::nav_params::{NavParams, GPS_CTRL_FUSED, IMU_CTRL_GRAVITY};
use super::state::ERR_POS;

/// Time without horizontal aiding after which the status reports dead reckoning [s]
/// (docs/navigation_filter.md §12).
pub const DEAD_RECKONING_AFTER_S: f64 = 1.0;
/// Period of the position-hold pseudo-measurement [s] (docs/navigation_filter.md §12, eq. (12.2)).
const HOLD_PERIOD_S: f64 = 0.2;

/// The aiding decision: when GNSS last aided the horizontal state, whether its next fix resets
/// instead of fusing, and the position hold while nothing aids
/// (docs/navigation_filter.md §6, §12).
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

    /// Notes the outcome of a GNSS velocity at `now_s` [s].
    pub fn note_velocity(&mut self, velocity: &Fusion, now_s: f64) {
        if velocity.accepted() {
            self.last_vel_s = Some(now_s);
            self.last_aiding_s = Some(now_s);
        }
    }

    /// Notes the outcome of a GNSS horizontal position at `now_s` [s].
    pub fn note_horizontal(&mut self, horizontal: &Fusion, now_s: f64) {
        if horizontal.accepted() {
            self.last_pos_s = Some(now_s);
            self.last_aiding_s = Some(now_s);
        }
    }

    /// A known state at `t_s` [s] counts as an aiding: the first fixes are fused into it, not
    /// reset to (docs/navigation_filter.md §11).
    pub fn known_state_at(&mut self, t_s: f64) {
        self.last_aiding_s = Some(t_s);
        self.last_pos_s = Some(t_s);
        self.last_vel_s = Some(t_s);
    }

    /// Whether GNSS position or velocity corrected the state within the last
    /// `DEAD_RECKONING_AFTER_S` at `now_s` [s] and GNSS fusion is on (`gps_ctrl`, PX4's
    /// "horizontal aiding active") (docs/navigation_filter.md §20, eq. (20.2)).
    pub fn horizontal_aiding_active(&self, now_s: f64, gps_ctrl: u8) -> bool {
        gps_ctrl & GPS_CTRL_FUSED != 0 && self.last_aiding_s.is_some_and(|t| now_s - t <= DEAD_RECKONING_AFTER_S)
    }

    /// While nothing has aided for `noaid_timeout_s` (or never), fuses the held horizontal
    /// position with noise `noaid_noise_m` every `HOLD_PERIOD_S`, which bounds the velocity and
    /// tilt errors (PX4's fake position fusion) (docs/navigation_filter.md §12, eq. (12.2)).
    /// With gravity-vector fusion on (`EKF2_IMU_CTRL` bit 2) the hold runs only while the vehicle
    /// is at rest: in motion the gravity vector levels the filter instead, as in PX4
    /// (docs/navigation_filter.md §20); `at_rest` says whether the IMU sees the vehicle at rest.
    pub fn update_position_hold(&mut self, core: &mut ErrorStateFilter, params: &NavParams, at_rest: bool) {
        let now = core.t_s;
        let gravity_levels = params.imu_ctrl & IMU_CTRL_GRAVITY != 0 && !at_rest;
        if gravity_levels || !Self::timed_out(self.last_aiding_s, now, params.noaid_timeout_s) {
            self.hold_pos_w = None;
            self.last_hold_s = None;
            return;
        }
        let hold = *self.hold_pos_w.get_or_insert(core.x.pos_w);
        if self.last_hold_s.is_some_and(|t| now - t < HOLD_PERIOD_S) {
            return;
        }
        self.last_hold_s = Some(now);
        let r = params.noaid_noise_m.powi(2);
        let group = [
            ScalarObservation::of_state(ERR_POS, hold.x - core.x.pos_w.x, r),
            ScalarObservation::of_state(ERR_POS + 1, hold.y - core.x.pos_w.y, r),
        ];
        if let Some(dx) = fuse_group(&mut core.p, &group, None).dx {
            core.apply(&dx, params);
        }
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
    fn aiding_times_out_and_is_active_only_with_gnss_fusion_on() {
        assert!(Aiding::timed_out(None, 0.0, 5.0));
        assert!(!Aiding::timed_out(Some(1.0), 6.0, 5.0));
        assert!(Aiding::timed_out(Some(1.0), 6.5, 5.0));
        let mut a = Aiding::default();
        a.note_velocity(&Fusion::skipped(super::super::fusion::SkipReason::Quality), 1.0);
        assert_eq!(a, Aiding::default());
        a.known_state_at(2.0);
        assert!(a.horizontal_aiding_active(2.5, GPS_CTRL_FUSED));
        assert!(!a.horizontal_aiding_active(2.5, 0));
        assert!(!a.horizontal_aiding_active(3.5, GPS_CTRL_FUSED));
    }

    #[test]
    fn the_position_is_held_while_nothing_aids_and_released_when_moving() {
        let params = NavParams::default();
        let mut core = ErrorStateFilter::new();
        let p = initial_covariance(&params, HeightSource::Gps, &UnitQuat::identity(), 1.0);
        core.restart(Nominal::default(), p);
        let mut a = Aiding::default();
        a.update_position_hold(&mut core, &params, true);
        assert_eq!(a.hold_pos_w, Some(Vec3::zeros()));
        assert!(core.p[(ERR_POS, ERR_POS)] < p[(ERR_POS, ERR_POS)], "the hold was fused");
        let after_first = core.p;
        a.update_position_hold(&mut core, &params, true);
        assert_eq!(core.p, after_first, "not again within the hold period");
        a.update_position_hold(&mut core, &params, false);
        assert_eq!(a.hold_pos_w, None, "in motion the gravity vector levels instead");
        a.known_state_at(0.0);
        a.update_position_hold(&mut core, &params, true);
        assert_eq!(a.hold_pos_w, None, "aided");
    }
}
