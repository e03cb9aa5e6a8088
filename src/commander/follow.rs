//! Follow-me (PX4's AUTO.FOLLOW_TARGET): FOLLOW_TARGET reports place a target; in the mode the
//! vehicle flies to the point [`FollowTarget::setpoint`] names, through the offboard limiter
//! with `FLW_TGT_MAX_VEL` as the speed cap, facing the target. Without a report for
//! [`TARGET_LOST_S`] it holds where it is (and follows again when reports resume).
//!
//! Live sticks adjust the follow as PX4's follow-target task lets them (they never take over
//! here): the throttle the height, the pitch stick the distance and the roll stick the angle,
//! each at its adjust speed (1.5 m/s, 2 m/s, 1.5 rad/s but never faster round the target than
//! `FLW_TGT_MAX_VEL`) through the POSCTL deadzone and expo, and only while the vehicle is within
//! half a second of that speed of the value it flies to, so the setting never runs away from it.

use crate::guidance::{FollowParams, FollowTarget, MotionLimits, SetpointLimiter, StickShaping, Sticks};
use crate::math::{wrap_pi, Vec3};

use super::landing::FlightDemand;
use super::Moment;

/// A target not reported for this long is lost [s].
pub const TARGET_LOST_S: f64 = 3.0;

/// Height change at full throttle [m/s] (PX4's follow-target task).
const HEIGHT_ADJUST_M_S: f64 = 1.5;
/// Distance change at full pitch stick [m/s].
const DISTANCE_ADJUST_M_S: f64 = 2.0;
/// Angle change at full roll stick [rad/s], at most `FLW_TGT_MAX_VEL` round the target.
const ANGLE_ADJUST_RAD_S: f64 = 1.5;
/// An adjustment applies while the vehicle is within this many seconds of its speed of the
/// adjusted value [s].
const ADJUST_WINDOW_S: f64 = 0.5;
/// Lower bound of the adjusted height and distance [m].
const ADJUST_MIN_M: f64 = 1.0;
/// Upper bound of the adjusted height and distance [m].
const ADJUST_MAX_M: f64 = 100.0;

/// What the sticks changed of the follow parameters since the mode was entered.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct FollowAdjust {
    /// Added to `FLW_TGT_HT` [m].
    height_m: f64,
    /// Added to `FLW_TGT_DST` [m].
    distance_m: f64,
    /// Added to `FLW_TGT_FA` [rad].
    angle_rad: f64,
}

impl FollowAdjust {
    /// `p` with the adjustments.
    fn applied(&self, p: &FollowParams) -> FollowParams {
        FollowParams {
            height_m: (p.height_m + self.height_m).clamp(ADJUST_MIN_M, ADJUST_MAX_M),
            distance_m: (p.distance_m + self.distance_m).clamp(ADJUST_MIN_M, ADJUST_MAX_M),
            angle_rad: wrap_pi(p.angle_rad + self.angle_rad),
            ..*p
        }
    }

    /// Moves the adjustments by the sticks over `dt_s` [s]; `flown` the parameters flown now,
    /// `height_error_m`, `distance_error_m` and `angle_error_rad` how far the vehicle is from
    /// them.
    fn step(&mut self, s: &Sticks, shaping: &StickShaping, flown: &FollowParams, errors: [f64; 3], dt_s: f64) {
        let (forward, right) = shaping.horizontal(s);
        let [height_error_m, distance_error_m, angle_error_rad] = errors;
        if height_error_m.abs() < HEIGHT_ADJUST_M_S * ADJUST_WINDOW_S {
            self.height_m += HEIGHT_ADJUST_M_S * shaping.climb(s) * dt_s;
        }
        if distance_error_m.abs() < DISTANCE_ADJUST_M_S * ADJUST_WINDOW_S {
            self.distance_m += DISTANCE_ADJUST_M_S * forward * dt_s;
        }
        if angle_error_rad.abs() < ANGLE_ADJUST_RAD_S * ADJUST_WINDOW_S {
            let rate = ANGLE_ADJUST_RAD_S.min(flown.max_speed_m_s / flown.distance_m.max(ADJUST_MIN_M));
            self.angle_rad = wrap_pi(self.angle_rad + rate * right * dt_s);
        }
    }
}

