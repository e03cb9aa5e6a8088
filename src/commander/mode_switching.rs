//! Mode switches and what each mode's tick does with its part's decision: AUTO.TAKEOFF climbs
//! to its target and hands over to AUTO.LOITER, AUTO.LAND descends (`MPC_LAND_ALT1` /
//! `MPC_LAND_ALT2` profile), AUTO.RTL starts its climb ([`Rtl`]), AUTO.MISSION starts its run,
//! the hold modes hold (idle on the ground); the failsafes' mode changes: a hold, a return or
//! landing after the `COM_FAIL_ACT_T` hold, a termination. Paths fly at the cruise speed
//! (`MPC_XY_CRUISE` or DO_CHANGE_SPEED's), capped at `MPC_XY_VEL_MAX` ([`AutoPaths`]).

use super::FailsafeCause;
use crate::control::VehicleState;
use crate::guidance::Guidance;
use crate::math::{euler_zyx, Vec3};

use super::auto_paths::AutoPaths;
use super::follow::FollowCommand;
use super::landing::FlightDemand;
use super::manual::StickWatch;
use super::mission_run::MissionFlight;
use super::offboard::GuidedStep;
use super::reactions::{loss_text, FailTo, Reaction};
use super::rtl::Rtl;
use super::{paths_of, Commander, Event, FlightMode, LinkLossAction, Moment, Outcome};

/// Take-off is complete within this distance of the target [m].
const TAKEOFF_ACCEPT_M: f64 = 0.2;

