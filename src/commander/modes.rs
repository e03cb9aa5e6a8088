//! Mode switches and each mode's guidance: AUTO.TAKEOFF climbs to its target and hands over to
//! AUTO.LOITER, AUTO.LAND descends (`MPC_LAND_ALT1` / `MPC_LAND_ALT2` profile), AUTO.RTL starts
//! its climb, AUTO.MISSION starts its run, the hold modes hold (idle on the ground). Paths fly at
//! the cruise speed (`MPC_XY_CRUISE` or DO_CHANGE_SPEED's), capped at `MPC_XY_VEL_MAX`.

use crate::control::VehicleState;
use crate::math::{euler_zyx, Vec3};
use crate::navigation::{DescentProfile, Guidance, MotionLimits, Track, TrackLeg};

use super::follow::FollowAdjust;
use super::mission_run::MissionState;
use super::rtl::RtlPhase;
use super::{Commander, Event, FlightMode, Outcome};

/// Take-off is complete within this distance of the target [m].
const TAKEOFF_ACCEPT_M: f64 = 0.2;

impl Commander {
    /// Horizontal speed of the AUTO modes [m/s]: DO_CHANGE_SPEED's, else `MPC_XY_CRUISE`.
    pub(super) fn cruise_speed(&self) -> f64 {
        self.speed_override.unwrap_or(self.params.cruise_speed_m_s)
    }

    /// AUTO path limits for a horizontal speed of `horizontal_m_s` [m/s], capped at
    /// `MPC_XY_VEL_MAX`; vertical speeds `MPC_Z_V_AUTO_UP` / `_DN` within `MPC_Z_VEL_MAX_UP` /
    /// `_DN`; every other limit as set.
    pub(super) fn limits(&self, horizontal_m_s: f64) -> MotionLimits {
        let (m, auto) = (&self.params.motion, &self.params.auto_vertical);
        MotionLimits {
            horizontal_m_s: horizontal_m_s.min(m.horizontal_m_s),
            up_m_s: auto.up_m_s.min(m.up_m_s),
            down_m_s: auto.down_m_s.min(m.down_m_s),
            ..*m
        }
    }

    /// The limits of a take-off climb at `height_m` [m] above the ground, as PX4's AUTO
    /// take-off: below `MPC_LAND_ALT1` at `MPC_TKO_SPEED`, reached in `MPC_TKO_RAMP_T`; above it
    /// as any AUTO path.
    fn takeoff_limits(&self, height_m: f64) -> MotionLimits {
        let limits = self.limits(self.cruise_speed());
        let auto = &self.params.auto_vertical;
        if height_m >= self.params.land_alt1_m {
            return limits;
        }
        let speed = auto.takeoff_m_s.min(limits.up_m_s);
        MotionLimits {
            up_m_s: speed,
            // A ramp time of 0 turns the ramp off (PX4).
            acc_up_m_s2: match auto.takeoff_ramp_s {
                ramp if ramp > 0.0 => limits.acc_up_m_s2.min(speed / ramp),
                _ => limits.acc_up_m_s2,
            },
            ..limits
        }
    }

    /// A take-off climb from where the vehicle is to `to_w` [m] at heading `yaw` [rad] (PX4's
    /// AUTO take-off speeds, [`Self::takeoff_limits`], kept as it climbs by [`Self::pace_climb`]).
    pub(super) fn climb_to(&self, x: &VehicleState, to_w: Vec3, yaw: f64, t_s: f64) -> Guidance {
        let leg = TrackLeg {
            target_w: to_w,
            next_w: None,
            accept_m: self.params.mission.accept_m,
            yaw_rad: yaw,
            cruise_m_s: self.cruise_speed(),
            corner_gain: self.params.mission.corner_gain,
        };
        let limits = self.takeoff_limits(self.height_above_ground(x));
        Guidance::Track(Track::new(x.pos_w, x.vel_w, yaw, t_s, leg, limits))
    }

    /// Keeps a take-off climb's speeds those of its height (below or above `MPC_LAND_ALT1`).
    pub(super) fn pace_climb(&mut self, x: &VehicleState) {
        if !self.climbing_out {
            return;
        }
        let limits = self.takeoff_limits(self.height_above_ground(x));
        if let Guidance::Track(track) = &mut self.guidance {
            track.set_limits(limits);
        }
    }