/// The target and the reference the mode flies.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Follow {
    /// The target, with the simulated time of its last report [s].
    target: Option<(FollowTarget, f64)>,
    /// The reference flown while following (`None` while holding).
    limiter: Option<SetpointLimiter>,
    /// What the sticks changed.
    adjust: FollowAdjust,
}

/// What one follow-me tick flies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum FollowCommand {
    /// Fly this.
    Fly(FlightDemand),
    /// The target was just lost: hold where the vehicle is.
    HoldHere,
    /// No target: fly the guidance there is (the hold).
    Wait,
}

impl Follow {
    /// A FOLLOW_TARGET report at `t_s` [s]: position `pos_w` [m], velocity `vel_w` [m/s],
    /// filtered with `p`.
    pub fn report(&mut self, pos_w: Vec3, vel_w: Vec3, t_s: f64, p: &FollowParams) {
        let target = match self.target {
            Some((mut target, _)) => {
                target.report(pos_w, vel_w, p);
                target
            }
            None => FollowTarget::new(pos_w, vel_w),
        };
        self.target = Some((target, t_s));
    }

    /// The mode is entered: the reference starts again from the vehicle, the sticks' changes
    /// are forgotten.
    pub fn restart(&mut self) {
        self.limiter = None;
        self.adjust = FollowAdjust::default();
    }