impl Commander {
    /// The AUTO paths with the current settings, cruise speed and ground.
    pub(super) fn paths(&self) -> AutoPaths<'_> {
        paths_of!(self)
    }

    /// Why `mode` cannot be flown (or armed in, `arming`) on the current estimate, if it cannot.
    pub(super) fn navigation_refusal(&self, mode: FlightMode, arming: bool) -> Option<Outcome> {
        self.nav.refusal(mode, arming, self.params.arm_without_gps)
    }

    /// A requested mode switch: AUTO.MISSION needs a mission, OFFBOARD a live setpoint stream,
    /// the stick modes but POSCTL live sticks, orbit, follow-me and GOTO the air (GOTO chosen so,
    /// without a target, holds where it is);
    /// AUTO.TAKEOFF without a target (or in the air) climbs to `MIS_TAKEOFF_ALT` from here.
    pub(super) fn set_mode(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64) -> Outcome {
        self.switch_mode(mode, x, t_s, true)
    }

    /// [`Self::set_mode`]; without `checked`, the navigation estimate and the mission are not
    /// checked (ArduCopter's mode change while disarmed: arming checks them).
    pub(super) fn switch_mode(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64, checked: bool) -> Outcome {
        if let Some(refusal) = self.manual.mode_refusal(mode, false) {
            return refusal;
        }
        if let Some(refusal) = self.navigation_refusal(mode, false).filter(|_| checked) {
            return refusal;
        }
        if mode != FlightMode::Land {
            self.failsafe.end_blind_descent();
        }
        // The pilot chose a mode: a failsafe waiting in its hold gives way (PX4).
        self.failsafe.give_way();
        match mode {
            FlightMode::Mission if checked && self.mission.is_empty() => {
                Outcome::TemporarilyRejected("Mode AUTO.MISSION: no mission".into())
            }
            FlightMode::Offboard if !self.offboard.alive() => {
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
        if self.mode == FlightMode::Mission && mode != FlightMode::Mission {
            self.mission.pause();
        }
        self.mode = mode;
        self.climbing_out = false;
        self.offboard.restart();
        self.manual.restart();
        if mode != FlightMode::Orbit {
            self.orbit.clear();
        }
        self.follow.restart();
        if mode == FlightMode::Guided {
            self.offboard.clear();
        }
        let yaw = euler_zyx(&x.r_wb).z;
        let on_ground = !self.in_air();
        let hold = Guidance::Hold {
            pos_w: x.pos_w,
            yaw_rad: yaw,
        };
        self.guidance = if !self.armed() {
            Guidance::Idle
        } else {
            match mode {
                FlightMode::Takeoff => {
                    let target = self
                        .takeoff_target_w
                        .unwrap_or(x.pos_w - Vec3::new(0.0, 0.0, self.params.takeoff_alt_m));
                    self.climbing_out = true;
                    self.paths().climb_to(x, target, yaw, t_s)
                }
                FlightMode::Land => self.paths().descend(x, yaw, t_s),
                FlightMode::Orbit if !on_ground => {
                    let (to_w, to_yaw) = self.orbit.approach(x, &self.params.motion);
                    let paths = self.paths();
                    paths.path_to(x, to_w, to_yaw, paths.cruise_speed(), t_s)
                }
                // PX4 never takes off for a return: landed, AUTO.RTL idles ("for safety reasons").
                FlightMode::ReturnToLaunch if on_ground => Guidance::Idle,
                FlightMode::ReturnToLaunch => {
                    self.rtl.start();
                    let to = self.plans.rtl_destination(&x.pos_w, self.params.rtl_type);
                    let z = -Rtl::return_height(&self.params, to, x);
                    let paths = self.paths();
                    paths.path_to(x, Vec3::new(x.pos_w.x, x.pos_w.y, z), yaw, paths.cruise_speed(), t_s)
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

    /// Motors off (explicit disarm, auto-disarm on the ground, or a termination); leaves the
    /// modes that only make sense armed.
    pub(super) fn disarm(&mut self) {
        self.arming.disarm();
        self.failsafe.end_blind_descent();
        self.guidance = Guidance::Idle;
        self.climbing_out = false;
        if matches!(
            self.mode,
            FlightMode::Takeoff | FlightMode::Land | FlightMode::ReturnToLaunch | FlightMode::Goto
        ) {
            self.mode = FlightMode::Loiter;
        }
    }

    /// A failsafe's `mode` (a return or a landing): after `COM_FAIL_ACT_T` in a hold, or at once
    /// ([`super::reactions::FailsafeState::fail_to`]). The hold's mode change is in `events`;
    /// the heartbeat shows it either way.
    pub(super) fn fail_to(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        let delay_s = self.params.fail_action_delay_s;
        match self.failsafe.fail_to(mode, self.mode, self.in_air(), t_s, delay_s) {
            FailTo::Retargeted | FailTo::Delayed { hold: false } => {}
            FailTo::Delayed { hold: true } => {
                self.enter(FlightMode::Loiter, x, t_s);
                events.push(Event::ModeChanged(FlightMode::Loiter));
            }
            FailTo::Now => {
                self.enter(mode, x, t_s);
                events.push(Event::ModeChanged(mode));
            }
        }
    }

    /// Runs a loss `action` (hold, return, land, or 5/6 motors off; the caller has checked the
    /// vehicle flies) for the lost stream `what`; the announcement.
    pub(super) fn react_to_loss(
        &mut self,
        (what, cause): (&str, FailsafeCause),
        action: LinkLossAction,
        x: &VehicleState,
        t_s: f64,
    ) -> Event {
        let mut events = Vec::new();
        match action.reaction() {
            Reaction::Hold => self.enter(FlightMode::Loiter, x, t_s),
            Reaction::FailTo(mode) => self.fail_to(mode, x, t_s, &mut events),
            Reaction::Terminate => self.disarm(),
            Reaction::Nothing => {}
        }
        Event::Failsafe(cause, loss_text(what, action))
    }

    /// Carries out a delayed failsafe once its hold is over.
    pub(super) fn run_delayed_failsafe(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        if let Some(mode) = self.failsafe.due(t_s) {
            self.enter(mode, x, t_s);
            events.push(Event::ModeChanged(mode));
        }
    }

    /// Each armed tick: the sticks' loss and return (a delayed failsafe they caused gives the
    /// pilot's mode back), and a pilot taking over an AUTO mode.
    pub(super) fn watch_sticks(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        let in_air = self.in_air();
        match self.manual.watch(self.mode, in_air, &self.params.manual) {
            StickWatch::Quiet => {}
            StickWatch::Alive { regained } => {
                if regained {
                    events.push(Event::Failsafe(FailsafeCause::Other, "Manual control regained".into()));
                    if let Some(resume) = self.failsafe.cancel(self.mode) {
                        self.enter(resume, x, t_s);
                        events.push(Event::ModeChanged(resume));
                    }
                }
                let (in_air, delayed) = (self.in_air(), self.failsafe.delayed());
                if self.manual.takes_over(self.mode, in_air, delayed, &self.params.manual) {
                    self.enter(FlightMode::Position, x, t_s);
                    events.push(Event::Failsafe(
                        FailsafeCause::Other,
                        "Pilot took over using sticks".into(),
                    ));
                    events.push(Event::ModeChanged(FlightMode::Position));
                }
            }
            StickWatch::Lost(action) => {
                let announced = self.react_to_loss(("Manual control", FailsafeCause::Other), action, x, t_s);
                events.push(announced);
            }
        }
    }

    /// One AUTO.TAKEOFF tick (or one of a user take-off's): once the climb is over within
    /// [`TAKEOFF_ACCEPT_M`] of the target, hold there, in AUTO.LOITER after AUTO.TAKEOFF, still in
    /// its mode after a user take-off (GUIDED holds; a stick mode flies its sticks from there).
    pub(super) fn complete_takeoff(&mut self, x: &VehicleState, yaw: f64, t_s: f64, events: &mut Vec<Event>) {
        let near = self
            .takeoff_target_w
            .is_none_or(|p| (x.pos_w - p).norm() < TAKEOFF_ACCEPT_M);
        if self.guidance.finished(t_s) && near {
            self.climbing_out = false;
            self.guidance = Guidance::Hold {
                pos_w: self.takeoff_target_w.unwrap_or(x.pos_w),
                yaw_rad: yaw,
            };
            if self.mode == FlightMode::Takeoff {
                self.mode = FlightMode::Loiter;
                events.push(Event::ModeChanged(FlightMode::Loiter));
            }
            // A stick mode's reference starts again from the top of the climb.
            self.manual.restart();
        }
    }

    /// Keeps a take-off climb's speeds those of its height (below or above `MPC_LAND_ALT1`).
    pub(super) fn pace_climb(&mut self, x: &VehicleState) {
        if !self.climbing_out {
            return;
        }
        let limits = self.paths().climb_limits(x);
        if let Guidance::Track(track) = &mut self.guidance {
            track.set_limits(limits);
        }
    }

    /// One AUTO.RTL tick: the return's next phase, and its announcement for the next tick.
    pub(super) fn advance_rtl(&mut self, x: &VehicleState, yaw: f64, t_s: f64) {
        let paths = paths_of!(self);
        let step = self.rtl.advance(&paths, &self.plans, self.guidance, x, yaw, t_s);
        if let Some(guidance) = step.guidance {
            self.guidance = guidance;
        }
        if let Some(notice) = step.notice {
            self.pending.push(notice);
        }
    }

    /// One AUTO.MISSION tick `now`: the run flies the guidance, and may hand over to another mode.
    pub(super) fn advance_mission(&mut self, now: Moment, events: &mut Vec<Event>) {
        let (x, t_s) = (now.x, now.t_s);
        let in_air = self.in_air();
        let flight = MissionFlight {
            guidance: self.guidance,
            takeoff_target_w: self.takeoff_target_w,
            climbing_out: self.climbing_out,
        };
        let paths = paths_of!(self);
        let (flight, then) = self.mission.advance(&paths, in_air, flight, now, events);
        self.guidance = flight.guidance;
        self.takeoff_target_w = flight.takeoff_target_w;
        self.climbing_out = flight.climbing_out;
        if let Some(mode) = then {
            self.enter(mode, x, t_s);
            events.push(Event::ModeChanged(mode));
        }
    }

    /// One OFFBOARD tick `now`: what to fly, or `None` when the stream was lost and
    /// `COM_OBL_RC_ACT` took over.
    pub(super) fn offboard_command(&mut self, now: Moment, events: &mut Vec<Event>) -> Option<FlightDemand> {
        let (x, t_s) = (now.x, now.t_s);
        let landed = self.detector.landed();
        let command = self.offboard.command(now, landed, &self.params.motion);
        if command.is_none() {
            events.push(Event::OffboardLost);
            let sticks = self.manual.alive();
            match self.params.offboard_loss_action.mode_on_loss(sticks) {
                Some(mode) => {
                    self.enter(mode, x, t_s);
                    events.push(Event::ModeChanged(mode));
                }
                None => {
                    self.disarm();
                    events.push(Event::Disarmed("offboard lost (COM_OBL_RC_ACT)"));
                }
            }
        }
        command
    }

    /// One GUIDED tick `now`: a take-off climb under way flies on (and holds at its top, still
    /// in GUIDED) until a guided target arrives; otherwise the latest guided target, or the hold
    /// the mode entered with; a target whose stream went silent stops the vehicle where it is.
    pub(super) fn guided_command(&mut self, now: Moment, events: &mut Vec<Event>) -> Option<FlightDemand> {
        if self.climbing_out && self.offboard.has_target() {
            // A target ends the take-off at once (ArduCopter's set_destination).
            self.climbing_out = false;
        }
        if self.climbing_out {
            self.complete_takeoff(now.x, now.yaw_rad, now.t_s, events);
            if self.climbing_out {
                return None;
            }
        }
        let landed = self.detector.landed();
        // Guided targets fly at the cruise speed (WPNAV_SPEED, or DO_CHANGE_SPEED's) and the
        // AUTO climb and descent speeds, as ArduCopter's waypoint controller flies them.
        let paths = self.paths();
        let motion = paths.limits(paths.cruise_speed());
        match self.offboard.guided(now, landed, &motion) {
            GuidedStep::Fly(command) => Some(command),
            GuidedStep::Stop => {
                if !landed {
                    self.guidance = Guidance::Hold {
                        pos_w: now.x.pos_w,
                        yaw_rad: now.yaw_rad,
                    };
                }
                None
            }
            GuidedStep::Nothing => None,
        }
    }

    /// One orbit-mode tick, `dt_s` [s] after the last.
    pub(super) fn advance_orbit(&mut self, dt_s: f64, t_s: f64) {
        let (manual, p) = (&self.manual, &self.params.manual);
        if let Some(guidance) = self
            .orbit
            .advance(self.guidance, || manual.live(), &p.shaping, dt_s, t_s)
        {
            self.guidance = guidance;
        }
    }

    /// One follow-me tick `now`: what to fly, or `None` to hold.
    pub(super) fn follow_command(&mut self, now: Moment) -> Option<FlightDemand> {
        let x = now.x;
        let paths = paths_of!(self);
        let p = &self.params;
        let sticks = self.manual.live();
        let limits = || paths.limits(p.follow.max_speed_m_s);
        let home_w = self.plans.home_w();
        match self
            .follow
            .command(now, home_w, sticks, &p.manual.shaping, &p.follow, limits)
        {
            FollowCommand::Fly(command) => Some(command),
            FollowCommand::HoldHere => {
                self.guidance = Guidance::Hold {
                    pos_w: x.pos_w,
                    yaw_rad: euler_zyx(&x.r_wb).z,
                };
                None
            }
            FollowCommand::Wait => None,
        }
    }

    /// One GOTO tick: the speed asked now, and the horizontal acceleration scaled to it.
    pub(super) fn advance_goto(&mut self) {
        let paths = paths_of!(self);
        if let Guidance::Track(track) = &mut self.guidance {
            paths.pace_goto(track);
        }
    }

    /// One tick `now` of a stick mode: what to fly.
    pub(super) fn stick_command(&mut self, now: Moment) -> FlightDemand {
        let landed = self.detector.landed();
        let p = &self.params;
        self.manual.command(self.mode, now, landed, &p.manual, &p.motion)
    }
}

#[cfg(test)]
#[path = "mode_switching_tests.rs"]
mod tests;