    /// Height of `x` above the ground the land detector last touched, else above home [m].
    fn height_above_ground(&self, x: &VehicleState) -> f64 {
        self.detector.ground_z_m().unwrap_or(self.home_w.z) - x.pos_w.z
    }

    /// A path at `speed_m_s` [m/s] from where the vehicle is to `to_w` [m], ending at heading
    /// `to_yaw_rad` [rad] (turned the short way within `MPC_YAWRAUTO_MAX`).
    pub(super) fn path_to(&self, x: &VehicleState, to_w: Vec3, to_yaw_rad: f64, speed_m_s: f64, t_s: f64) -> Guidance {
        let yaw = euler_zyx(&x.r_wb).z;
        Guidance::path(x.pos_w, to_w, yaw, to_yaw_rad, &self.limits(speed_m_s), t_s)
    }

    /// A landing descent from where the vehicle is, at heading `yaw` [rad]: `MPC_Z_V_AUTO_DN`
    /// above `MPC_LAND_ALT1`, slowing to `MPC_LAND_SPEED` below `MPC_LAND_ALT2`.
    pub(super) fn descend(&self, x: &VehicleState, yaw: f64, t_s: f64) -> Guidance {
        Guidance::Descend {
            xy_w: x.pos_w,
            yaw_rad: yaw,
            z_start_m: x.pos_w.z,
            start_s: t_s,
            start_down_m_s: x.vel_w.z,
            profile: DescentProfile {
                fast_m_s: self.limits(0.0).down_m_s,
                land_m_s: self.params.land_speed_m_s,
                slow_from_m: self.params.land_alt1_m,
                land_from_m: self.params.land_alt2_m,
                acc_m_s2: self.params.motion.acc_down_m_s2,
            },
        }
    }

    /// A requested mode switch: AUTO.MISSION needs a mission, OFFBOARD a live setpoint stream,
    /// the stick modes but POSCTL live sticks, orbit, follow-me and GOTO the air (GOTO chosen so,
    /// without a target, holds where it is);
    /// AUTO.TAKEOFF without a target (or in the air) climbs to `MIS_TAKEOFF_ALT` from here.
    pub(super) fn set_mode(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64) -> Outcome {
        if let Some(refusal) = self.stick_mode_refusal(mode, t_s, false) {
            return refusal;
        }
        if let Some(refusal) = self.navigation_refusal(mode, false) {
            return refusal;
        }
        if mode != FlightMode::Land {
            self.blind_descent = false;
        }
        // The pilot chose a mode: a failsafe waiting in its hold gives way (PX4).
        self.delayed_failsafe = None;
        match mode {
            FlightMode::Mission if self.mission.mission.is_empty() => {
                Outcome::TemporarilyRejected("Mode AUTO.MISSION: no mission".into())
            }
            FlightMode::Offboard if !self.offboard_alive(t_s) => {
                Outcome::TemporarilyRejected("Mode OFFBOARD: no setpoint stream".into())
            }
            FlightMode::Orbit | FlightMode::FollowTarget | FlightMode::Goto if !self.in_air() => {
                Outcome::TemporarilyRejected(format!("Mode {}: not in the air", mode.name()))
            }
            FlightMode::Takeoff if self.takeoff_target_w.is_none() || self.in_air() => {
                let h = self.params.takeoff_alt_m;
                self.takeoff_target_w = Some(Vec3::new(x.pos_w.x, x.pos_w.y, -h));
                self.enter(mode, x, t_s);
                Outcome::Accepted
            }
            _ => {
                self.enter(mode, x, t_s);
                Outcome::Accepted
            }
        }
    }