    /// One follow-me tick `now`, with home at `home_w` [m], the live `sticks` (if any) shaped
    /// by `shaping`, the follow settings `p` and the path limits at `FLW_TGT_MAX_VEL` `limits`:
    /// what to fly.
    pub fn command(
        &mut self,
        now: Moment,
        home_w: Vec3,
        sticks: Option<Sticks>,
        shaping: &StickShaping,
        p: &FollowParams,
        limits: impl FnOnce() -> MotionLimits,
    ) -> FollowCommand {
        let Moment { x, dt_s, t_s, .. } = now;
        let fresh = self.target.filter(|(_, heard_s)| t_s - heard_s < TARGET_LOST_S);
        let Some((mut target, heard_s)) = fresh else {
            return if self.limiter.take().is_some() {
                FollowCommand::HoldHere
            } else {
                FollowCommand::Wait
            };
        };
        let flown = self.adjust.applied(p);
        let raw = target.setpoint(x.pos_w, home_w, &flown);
        if let (Some(sticks), Some(point)) = (sticks, raw.pos_w) {
            let from_target = x.pos_w - target.pos_w;
            let point_from_target = point - target.pos_w;
            let errors = [
                point.z - x.pos_w.z,
                from_target.xy().norm() - flown.distance_m,
                wrap_pi(from_target.y.atan2(from_target.x) - point_from_target.y.atan2(point_from_target.x)),
            ];
            self.adjust.step(&sticks, shaping, &flown, errors, dt_s);
        }
        self.target = Some((target, heard_s));
        let limits = limits();
        let limiter = self.limiter.get_or_insert_with(|| SetpointLimiter::at(x));
        FollowCommand::Fly(FlightDemand::Flat(limiter.step(&raw, x, &limits, dt_s)))
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use super::*;
    use crate::control::VehicleState;
    use crate::math::euler_zyx;

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
    fn the_sticks_adjust_height_distance_and_angle_and_never_take_over() {
        use crate::guidance::Sticks;
        let mut s = Script::new(CommanderParams::default());
        s.airborne(5.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::FollowTarget)), Outcome::Accepted);
        let target = Vec3::new(20.0, 0.0, 0.0);
        let hold = |s: &mut Script, sticks: Sticks, seconds: f64| {
            for _ in 0..(seconds / super::super::script::DT_S).round() as usize {
                assert_eq!(s.request(Request::ManualControl(sticks)), Outcome::Accepted);
                assert_eq!(
                    s.request(Request::FollowTarget {
                        pos_w: target,
                        vel_w: Vec3::zeros()
                    }),
                    Outcome::Accepted
                );
                s.step();
            }
        };
        hold(&mut s, Sticks::CENTRED, 15.0);
        let settled = s.x.pos_w;
        let (d0, h0) = ((settled - target).xy().norm(), -settled.z);
        assert!(
            (d0 - 8.0).abs() < 0.1 && (h0 - 8.0).abs() < 0.1,
            "FLW_TGT_DST / _HT: {settled:?}"
        );
        let bearing = |p: Vec3| (p.y - target.y).atan2(p.x - target.x);
        let a0 = bearing(settled);
        // Throttle up 3 s, then centred: higher by about 1.5 m/s × 3 s.
        hold(
            &mut s,
            Sticks {
                throttle: 1.0,
                ..Sticks::CENTRED
            },
            3.0,
        );
        hold(&mut s, Sticks::CENTRED, 5.0);
        assert!(-s.x.pos_w.z - h0 > 3.0, "height {}", -s.x.pos_w.z);
        // Pitch forward 3 s: farther by about 2 m/s × 3 s.
        hold(
            &mut s,
            Sticks {
                pitch: 1.0,
                ..Sticks::CENTRED
            },
            3.0,
        );
        hold(&mut s, Sticks::CENTRED, 5.0);
        let d1 = (s.x.pos_w - target).xy().norm();
        assert!(d1 - d0 > 3.0 && d1 - d0 < 6.5, "distance {d1} from {d0}");
        // Roll right 3 s: round the target clockwise, no faster than FLW_TGT_MAX_VEL allows.
        hold(
            &mut s,
            Sticks {
                roll: 1.0,
                ..Sticks::CENTRED
            },
            3.0,
        );
        hold(&mut s, Sticks::CENTRED, 5.0);
        let turned = crate::math::wrap_pi(bearing(s.x.pos_w) - a0);
        let most = 3.0 * 5.0 / d1;
        assert!(
            turned > 0.5 * most && turned < most + 0.05,
            "turned {turned} rad (at most {most})"
        );
        assert_eq!(
            s.c.mode(),
            FlightMode::FollowTarget,
            "the sticks adjust, they never take over"
        );
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

    #[test]
    fn a_target_is_followed_while_reported_then_held_once_lost() {
        let p = CommanderParams::default();
        let x = VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(0.0, 0.0, -5.0),
            vel_w: Vec3::zeros(),
            r_wb: crate::math::Mat3::identity(),
            omega_b: Vec3::zeros(),
        };
        let mut f = Follow::default();
        let limits = || MotionLimits::default();
        let shaping = p.manual.shaping;
        let tick = |f: &mut Follow, t_s| {
            let now = Moment {
                x: &x,
                yaw_rad: 0.0,
                dt_s: 0.01,
                t_s,
            };
            f.command(now, Vec3::zeros(), None, &shaping, &p.follow, limits)
        };
        assert_eq!(tick(&mut f, 0.0), FollowCommand::Wait, "no target");
        f.report(Vec3::new(20.0, 0.0, 0.0), Vec3::zeros(), 1.0, &p.follow);
        assert!(matches!(tick(&mut f, 1.0), FollowCommand::Fly(FlightDemand::Flat(_))));
        assert!(matches!(
            tick(&mut f, 1.0 + TARGET_LOST_S - 0.01),
            FollowCommand::Fly(_)
        ));
        assert_eq!(tick(&mut f, 1.0 + TARGET_LOST_S), FollowCommand::HoldHere, "lost: hold");
        assert_eq!(
            tick(&mut f, 2.0 + TARGET_LOST_S),
            FollowCommand::Wait,
            "then the hold flies"
        );
    }
}
