//! What comes into the commander: [`Commander::request`] hands each ground-station request to
//! the part that handles it (arming, plans, the mission run, the streams, orbit, follow-me,
//! DO_REPOSITION) and applies its answer; the flight controller's failsafe checks
//! ([`Commander::check_failsafes`]), rotor failures ([`Commander::rotor_failed`]) and the
//! navigation estimate's validity ([`Commander::check_navigation`]) likewise.

use super::FailsafeCause;
use crate::control::{FlatSetpoint, VehicleState};
use crate::guidance::{Geofence, Guidance};
use crate::math::{euler_zyx, Vec3};

use super::arming::{Arming, ArmingChecks};
use super::goto::{RepositionAction, RepositionTarget};
use super::navigation_checks::PositionLoss;
use super::offboard::OffboardTarget;
use super::reactions::Reaction;
use super::{
    Commander, Event, FailsafeAction, FlightMode, GeofenceAction, InputStream, LinkLossAction, NavValidity,
    OrbitRequest, Outcome, Request, RotorLoss,
};

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
            Request::SelectMode(mode) => {
                let checked = self.armed();
                self.switch_mode(mode, x, t_s, checked)
            }
            Request::Takeoff { height_m } => self.takeoff(height_m, x, t_s),
            Request::Land => self.set_mode(FlightMode::Land, x, t_s),
            Request::TurnTo { yaw_rad } => self.turn_to(yaw_rad),
            Request::UserTakeoff { height_m } => self.user_takeoff(height_m, x, t_s),
            Request::GuidedGoto { pos_w, yaw_rad } => self.guided_goto(pos_w, yaw_rad, x, t_s),
            Request::ReturnToLaunch => self.set_mode(FlightMode::ReturnToLaunch, x, t_s),
            Request::OffboardSetpoint { setpoint, body_frame } => {
                self.offboard.receive(OffboardTarget::Flat(setpoint, body_frame));
                Outcome::Accepted
            }
            Request::OffboardAttitude(target) => {
                self.offboard.receive(OffboardTarget::Attitude(target));
                Outcome::Accepted
            }
            Request::GuidedLean(lean) => {
                self.offboard.receive(OffboardTarget::Lean(lean));
                Outcome::Accepted
            }
            Request::StreamLost(stream) => {
                match stream {
                    InputStream::Offboard => self.offboard.set_lost(),
                    InputStream::ManualControl => self.manual.set_silent(),
                }
                Outcome::Accepted
            }
            Request::Orbit(orbit) => self.orbit_request(orbit, x, t_s),
            Request::Circle { radius_m, speed_m_s } => {
                let yaw = euler_zyx(&x.r_wb).z;
                let ahead = (x.pos_w.x + radius_m * yaw.cos(), x.pos_w.y + radius_m * yaw.sin());
                let circle = OrbitRequest {
                    radius_m: Some(radius_m),
                    speed_m_s: Some(speed_m_s),
                    yaw: None,
                    centre_ne_m: Some(ahead),
                    centre_down_m: None,
                };
                self.orbit_request(circle, x, t_s)
            }
            Request::FollowTarget { pos_w, vel_w } => {
                self.follow.report(pos_w, vel_w, t_s, &self.params.follow);
                Outcome::Accepted
            }
            Request::ManualControl(sticks) => {
                self.manual.receive(sticks, t_s);
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
            Request::SetRallyPoints(rally) => {
                self.plans.set_rally_points(rally);
                Outcome::Accepted
            }
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
            Request::ChangeVerticalSpeed { up, speed_m_s } => {
                if !(speed_m_s.is_finite() && speed_m_s > 0.0 && speed_m_s <= MAX_SPEED_M_S) {
                    return Outcome::Denied(format!("Change speed refused: {speed_m_s} m/s"));
                }
                let speeds = &mut self.vertical_speeds;
                *(if up { &mut speeds.0 } else { &mut speeds.1 }) = Some(speed_m_s);
                Outcome::Accepted
            }
            Request::SetHome(p) => {
                let p = p.unwrap_or(x.pos_w);
                if !p.iter().all(|v| v.is_finite()) {
                    return Outcome::Denied("Set home refused: bad position".into());
                }
                self.plans.set_home(p);
                Outcome::Accepted
            }
            Request::GcsLinkLost => self.gcs_link_lost(x, t_s),
            Request::InjectRotorFailure { .. } | Request::InjectSensorFailure(_) => {
                Outcome::Denied("Failure injection is applied by the vehicle, not the commander".into())
            }
        }
    }

    /// ARM: the pre-arm checks of the mode (skipped when `force`), then arms and starts the
    /// mode's guidance.
    fn arm(&mut self, force: bool, x: &VehicleState, t_s: f64) -> Outcome {
        if self.armed() {
            return Outcome::Accepted;
        }
        if !force {
            // RP_ARM_CHECKS 0 keeps the mandatory checks only: the estimate and the mode's needs.
            let all = self.params.arming_checks;
            let checks = ArmingChecks {
                navigation: self.navigation_refusal(self.mode, true),
                outside_fence: all && self.plans.arming_fence_breach(&self.params.failsafe, x).is_some(),
                has_mission: !self.mission.is_empty(),
                offboard_alive: self.offboard.alive(),
                sticks: self.manual.mode_refusal(self.mode, true).filter(|_| all),
            };
            if let Some(refusal) = Arming::refusal(self.mode, checks) {
                return refusal;
            }
        }
        self.arming.arm(t_s, self.detector.landed());
        self.manual.armed_at();
        self.enter(self.mode, x, t_s);
        Outcome::Accepted
    }

    /// DISARM: refused in the air unless `force`.
    fn disarm_request(&mut self, force: bool) -> Outcome {
        if self.in_air() && !force {
            return Outcome::TemporarilyRejected("Disarm refused: vehicle in the air".into());
        }
        self.disarm();
        Outcome::Accepted
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

    /// ArduCopter's user take-off: in GUIDED, POSCTL (LOITER, POSHOLD) or ALTCTL (ALT_HOLD),
    /// armed, on the ground, to a height above the vehicle; climbs in place and holds at the top,
    /// staying in the mode.
    fn user_takeoff(&mut self, h: f64, x: &VehicleState, t_s: f64) -> Outcome {
        if !matches!(
            self.mode,
            FlightMode::Guided | FlightMode::Position | FlightMode::Altitude
        ) {
            return Outcome::Failed(format!("Takeoff: mode {} takes no user take-off", self.mode.name()));
        }
        if !self.armed() {
            return Outcome::Failed("Takeoff: not armed".into());
        }
        if self.in_air() {
            return Outcome::Failed("Takeoff: already flying".into());
        }
        let above_home_m = self.plans.home_w().z - x.pos_w.z;
        if !(h.is_finite() && h > above_home_m && h <= MAX_TAKEOFF_M) {
            return Outcome::Failed(format!("Takeoff: {h} m is not above the vehicle"));
        }
        let target = Vec3::new(x.pos_w.x, x.pos_w.y, self.plans.home_w().z - h);
        self.takeoff_target_w = Some(target);
        self.climbing_out = true;
        let yaw = euler_zyx(&x.r_wb).z;
        self.guidance = self.paths().climb_to(x, target, yaw, t_s);
        Outcome::Accepted
    }

    /// CONDITION_YAW in GUIDED: the latest guided target, or the hold, takes heading `yaw_rad`.
    fn turn_to(&mut self, yaw_rad: f64) -> Outcome {
        if self.mode != FlightMode::Guided {
            return Outcome::Failed(format!("Condition yaw: only in GUIDED (mode {})", self.mode.name()));
        }
        if !self.offboard.turn_to(yaw_rad) {
            if let Guidance::Hold { pos_w, .. } = self.guidance {
                self.guidance = Guidance::Hold { pos_w, yaw_rad };
            }
        }
        Outcome::Accepted
    }

    /// DO_REPOSITION as ArduCopter flies it: GUIDED (entered if need be) with a position target.
    fn guided_goto(&mut self, pos_w: Vec3, yaw_rad: Option<f64>, x: &VehicleState, t_s: f64) -> Outcome {
        if self.mode != FlightMode::Guided {
            let entered = self.set_mode(FlightMode::Guided, x, t_s);
            if entered != Outcome::Accepted {
                return entered;
            }
        }
        let target = FlatSetpoint {
            pos_w: Some(pos_w),
            yaw_rad,
            ..Default::default()
        };
        self.offboard.receive(OffboardTarget::Flat(target, false));
        Outcome::Accepted
    }

    /// MISSION_START from item `first`: a finished mission can be flown again.
    fn start_mission(&mut self, first: usize, x: &VehicleState, t_s: f64) -> Outcome {
        if !self.mission.start_at(first) {
            return Outcome::Denied(format!("Mission start: no item {first}"));
        }
        self.set_mode(FlightMode::Mission, x, t_s)
    }

    /// MISSION_SET_CURRENT / DO_SET_MISSION_CURRENT: the mission goes on at `seq` (flown from
    /// there at once in AUTO.MISSION; a DO_JUMP there is resolved as if reached).
    fn set_mission_current(&mut self, seq: Option<usize>, reset: bool) -> Outcome {
        let seq = seq.unwrap_or(self.mission.seq());
        if self.mission.set_current(seq, reset) {
            self.pending.push(Event::MissionCurrent(seq as u16));
            Outcome::Accepted
        } else {
            let (_, len, _) = self.mission.progress();
            Outcome::Denied(format!("Mission: no item {seq} (the mission has {len})"))
        }
    }

    /// A new uploaded fence: the zones home (and, in flight with `GF_ACTION` set, the vehicle)
    /// breaks are left out, each announced on the next tick. Always accepted (the plan is stored
    /// as uploaded).
    fn set_geofence(&mut self, fence: Geofence, x: &VehicleState) -> Outcome {
        let fs = &self.params.failsafe;
        let check_here = fs.geofence_enabled && fs.geofence_action != GeofenceAction::Disabled && self.in_air();
        let left_out = self.plans.set_geofence(fence, x, check_here);
        self.pending.extend(left_out);
        Outcome::Accepted
    }

    /// DO_ORBIT: planned by the orbit mode, then flown in it.
    fn orbit_request(&mut self, req: OrbitRequest, x: &VehicleState, t_s: f64) -> Outcome {
        let (in_air, in_mode) = (self.in_air(), self.mode == FlightMode::Orbit);
        match self.orbit.request(req, x, in_air, in_mode, &self.params.motion) {
            Ok(()) => {
                self.enter(FlightMode::Orbit, x, t_s);
                Outcome::Accepted
            }
            Err(refusal) => refusal,
        }
    }

    /// DO_REPOSITION to `target`, mode change asked with `change_mode` (`goto.rs`); only in the
    /// air.
    fn reposition(&mut self, target: RepositionTarget, change_mode: bool, x: &VehicleState, t_s: f64) -> Outcome {
        if !self.in_air() {
            return Outcome::TemporarilyRejected("Reposition refused: not flying".into());
        }
        let (horizontal, other) = (target.horizontal(), target.height_or_heading());
        match RepositionAction::decide(self.mode, change_mode, horizontal, other) {
            RepositionAction::Refused => Outcome::Denied(format!(
                "Reposition refused: no mode change asked in {}",
                self.mode.name()
            )),
            RepositionAction::Goto => self.fly_goto(target, x, t_s),
            RepositionAction::Hold | RepositionAction::InHold => self.fly_in_hold(target, x, t_s),
        }
    }

    /// AUTO.LOITER flies to `target` (unset coordinates: where the vehicle is) and holds there.
    fn fly_in_hold(&mut self, target: RepositionTarget, x: &VehicleState, t_s: f64) -> Outcome {
        let to = match target.point_from(x.pos_w) {
            Ok(to) => to,
            Err(refusal) => return refusal,
        };
        if let Some(refusal) = self.navigation_refusal(FlightMode::Loiter, false) {
            return refusal;
        }
        self.enter(FlightMode::Loiter, x, t_s);
        let yaw = target.yaw_rad.unwrap_or(euler_zyx(&x.r_wb).z);
        let speed = target
            .speed_m_s
            .filter(|v| *v > 0.0)
            .unwrap_or(self.paths().cruise_speed());
        self.guidance = self.paths().path_to(x, to, yaw, speed, t_s);
        Outcome::Accepted
    }

    /// GOTO flies to `target` (unset coordinates: those of the target flown, else where the
    /// vehicle is), keeping the reference's motion when GOTO already flies.
    fn fly_goto(&mut self, target: RepositionTarget, x: &VehicleState, t_s: f64) -> Outcome {
        let running = match (self.mode, self.guidance) {
            (FlightMode::Goto, Guidance::Track(track)) => Some(track),
            _ => None,
        };
        let to = match target.point_from(running.map_or(x.pos_w, |t| t.leg.target_w)) {
            Ok(to) => to,
            Err(refusal) => return refusal,
        };
        if let Some(refusal) = self.navigation_refusal(FlightMode::Goto, false) {
            return refusal;
        }
        let yaw = euler_zyx(&x.r_wb).z;
        let heading = target.goto_heading(to, running, x, self.params.mission.accept_m);
        if self.mode != FlightMode::Goto {
            // A mode the pilot chose: a failsafe waiting in its hold gives way, as for a mode switch.
            self.failsafe.give_way();
            self.failsafe.end_blind_descent();
            self.enter(FlightMode::Goto, x, t_s);
        }
        self.speed_override = target.speed_m_s.filter(|v| *v > 0.0);
        let track = self.paths().goto_track(running, to, heading, x, yaw, t_s);
        self.guidance = Guidance::Track(track);
        Outcome::Accepted
    }

    /// Draws `power_w` [W] from the battery for `dt_s` [s], then runs the geofence and battery
    /// failsafes for state `x` at `t_s` [s]: each announces itself and switches the mode (hold,
    /// return, land) or terminates, which the next heartbeat shows.
    pub fn check_failsafes(&mut self, x: &VehicleState, power_w: f64, dt_s: f64, t_s: f64) -> Vec<Event> {
        self.failsafe.draw(power_w, dt_s);
        let rel = x.pos_w - self.plans.home_w();
        let in_air = self.in_air();
        let fired = self.failsafe.check(
            &self.params,
            [rel.x, rel.y, rel.z],
            self.plans.geofence(),
            &x.pos_w,
            in_air,
        );
        let mut events = Vec::new();
        for failsafe in fired {
            events.push(Event::Failsafe(failsafe.cause, failsafe.text));
            let mode = failsafe.action.mode();
            if failsafe.action == FailsafeAction::Terminate {
                self.disarm();
                events.push(Event::Disarmed("flight termination"));
            }
            // Never step back from landing to a return, nor restart a return or landing already
            // running; a hold while in the hold mode stops what it was flying (a DO_REPOSITION).
            match mode {
                _ if self.mode == FlightMode::Land => {}
                Some(mode) if mode != self.mode => self.fail_to(mode, x, t_s, &mut events),
                Some(FlightMode::Loiter) => self.enter(FlightMode::Loiter, x, t_s),
                _ => {}
            }
        }
        events
    }

    /// A motor failed (`loss` says which and what the allocation did about it): announced
    /// (critical) in any case; in flight `COM_ACT_FAIL_ACT` runs: nothing more (0, PX4's
    /// default: the vehicle flies on in its mode), hold (1), land (2) or return (3), the last
    /// two after the `COM_FAIL_ACT_T` hold, or flight termination (4: motors off at once). A
    /// landing under way is never turned into a hold or a return.
    pub fn rotor_failed(&mut self, loss: RotorLoss, x: &VehicleState, t_s: f64) -> Vec<Event> {
        let action = self.params.actuator_failure_action;
        let in_air = self.armed() && self.in_air();
        let mut events = vec![Event::Failsafe(FailsafeCause::Other, loss.announcement(action, in_air))];
        if !in_air {
            return events;
        }
        match action.reaction(self.mode) {
            Reaction::Nothing => {}
            Reaction::Hold => {
                self.enter(FlightMode::Loiter, x, t_s);
                events.push(Event::ModeChanged(FlightMode::Loiter));
            }
            Reaction::FailTo(mode) => self.fail_to(mode, x, t_s, &mut events),
            Reaction::Terminate => {
                self.disarm();
                events.push(Event::Disarmed("flight termination"));
            }
        }
        events
    }

    /// No GCS heartbeat for `COM_DL_LOSS_T`: runs `NAV_DLL_ACT` once if flying (hold, return,
    /// land, or 5/6 motors off). Always accepted; a reaction is announced as an
    /// [`Event::Failsafe`] of the next tick.
    fn gcs_link_lost(&mut self, x: &VehicleState, t_s: f64) -> Outcome {
        let action = self.params.link_loss_action;
        if action == LinkLossAction::Disabled || !self.armed() || !self.in_air() {
            return Outcome::Accepted;
        }
        let event = self.react_to_loss(("GCS link", FailsafeCause::GcsLink), action, x, t_s);
        self.pending.push(event);
        Outcome::Accepted
    }

    /// Each tick, before the other failsafes: the estimate's validity `v` with the vehicle in
    /// (estimated) state `x` at `t_s` [s]; what the commander did about it.
    pub fn check_navigation(&mut self, v: NavValidity, x: &VehicleState, t_s: f64) -> Vec<Event> {
        let mut events = Vec::new();
        if let (Some((cause, text)), true) = (v.position_change(&self.nav), self.armed()) {
            events.push(Event::Failsafe(cause, text.into()));
        }
        self.nav = v;
        if !self.armed() {
            self.failsafe.end_blind_descent();
            return events;
        }
        let (in_air, blind) = (self.in_air(), self.failsafe.descending_blind());
        let lands = self.params.position_loss_lands;
        match v.position_loss(self.mode, in_air, blind, || self.manual.alive(), lands) {
            PositionLoss::Fly => {}
            PositionLoss::Altitude => {
                self.enter(FlightMode::Altitude, x, t_s);
                events.push(Event::Failsafe(
                    FailsafeCause::PositionAction(FlightMode::Altitude),
                    "No position estimate: switching to Altitude mode".into(),
                ));
                events.push(Event::ModeChanged(FlightMode::Altitude));
            }
            PositionLoss::Descend => {
                self.failsafe.start_blind_descent();
                self.enter(FlightMode::Land, x, t_s);
                events.push(Event::Failsafe(
                    FailsafeCause::PositionAction(FlightMode::Land),
                    "No position estimate: descending".into(),
                ));
                events.push(Event::ModeChanged(FlightMode::Land));
            }
        }
        events
    }
}

#[cfg(test)]
#[path = "requests_tests.rs"]
mod tests;