    /// Switches to `mode` and sets its guidance from the current state.
    pub(super) fn enter(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64) {
        if self.mode == FlightMode::Mission && mode != FlightMode::Mission && self.mission.state == MissionState::Active
        {
            self.mission.state = MissionState::Paused;
        }
        self.mode = mode;
        self.climbing_out = false;
        self.offboard.limiter = None;
        self.manual.reference = None;
        self.manual.heading_rad = None;
        if mode != FlightMode::Orbit {
            self.orbit = None;
        }
        self.follow.limiter = None;
        self.follow.adjust = FollowAdjust::default();
        let yaw = euler_zyx(&x.r_wb).z;
        let on_ground = !self.in_air();
        let hold = Guidance::Hold {
            pos_w: x.pos_w,
            yaw_rad: yaw,
        };
        self.guidance = if !self.armed {
            Guidance::Idle
        } else {
            match mode {
                FlightMode::Takeoff => {
                    let target = self
                        .takeoff_target_w
                        .unwrap_or(x.pos_w - Vec3::new(0.0, 0.0, self.params.takeoff_alt_m));
                    self.climbing_out = true;
                    self.climb_to(x, target, yaw, t_s)
                }
                FlightMode::Land => self.descend(x, yaw, t_s),
                FlightMode::Orbit if !on_ground => self.orbit_approach(x, t_s),
                // PX4 never takes off for a return: landed, AUTO.RTL idles ("for safety reasons").
                FlightMode::ReturnToLaunch if on_ground => Guidance::Idle,
                FlightMode::ReturnToLaunch => {
                    self.rtl_phase = RtlPhase::Climb;
                    let z = -self.rtl_return_height(x);
                    self.path_to(x, Vec3::new(x.pos_w.x, x.pos_w.y, z), yaw, self.cruise_speed(), t_s)
                }
                FlightMode::Mission => {
                    // The mission's first tick sets the item's guidance.
                    self.mission.start();
                    if on_ground {
                        Guidance::Idle
                    } else {
                        hold
                    }
                }
                // Armed on the ground in a hold mode: motors idle until a take-off.
                _ if on_ground => Guidance::Idle,
                _ => hold,
            }
        };
    }

