//! AUTO.RTL's phases: climb to the return altitude (or stay higher), fly over the destination
//! `RTL_TYPE` chooses (home or a rally point) at that height, then descend and land there.
//!
//! The return altitude, as PX4's multicopter return computes it, with d the horizontal distance
//! to the destination and h heights above it:
//! ```text
//! d ≤ NAV_ACC_RAD:  h = 2 d
//! else:             h = RTL_RETURN_ALT, lowered to d / tan(RTL_CONE_ANG) when d ≤ RTL_MIN_DIST,
//!                   and at least 2 NAV_ACC_RAD
//! h_return = max(h_now, min(h, RTL_RETURN_ALT))     (RTL_CONE_ANG 0: max(h_now, RTL_RETURN_ALT))
//! ```
//! so a return asked right above home lands where it is instead of climbing 60 m first.

use crate::control::VehicleState;
use crate::math::Vec3;

use super::Commander;
use crate::navigation::Guidance;

/// Where a return is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RtlPhase {
    /// Climbing to the return altitude.
    Climb,
    /// Flying over the destination.
    Return,
    /// Descending to land at the destination.
    Descend,
}

impl Commander {
    /// The height [m] (up, local NED origin) a return from `x` climbs to: the cone rule above,
    /// about the destination `RTL_TYPE` chooses.
    pub(super) fn rtl_return_height(&self, x: &VehicleState) -> f64 {
        let to = self.rtl_destination(&x.pos_w);
        let (dest_up, now_up) = (-to.z, -x.pos_w.z);
        let d = (x.pos_w.xy() - to.xy()).norm();
        let (ret, accept) = (self.params.rtl_return_alt_m, self.params.mission.accept_m);
        let cone = self.params.rtl_cone_rad;
        let above = if cone <= 0.0 {
            ret
        } else if d <= accept {
            2.0 * d
        } else {
            let mut h = ret;
            if d <= self.params.rtl_min_dist_m {
                h = h.min(d / cone.tan());
            }
            h.max(2.0 * accept).min(ret)
        };
        now_up.max(dest_up + above)
    }

