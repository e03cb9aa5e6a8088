//! [`Commander::request`]: each ground-station request to the part of the commander that
//! handles it, and the small requests handled here: take-off, change speed (DO_CHANGE_SPEED),
//! set home (DO_SET_HOME), set and start the mission, and the offboard setpoint store (the
//! geofence and rally points go to `plans.rs`, DO_REPOSITION to `goto.rs`).

use crate::control::VehicleState;
use crate::math::Vec3;

use super::goto::RepositionTarget;
use super::mission_run::MissionState;
use super::offboard::OffboardTarget;
use super::{Commander, FlightMode, InputStream, Outcome, Request};

/// Highest take-off height accepted [m].
const MAX_TAKEOFF_M: f64 = 1000.0;
/// Highest DO_CHANGE_SPEED speed accepted [m/s].
const MAX_SPEED_M_S: f64 = 30.0;

impl Commander {
    /// Handles `request` at simulated time `t_s` [s] with the vehicle in state `x`.
    pub fn request(&mut self, request: Request, x: &VehicleState, t_s: f64) -> Outcome {
        match request {
            Request::Arm { force } => self.arm(force, x, t_s),
            Request::Disarm { force } => self.disarm_request(force),
            Request::SetMode(mode) => self.set_mode(mode, x, t_s),
            Request::Takeoff { height_m } => self.takeoff(height_m, x, t_s),
            Request::Land => self.set_mode(FlightMode::Land, x, t_s),
            Request::ReturnToLaunch => self.set_mode(FlightMode::ReturnToLaunch, x, t_s),
            Request::OffboardSetpoint { setpoint, body_frame } => {
                self.offboard.latest = Some((OffboardTarget::Flat(setpoint, body_frame), t_s));
                Outcome::Accepted
            }
            Request::OffboardAttitude(target) => {
                self.offboard.latest = Some((OffboardTarget::Attitude(target), t_s));
                Outcome::Accepted
            }
            Request::StreamInWallTime { stream, alive } => {
                match stream {
                    InputStream::Offboard => self.offboard.alive_in_wall_time = alive,
                    InputStream::ManualControl => self.manual.alive_in_wall_time = alive,
                }
                Outcome::Accepted
            }
            Request::Orbit(orbit) => self.orbit(orbit, x, t_s),
            Request::FollowTarget { pos_w, vel_w } => {
                self.follow_report(pos_w, vel_w, t_s);
                Outcome::Accepted
            }
            Request::ManualControl(sticks) => {
                self.manual.latest = Some((sticks, t_s));
                self.manual.motion.sample(sticks, t_s);
                Outcome::Accepted
            }
            Request::SetMission(mission) => {
                self.mission.replace(mission);
                if self.mode == FlightMode::Mission {
                    self.enter(FlightMode::Loiter, x, t_s);
                }
                Outcome::Accepted
            }
            Request::SetGeofence(fence) => self.set_geofence(fence, x),
            Request::SetRallyPoints(rally) => self.set_rally_points(rally),
            Request::StartMission { first } => self.start_mission(first, x, t_s),
            Request::SetMissionCurrent { seq, reset } => self.set_mission_current(seq, reset),
            Request::Reposition {
                north_m,
                east_m,
                down_m,
                yaw_rad,
                speed_m_s,
                change_mode,
            } => {
                let target = RepositionTarget {
                    ned_m: [north_m, east_m, down_m],
                    yaw_rad,
                    speed_m_s,
                };
                self.reposition(target, change_mode, x, t_s)
            }
            Request::ChangeSpeed(v) => {
                if !(v.is_finite() && v > 0.0 && v <= MAX_SPEED_M_S) {
                    return Outcome::Denied(format!("Change speed refused: {v} m/s"));
                }
                self.speed_override = Some(v);
                Outcome::Accepted
            }
            Request::SetHome(p) => {
                let p = p.unwrap_or(x.pos_w);
                if !p.iter().all(|v| v.is_finite()) {
                    return Outcome::Denied("Set home refused: bad position".into());
                }
                self.home_w = p;
                Outcome::Accepted
            }
            Request::GcsLinkLost => self.gcs_link_lost(x, t_s),
            Request::InjectRotorFailure { .. } | Request::InjectSensorFailure(_) => {
                Outcome::Denied("Failure injection is applied by the vehicle, not the commander".into())
            }
        }
    }