    /// One AUTO.TAKEOFF tick: once the climb is over within [`TAKEOFF_ACCEPT_M`] of the target,
    /// hold there in AUTO.LOITER.
    pub(super) fn complete_takeoff(&mut self, x: &VehicleState, yaw: f64, t_s: f64, events: &mut Vec<Event>) {
        let near = self
            .takeoff_target_w
            .is_none_or(|p| (x.pos_w - p).norm() < TAKEOFF_ACCEPT_M);
        if self.guidance.finished(t_s) && near {
            self.mode = FlightMode::Loiter;
            self.climbing_out = false;
            self.guidance = Guidance::Hold {
                pos_w: self.takeoff_target_w.unwrap_or(x.pos_w),
                yaw_rad: yaw,
            };
            events.push(Event::ModeChanged(FlightMode::Loiter));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::{Script, GROUND_Z_M};
    use super::super::{CommanderParams, Event, FlightMode, LandedState, Outcome, Request};
    use crate::math::Vec3;

    #[test]
    fn takeoff_climbs_to_its_height_then_holds_there_in_auto_loiter() {
        let mut s = Script::new(CommanderParams::default());
        assert_eq!(s.request(Request::Takeoff { height_m: Some(5.0) }), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Takeoff);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        assert!(s.fly_until(10.0, |s| s.c.landed_state() == LandedState::Takeoff));
        assert!(s.fly_until(20.0, |s| s.c.mode() == FlightMode::Loiter));
        assert!((s.x.pos_w - Vec3::new(0.0, 0.0, -5.0)).norm() < 0.2, "{:?}", s.x.pos_w);
        assert_eq!(s.c.landed_state(), LandedState::InAir);
        let airborne = s.events.iter().position(|e| *e == Event::Airborne);
        let loiter = s
            .events
            .iter()
            .position(|e| *e == Event::ModeChanged(FlightMode::Loiter));
        assert!(airborne.is_some() && airborne < loiter, "{:?}", s.events);
        // Then it holds the take-off point.
        assert!(s.fly(5.0).is_empty());
        assert!((s.x.pos_w - Vec3::new(0.0, 0.0, -5.0)).norm() < 1e-9);
    }

    #[test]
    fn takeoff_climbs_at_px4s_takeoff_speed_then_at_the_auto_climb_speed() {
        let mut s = Script::new(CommanderParams::default());
        assert_eq!(s.request(Request::Takeoff { height_m: Some(100.0) }), Outcome::Accepted);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        let (mut low_peak, mut high_peak, mut acc_peak, mut t) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0);
        while s.c.mode() == FlightMode::Takeoff && t < 120.0 {
            s.step();
            t += super::super::script::DT_S;
            let Some(sp) = s.last.as_ref().and_then(|tick| tick.setpoint) else {
                continue;
            };
            let (height, up) = (GROUND_Z_M - s.x.pos_w.z, -sp.vel_w.unwrap_or_default().z);
            if height < 9.0 {
                low_peak = low_peak.max(up);
                acc_peak = acc_peak.max(-sp.acc_w.unwrap_or_default().z);
            } else {
                high_peak = high_peak.max(up);
            }
        }
        // MPC_TKO_SPEED 1.5 m/s reached in MPC_TKO_RAMP_T 3 s below MPC_LAND_ALT1 10 m, then
        // MPC_Z_V_AUTO_UP 3 m/s: 10 m in ≈ 8 s, 90 m in ≈ 31 s (PX4 SITL: ≈ 40 s to 100 m).
        assert!((low_peak - 1.5).abs() < 0.01, "{low_peak}");
        assert!(acc_peak < 0.5 + 1e-9, "{acc_peak}");
        assert!((high_peak - 3.0).abs() < 0.01, "{high_peak}");
        assert!((36.0..45.0).contains(&t), "took {t} s");
        assert!((s.x.pos_w.z - (GROUND_Z_M - 100.0)).abs() < 0.2, "{:?}", s.x.pos_w);
    }

    #[test]
    fn the_auto_vertical_speeds_are_kept_within_the_caps() {
        let mut s = Script::new(CommanderParams::default());
        s.c.params.auto_vertical.up_m_s = 5.0;
        s.c.params.auto_vertical.down_m_s = 1.0;
        let limits = s.c.limits(5.0);
        assert_eq!(
            (limits.up_m_s, limits.down_m_s),
            (3.0, 1.0),
            "MPC_Z_VEL_MAX_UP caps MPC_Z_V_AUTO_UP"
        );
        s.c.params.auto_vertical.takeoff_ramp_s = 0.0;
        assert_eq!(s.c.takeoff_limits(1.0).acc_up_m_s2, 4.0, "no ramp: MPC_ACC_UP_MAX");
        assert_eq!(s.c.takeoff_limits(1.0).up_m_s, 1.5);
        assert_eq!(s.c.takeoff_limits(10.0).up_m_s, 3.0);
    }

    #[test]
    fn land_descends_lands_and_disarms_after_com_disarm_land() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(8.0);
        assert_eq!(
            s.request(Request::Reposition {
                north_m: Some(3.0),
                east_m: Some(-2.0),
                down_m: None,
                yaw_rad: None,
                speed_m_s: None,
                change_mode: true,
            }),
            Outcome::Accepted
        );
        s.fly(10.0);
        assert_eq!(s.request(Request::Land), Outcome::Accepted);
        assert_eq!(s.c.landed_state(), LandedState::Landing);
        assert!(s.fly_until(60.0, |s| s.c.landed_state() == LandedState::OnGround));
        let landed_s = s.t();
        assert!(s.c.armed() && s.events.contains(&Event::Landed));
        assert!(
            (s.x.pos_w - Vec3::new(3.0, -2.0, GROUND_Z_M)).norm() < 1e-6,
            "lands where it was"
        );
        assert!(s.until_disarmed(5.0));
        let after_s = s.t() - landed_s;
        assert!(
            (after_s - 2.0).abs() < 0.05,
            "COM_DISARM_LAND 2 s, disarmed after {after_s} s"
        );
        assert_eq!(s.events.last(), Some(&Event::Disarmed("landed")));
        assert_eq!(s.c.mode(), FlightMode::Loiter);
    }

    #[test]
    fn mission_and_offboard_need_something_to_fly() {
        let mut s = Script::new(CommanderParams::default());
        let refused = |text: &str| Outcome::TemporarilyRejected(text.into());
        assert_eq!(
            s.request(Request::SetMode(FlightMode::Mission)),
            refused("Mode AUTO.MISSION: no mission")
        );
        assert_eq!(
            s.request(Request::SetMode(FlightMode::Offboard)),
            refused("Mode OFFBOARD: no setpoint stream")
        );
        assert_eq!(s.c.mode(), FlightMode::Loiter);
    }

    #[test]
    fn auto_takeoff_selected_in_the_air_goes_to_mis_takeoff_alt() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(6.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::Takeoff)), Outcome::Accepted);
        assert!(s.fly_until(20.0, |s| s.c.mode() == FlightMode::Loiter));
        assert!((s.x.pos_w.z + 2.5).abs() < 0.2, "MIS_TAKEOFF_ALT: {:?}", s.x.pos_w);
    }
}