    /// One AUTO.RTL tick: when a phase's path is flown, the next phase starts from here.
    pub(super) fn advance_rtl(&mut self, x: &VehicleState, yaw: f64, t_s: f64) {
        // Entered on the ground: nothing to return from (PX4 does not take off for a return).
        if !self.guidance.finished(t_s) || self.guidance == Guidance::Idle {
            return;
        }
        match self.rtl_phase {
            RtlPhase::Climb => {
                self.rtl_phase = RtlPhase::Return;
                let to = self.rtl_destination(&x.pos_w);
                let over = Vec3::new(to.x, to.y, x.pos_w.z);
                self.guidance = self.path_to(x, over, yaw, self.cruise_speed(), t_s);
            }
            RtlPhase::Return => {
                self.rtl_phase = RtlPhase::Descend;
                self.guidance = self.descend(x, yaw, t_s);
            }
            RtlPhase::Descend => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::{Script, GROUND_Z_M};
    use super::super::{CommanderParams, Event, FlightMode, Outcome, Request};
    use crate::math::Vec3;
    use crate::navigation::RallyPoints;

    fn params() -> CommanderParams {
        CommanderParams {
            rtl_return_alt_m: 15.0,
            ..Default::default()
        }
    }

    fn reposition(s: &mut Script, north_m: Option<f64>, east_m: Option<f64>, down_m: Option<f64>) {
        let to = Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        };
        assert_eq!(s.request(to), Outcome::Accepted);
        s.fly(20.0);
    }

    #[test]
    fn rtl_climbs_to_rtl_return_alt_returns_home_and_lands() {
        let mut s = Script::new(params());
        s.airborne(3.0);
        reposition(&mut s, Some(20.0), Some(10.0), None);
        s.events.clear();
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::ReturnToLaunch);
        // Straight up first, to the return altitude above home.
        let start_xy = Vec3::new(20.0, 10.0, 0.0).xy();
        let mut climbed_in_place = true;
        assert!(s.fly_until(30.0, |s| {
            climbed_in_place &= (s.x.pos_w.xy() - start_xy).norm() < 1e-9;
            s.x.pos_w.z < -15.0 + 1e-6
        }));
        assert!(climbed_in_place, "climbs before it turns home");
        let mut highest: f64 = 0.0;
        let landed = s.fly_until(200.0, |s| {
            highest = highest.max(-s.x.pos_w.z);
            !s.c.armed()
        });
        assert!(landed, "returned, landed and disarmed: {:?}", s.events);
        assert!((highest - 15.0).abs() < 1e-6, "returned at RTL_RETURN_ALT: {highest} m");
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
            "home is nearer: {:?}",
            s.x.pos_w
        );
        assert_eq!(s.events, vec![Event::Landed, Event::Disarmed("landed")]);
    }

    #[test]
    fn close_to_home_the_cone_lowers_the_return_altitude() {
        // RTL_RETURN_ALT 15, cone 45°, RTL_MIN_DIST 10, NAV_ACC_RAD 2; 3 m up.
        for (north_m, expected_m) in [(0.0, 3.0), (1.5, 3.0), (8.0, 8.0), (30.0, 15.0)] {
            let mut s = Script::new(params());
            s.airborne(3.0);
            if north_m > 0.0 {
                reposition(&mut s, Some(north_m), None, None);
            }
            assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
            let mut highest: f64 = 0.0;
            assert!(s.fly_until(200.0, |s| {
                highest = highest.max(-s.x.pos_w.z);
                !s.c.armed()
            }));
            assert!(
                (highest - expected_m).abs() < 1e-3,
                "{north_m} m out: climbed to {highest} m"
            );
            assert!(s.x.pos_w.xy().norm() < 1e-3, "landed at home: {:?}", s.x.pos_w);
        }
    }

    #[test]
    fn a_return_asked_on_the_ground_does_not_take_off() {
        let mut s = Script::new(params());
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        s.fly(5.0);
        assert!(
            (s.x.pos_w.z - GROUND_Z_M).abs() < 1e-9,
            "stayed on the ground: {:?}",
            s.x.pos_w
        );
        assert!(s.until_disarmed(15.0), "auto-disarm without a take-off: {:?}", s.events);
    }

    #[test]
    fn rtl_with_a_rally_point_nearer_than_home_lands_there() {
        let mut s = Script::new(params());
        let rally = RallyPoints {
            points_w: vec![Vec3::new(40.0, 10.0, 0.0), Vec3::new(-60.0, 0.0, 0.0)],
        };
        assert_eq!(s.request(Request::SetRallyPoints(rally)), Outcome::Accepted);
        s.airborne(3.0);
        reposition(&mut s, Some(30.0), Some(0.0), None);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert!(s.until_disarmed(200.0), "{:?}", s.events);
        let landed_at = Vec3::new(40.0, 10.0, GROUND_Z_M);
        assert!((s.x.pos_w - landed_at).norm() < 1e-6, "{:?}", s.x.pos_w);
        // From near home, home is closer: it lands at home.
        s.airborne(3.0);
        reposition(&mut s, Some(-5.0), Some(5.0), None);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert!(s.until_disarmed(200.0));
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
            "home is nearer: {:?}",
            s.x.pos_w
        );
    }

    #[test]
    fn rtl_above_the_return_altitude_keeps_its_height_and_lands_at_a_moved_home() {
        let mut s = Script::new(params());
        s.airborne(3.0);
        reposition(&mut s, Some(5.0), Some(5.0), Some(-20.0));
        assert_eq!(
            s.request(Request::SetHome(Some(Vec3::new(-4.0, 2.0, 0.0)))),
            Outcome::Accepted
        );
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        let home_xy = Vec3::new(-4.0, 2.0, 0.0).xy();
        let mut heights = (f64::MAX, 0.0_f64);
        let over_home = s.fly_until(60.0, |s| {
            heights = (heights.0.min(-s.x.pos_w.z), heights.1.max(-s.x.pos_w.z));
            (s.x.pos_w.xy() - home_xy).norm() < 1e-6
        });
        assert!(over_home);
        assert!(
            (heights.0 - 20.0).abs() < 1e-6 && (heights.1 - 20.0).abs() < 1e-6,
            "{heights:?}"
        );
        assert!(s.until_disarmed(120.0));
        assert!(
            (s.x.pos_w - Vec3::new(-4.0, 2.0, GROUND_Z_M)).norm() < 1e-6,
            "{:?}",
            s.x.pos_w
        );
    }
}