    /// NAV_TAKEOFF to `height_m` above home [m] (`None`: `MIS_TAKEOFF_ALT`) straight up from
    /// here; refused in the air and for heights outside (0, 1000] m.
    fn takeoff(&mut self, height_m: Option<f64>, x: &VehicleState, t_s: f64) -> Outcome {
        if self.in_air() {
            return Outcome::TemporarilyRejected("Takeoff refused: already flying".into());
        }
        let h = height_m.unwrap_or(self.params.takeoff_alt_m);
        if !(h.is_finite() && h > 0.0 && h <= MAX_TAKEOFF_M) {
            return Outcome::Denied(format!("Takeoff refused: height {h} m"));
        }
        if let Some(refusal) = self.navigation_refusal(FlightMode::Takeoff, false) {
            return refusal;
        }
        self.takeoff_target_w = Some(Vec3::new(x.pos_w.x, x.pos_w.y, -h));
        self.enter(FlightMode::Takeoff, x, t_s);
        Outcome::Accepted
    }

    /// MISSION_START from item `first`: a finished mission can be flown again.
    fn start_mission(&mut self, first: usize, x: &VehicleState, t_s: f64) -> Outcome {
        if first >= self.mission.mission.len() {
            return Outcome::Denied(format!("Mission start: no item {first}"));
        }
        self.mission.seq = first;
        if self.mission.state == MissionState::Complete {
            self.mission.state = MissionState::NotStarted;
        }
        self.set_mode(FlightMode::Mission, x, t_s)
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, MissionState, Outcome, Request};
    use crate::math::Vec3;
    use crate::navigation::{Mission, MissionItem};

    #[test]
    fn change_speed_refuses_bad_speeds_and_sets_the_cruise_speed() {
        let mut s = Script::new(CommanderParams::default());
        for v in [0.0, -1.0, f64::NAN, f64::INFINITY, 31.0] {
            assert!(matches!(s.request(Request::ChangeSpeed(v)), Outcome::Denied(_)), "{v}");
        }
        assert_eq!(s.request(Request::ChangeSpeed(2.0)), Outcome::Accepted);
        s.airborne(3.0);
        // Flown in AUTO.LOITER (no mode change asked), at DO_CHANGE_SPEED's speed.
        let in_hold = Request::Reposition {
            north_m: Some(30.0),
            east_m: Some(0.0),
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: false,
        };
        assert_eq!(s.request(in_hold), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Loiter);
        let mut fastest: f64 = 0.0;
        assert!(s.fly_until(60.0, |s| {
            fastest = fastest.max(s.x.vel_w.xy().norm());
            (s.x.pos_w.x - 30.0).abs() < 1e-6
        }));
        assert!(
            fastest <= 2.0 + 1e-9 && fastest > 1.9,
            "DO_CHANGE_SPEED 2 m/s: {fastest} m/s"
        );
    }

    #[test]
    fn takeoff_set_home_and_failure_injection_check_their_values() {
        let mut s = Script::new(CommanderParams::default());
        for h in [0.0, -2.0, 1001.0] {
            let takeoff = Request::Takeoff { height_m: Some(h) };
            assert!(matches!(s.request(takeoff), Outcome::Denied(_)), "{h}");
        }
        let bad_home = Request::SetHome(Some(Vec3::new(f64::NAN, 0.0, 0.0)));
        assert!(matches!(s.request(bad_home), Outcome::Denied(_)));
        assert_eq!(s.c.home_w(), Vec3::zeros());
        let inject = Request::InjectRotorFailure { rotor: 1, failed: true };
        assert!(matches!(s.request(inject), Outcome::Denied(_)));
        s.airborne(3.0);
        assert_eq!(
            s.request(Request::Takeoff { height_m: None }),
            Outcome::TemporarilyRejected("Takeoff refused: already flying".into())
        );
        assert_eq!(s.request(Request::SetHome(None)), Outcome::Accepted);
        assert_eq!(s.c.home_w(), s.x.pos_w, "home here");
    }

    #[test]
    fn a_mission_is_stored_started_from_an_item_and_replacing_it_leaves_auto_mission() {
        let mut s = Script::new(CommanderParams::default());
        assert!(matches!(
            s.request(Request::StartMission { first: 0 }),
            Outcome::Denied(_)
        ));
        let wp = |north_m| MissionItem::Waypoint {
            pos_w: Vec3::new(north_m, 0.0, -4.0),
            hold_s: 0.0,
            accept_m: Some(0.5),
            yaw_rad: None,
        };
        let mission = Mission {
            items: vec![wp(5.0), wp(10.0)],
            ..Default::default()
        };
        assert_eq!(s.request(Request::SetMission(mission)), Outcome::Accepted);
        assert_eq!(s.c.mission_progress(), (0, 2, MissionState::NotStarted));
        assert!(matches!(
            s.request(Request::StartMission { first: 2 }),
            Outcome::Denied(_)
        ));
        assert_eq!(s.request(Request::StartMission { first: 1 }), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Mission);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        s.fly(3.0);
        assert_eq!(s.c.mission_progress(), (1, 2, MissionState::Active));
        assert_eq!(s.request(Request::SetMission(Mission::default())), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Loiter);
        assert_eq!(s.c.mission_progress(), (0, 0, MissionState::NoMission));
    }
}
