//! Follow-me (PX4's AUTO.FOLLOW_TARGET): FOLLOW_TARGET reports place a target; in the mode the
//! vehicle flies to the point [`FollowTarget::setpoint`] names, through the offboard limiter
//! with `FLW_TGT_MAX_VEL` as the speed cap, facing the target. Without a report for
//! [`TARGET_LOST_S`] it holds where it is (and follows again when reports resume).

use crate::control::VehicleState;
use crate::math::{euler_zyx, Vec3};
use crate::navigation::{FollowTarget, Guidance, MotionLimits, SetpointLimiter};

use super::landing::Command;
use super::Commander;

/// A target not reported for this long is lost [s].
pub const TARGET_LOST_S: f64 = 3.0;

/// The target and the reference the mode flies.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Follow {
    /// The target, with the simulated time of its last report [s].
    pub target: Option<(FollowTarget, f64)>,
    /// The reference flown while following (`None` while holding).
    pub limiter: Option<SetpointLimiter>,
}

impl Commander {
    /// A FOLLOW_TARGET report: position `pos_w` [m], velocity `vel_w` [m/s].
    pub(super) fn follow_report(&mut self, pos_w: Vec3, vel_w: Vec3, t_s: f64) {
        let p = self.params.follow;
        let target = match self.follow.target {
            Some((mut target, _)) => {
                target.report(pos_w, vel_w, &p);
                target
            }
            None => FollowTarget::new(pos_w, vel_w),
        };
        self.follow.target = Some((target, t_s));
    }

    /// One follow-me tick, `dt_s` [s] after the last: what to fly, or `None` to hold (no
    /// target, or lost).
    pub(super) fn follow_command(&mut self, x: &VehicleState, dt_s: f64, t_s: f64) -> Option<Command> {
        let fresh = self.follow.target.filter(|(_, heard_s)| t_s - heard_s < TARGET_LOST_S);
        let Some((mut target, heard_s)) = fresh else {
            if self.follow.limiter.take().is_some() {
                self.guidance = Guidance::Hold {
                    pos_w: x.pos_w,
                    yaw_rad: euler_zyx(&x.r_wb).z,
                };
            }
            return None;
        };
        let raw = target.setpoint(x.pos_w, self.home_w, &self.params.follow);
        self.follow.target = Some((target, heard_s));
        let limits = MotionLimits {
            horizontal_m_s: self.params.follow.max_speed_m_s.min(self.params.motion.horizontal_m_s),
            ..self.params.motion
        };
        let limiter = self.follow.limiter.get_or_insert_with(|| SetpointLimiter::at(x));
        Some(Command::Flat(limiter.step(&raw, x, &limits, dt_s)))
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use super::*;

    fn report(s: &mut Script, north_m: f64, east_m: f64, vel_w: Vec3) {
        let pos_w = Vec3::new(north_m, east_m, 0.0);
        assert_eq!(s.request(Request::FollowTarget { pos_w, vel_w }), Outcome::Accepted);
    }

    #[test]
    fn the_vehicle_follows_a_walking_target_from_behind_and_holds_when_it_is_lost() {
        let mut s = Script::new(CommanderParams::default());
        assert_eq!(
            s.request(Request::SetMode(FlightMode::FollowTarget)),
            Outcome::TemporarilyRejected("Mode AUTO.FOLLOW_TARGET: not in the air".into())
        );
        s.airborne(5.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::FollowTarget)), Outcome::Accepted);
        s.fly(2.0);
        let here = s.x.pos_w;
        assert!((s.x.pos_w - here).norm() < 1e-9, "no target: it holds");
        // The target walks east at 1.5 m/s from 20 m north; reports at 1 Hz.
        let walk = Vec3::new(0.0, 1.5, 0.0);
        for k in 0..40 {
            report(&mut s, 20.0, 1.5 * f64::from(k), walk);
            s.fly(1.0);
        }
        let target = Vec3::new(20.0, 1.5 * 39.0, 0.0);
        let behind = target - Vec3::new(0.0, 8.0, 0.0);
        let d = s.x.pos_w - behind;
        assert!(d.xy().norm() < 2.0, "8 m behind it (FLW_TGT_FA 180): {:?}", s.x.pos_w);
        assert!((s.x.pos_w.z + 8.0).abs() < 1e-6, "FLW_TGT_HT above home");
        let yaw = euler_zyx(&s.x.r_wb).z;
        assert!(
            (yaw - std::f64::consts::FRAC_PI_2).abs() < 0.1,
            "facing the target: {yaw}"
        );
        s.fly(TARGET_LOST_S + 0.5);
        let lost_at = s.x.pos_w;
        s.fly(3.0);
        assert!((s.x.pos_w - lost_at).norm() < 1e-9, "lost: holds");
        assert_eq!(s.c.mode(), FlightMode::FollowTarget);
    }

    #[test]
    fn the_speed_is_capped_at_flw_tgt_max_vel() {
        let mut params = CommanderParams::default();
        params.follow.max_speed_m_s = 2.0;
        let mut s = Script::new(params);
        s.airborne(5.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::FollowTarget)), Outcome::Accepted);
        let mut fastest: f64 = 0.0;
        for _ in 0..20 {
            report(&mut s, 100.0, 0.0, Vec3::zeros());
            for _ in 0..100 {
                s.step();
                fastest = fastest.max(s.x.vel_w.xy().norm());
            }
        }
        assert!(fastest <= 2.0 + 1e-9 && fastest > 1.9, "{fastest}");
    }
}
