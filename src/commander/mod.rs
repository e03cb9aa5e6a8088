//! The commander (PX4 semantics): armed state, flight mode, landed state, take-off / hold /
//! land / return / mission / offboard, all on simulated time. Pure: requests and the vehicle
//! state in, an outcome, a setpoint and events out.
//!
//! # Layout
//! The [`Commander`] is a composition of smaller types, each owning its fields behind its own
//! methods: they take values (the time included) and return values or decisions (a mode to
//! switch to, a guidance to fly) that the commander applies. Only three files hold
//! `impl Commander`:
//! - `mod.rs`: the [`Commander`] struct, its accessors and the tick ([`Commander::update`]) with
//!   the land detector's verdict applied.
//! - `requests.rs`: what comes in: [`Commander::request`] dispatched to the part that handles
//!   it, the failsafe checks, a rotor failure, the navigation estimate's validity.
//! - `modes.rs`: mode switches and what each mode's tick does with its part's decision; the
//!   failsafes' mode changes (hold, delayed return or landing, termination).
//!
//! The parts:
//! - `arming.rs`: [`arming::Arming`]: armed, when, whether airborne since; the pre-arm refusals
//!   and auto-disarm.
//! - `auto_paths.rs`: [`auto_paths::AutoPaths`]: the AUTO modes' paths, climbs and descents.
//! - `rtl.rs`: [`rtl::Rtl`]: AUTO.RTL's phases (climb, return round the fence, descend).
//! - `plans.rs`: [`plans::Plans`]: home, the uploaded geofence and rally points: which zones
//!   count, the arming refusal, the return destination (`RTL_TYPE`).
//! - `reactions.rs`: [`reactions::FailsafeState`]: the geofence / battery monitor, the battery
//!   gauge, the `COM_FAIL_ACT_T` hold, the position-loss descent; rotor failures and link losses
//!   as decisions.
//! - `navigation_checks.rs`: what the navigation estimate allows ([`NavValidity`]): mode
//!   requirements, pre-arm refusals, the position-loss descent.
//! - `mission_run.rs`: [`mission_run::MissionRun`]: AUTO.MISSION, item by item.
//! - `goto.rs`: DO_REPOSITION (the mode-change flag as PX4's commander reads it) and the GOTO
//!   mode it flies in.
//! - `offboard.rs`: [`offboard::Offboard`]: the offboard setpoint stream, its limiter and its loss.
//! - `manual.rs`: [`manual::ManualInput`]: the stick modes (POSCTL, ALTCTL, STABILIZED, ACRO),
//!   the sticks' loss (`NAV_RCL_ACT`) and a pilot taking over with the sticks.
//! - `orbit.rs`: [`orbit::OrbitMode`] (MAV_CMD_DO_ORBIT); `follow.rs`: [`follow::Follow`]
//!   (FOLLOW_TARGET).
//! - [`land_detector`]: on the ground or in the air, from what the vehicle does; `landing.rs`:
//!   what the verdict changes: touch-down thrust cut, idle on the ground, hold after a lift-off.
//! - `messages.rs`: requests, outcomes, events, landed state; `params.rs`: the settings.
//! - `failsafe.rs`, `battery.rs`, `mode.rs`: geofence/battery monitor, energy gauge, PX4 modes.
//! - `actions.rs`: the failsafe parameters' actions (`NAV_DLL_ACT`, `COM_OBL_RC_ACT`,
//!   `GF_ACTION`, `COM_LOW_BAT_ACT`) and `RTL_TYPE` as enums with PX4's codes.
//! - `script.rs` (tests only): a commander flying a vehicle that tracks its setpoints exactly.
//!
//! Home is the local NED origin. Wrong-state results follow PX4 (TEMPORARILY_REJECTED when
//! waiting can fix it, DENIED for bad values). What the commander does on its own (also in
//! answer to a request, as a link-loss reaction) is an [`Event`] of the next tick.

mod actions;
mod arming;
mod auto_paths;
mod battery;
mod commander_params;
mod failsafe;
mod flight_mode;
mod follow;
mod goto;
pub mod land_detector;
mod landing;
mod manual;
mod messages;
mod mission_run;
mod mode_switching;
mod navigation_checks;
mod offboard;
mod orbit;
mod plans;
mod reactions;
mod requests;
mod rtl;
#[cfg(test)]
mod script;

pub use actions::{
    ActuatorFailureAction, GeofenceAction, LinkLossAction, LowBatteryAction, ManualInputMode, ManualLossAction,
    OffboardLossAction, RtlType, UnknownAction,
};
pub use battery::{BatteryGauge, BatteryParams};
pub use commander_params::{AutoVertical, CommanderParams, ManualParams, MissionParams};
pub use failsafe::{
    BatteryLevel, Failsafe, FailsafeAction, FailsafeCause, FailsafeMonitor, FailsafeParams, FenceLimits,
};
pub use flight_mode::{FlightMode, ModeRefusal};
pub use land_detector::{LandDetectorParams, LandStage};
pub use messages::{CommanderTick, Event, InputStream, LandedState, Lean, OrbitRequest, Outcome, Request};
pub use mission_run::MissionState;
pub use navigation_checks::NavValidity;
pub use reactions::{LossAllocation, RotorLoss};

use arming::Arming;
use follow::Follow;
use land_detector::{LandDetector, LandInput, LandTransition};
use landing::FlightDemand;
use manual::ManualInput;
use mission_run::MissionRun;
use offboard::Offboard;
use orbit::OrbitMode;
use plans::Plans;
use reactions::FailsafeState;
use rtl::Rtl;

use crate::control::{FlatSetpoint, VehicleState};
use crate::guidance::Guidance;
use crate::math::{euler_zyx, Vec3};

/// Tick length assumed before the second tick [s].
const DEFAULT_DT_S: f64 = 0.001;

/// The [`auto_paths::AutoPaths`] of a commander, borrowing only its settings (its other fields
/// stay free to change meanwhile).
macro_rules! paths_of {
    ($c:expr) => {
        $crate::commander::auto_paths::AutoPaths::new(
            &$c.params,
            ($c.speed_override, $c.vertical_speeds),
            $c.detector.ground_z_m(),
            $c.plans.home_w().z,
        )
    };
}
pub(crate) use paths_of;

/// The vehicle and the clock of one tick, as the parts read them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Moment<'a> {
    /// The vehicle's state.
    pub x: &'a VehicleState,
    /// Its heading [rad].
    pub yaw_rad: f64,
    /// Time since the last tick [s].
    pub dt_s: f64,
    /// Simulated time [s].
    pub t_s: f64,
}

/// Armed state, mode and guidance of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Commander {
    /// Settings.
    pub params: CommanderParams,
    mode: FlightMode,
    detector: LandDetector,
    /// A take-off climb is under way (AUTO.TAKEOFF, a mission's take-off or first climb).
    climbing_out: bool,
    guidance: Guidance,
    takeoff_target_w: Option<Vec3>,
    /// DO_CHANGE_SPEED's (or a reposition's) horizontal speed [m/s].
    speed_override: Option<f64>,
    /// DO_CHANGE_SPEED's climb and descent speeds (ArduCopter's types 2 and 3) [m/s].
    vertical_speeds: (Option<f64>, Option<f64>),
    arming: Arming,
    rtl: Rtl,
    offboard: Offboard,
    manual: ManualInput,
    mission: MissionRun,
    orbit: OrbitMode,
    follow: Follow,
    plans: Plans,
    failsafe: FailsafeState,
    last_update_s: Option<f64>,
    /// Events of a request's reaction, announced at the start of the next tick.
    pending: Vec<Event>,
    /// The validity of the latest navigation estimate.
    nav: NavValidity,
}

impl Commander {
    /// Disarmed on the ground in AUTO.LOITER (PX4's default "Hold").
    pub fn new(params: CommanderParams) -> Self {
        Self {
            params,
            mode: FlightMode::Loiter,
            detector: LandDetector::default(),
            climbing_out: false,
            guidance: Guidance::Idle,
            takeoff_target_w: None,
            speed_override: None,
            vertical_speeds: (None, None),
            arming: Arming::default(),
            rtl: Rtl::default(),
            offboard: Offboard::default(),
            manual: ManualInput::default(),
            mission: MissionRun::default(),
            orbit: OrbitMode::default(),
            follow: Follow::default(),
            plans: Plans::default(),
            failsafe: FailsafeState::default(),
            last_update_s: None,
            pending: Vec::new(),
            nav: NavValidity::EXACT,
        }
    }

    /// The local NED point RTL returns to [m].
    pub fn home_w(&self) -> Vec3 {
        self.plans.home_w()
    }

    /// Current mission item, item count and mission state (MISSION_CURRENT).
    pub fn mission_progress(&self) -> (usize, usize, MissionState) {
        self.mission.progress()
    }

    /// The battery gauge and the pack it measures.
    pub fn battery(&self) -> (BatteryGauge, BatteryParams) {
        (self.failsafe.battery(), self.params.battery)
    }

    /// Armed.
    pub fn armed(&self) -> bool {
        self.arming.armed()
    }

    /// Current mode.
    pub fn mode(&self) -> FlightMode {
        self.mode
    }

    /// Armed and not on the ground (the land detector's verdict).
    pub fn in_air(&self) -> bool {
        self.arming.armed() && !self.detector.landed()
    }

    /// The land detector's stage.
    pub fn land_stage(&self) -> LandStage {
        self.detector.stage()
    }

    /// Landed state (EXTENDED_SYS_STATE): on the ground when the land detector says so; in the
    /// air, taking off during a take-off climb and landing during a final descent.
    pub fn landed_state(&self) -> LandedState {
        if !self.in_air() {
            LandedState::OnGround
        } else if self.climbing_out {
            LandedState::Takeoff
        } else if matches!(self.guidance, Guidance::Descend { .. }) {
            LandedState::Landing
        } else {
            LandedState::InAir
        }
    }

    /// A geofence limit is breached right now (SYS_STATUS health).
    pub fn geofence_breached(&self) -> bool {
        self.failsafe.geofence_breached()
    }

    /// The orbit flown (centre [m] and radius [m], positive clockwise) while in orbit mode.
    pub fn orbit_status(&self) -> Option<(Vec3, f64)> {
        self.orbit.status(self.mode == FlightMode::Orbit)
    }

    /// The validity of the latest estimate.
    pub fn navigation(&self) -> NavValidity {
        self.nav
    }

    /// Takes the estimate's validity `v` before the first tick (a flight controller that will
    /// fly on its navigation filter starts unaligned), without reacting to it.
    pub fn set_navigation(&mut self, v: NavValidity) {
        self.nav = v;
    }

    /// True when arming now would pass the navigation checks of the current mode (SYS_STATUS's
    /// pre-arm bit).
    pub fn navigation_armable(&self) -> bool {
        self.nav.missing(self.mode, true, self.params.arm_without_gps).is_none()
    }

    /// True while the vehicle descends without a position (the position-loss failsafe).
    pub fn descending_blind(&self) -> bool {
        self.failsafe.descending_blind()
    }

    /// One tick at simulated time `t_s` [s] with the vehicle in state `x` and the last tick's
    /// collective thrust over the believed weight `thrust_over_weight` [-]: the events pending
    /// from requests first, then mode progress, then land detection, touch-down and auto-disarm
    /// (see [`land_detector`]), then what to fly.
    pub fn update(&mut self, x: &VehicleState, thrust_over_weight: f64, t_s: f64) -> CommanderTick {
        let dt_s = self
            .last_update_s
            .map_or(DEFAULT_DT_S, |last| (t_s - last).clamp(1e-6, 0.1));
        self.last_update_s = Some(t_s);
        let mut events = std::mem::take(&mut self.pending);
        if !self.armed() {
            self.detect_landing(x, FlightDemand::Idle, thrust_over_weight, t_s, &mut events);
            return CommanderTick::idle(events);
        }
        self.watch_sticks(x, t_s, &mut events);
        if !self.armed() {
            return CommanderTick::idle(events);
        }
        self.run_delayed_failsafe(x, t_s, &mut events);
        let yaw = euler_zyx(&x.r_wb).z;
        let now = Moment {
            x,
            yaw_rad: yaw,
            dt_s,
            t_s,
        };
        let command = match self.mode {
            FlightMode::Takeoff => {
                self.complete_takeoff(x, yaw, t_s, &mut events);
                None
            }
            FlightMode::ReturnToLaunch => {
                self.advance_rtl(x, yaw, t_s);
                None
            }
            FlightMode::Mission => {
                self.advance_mission(now, &mut events);
                None
            }
            FlightMode::Offboard => self.offboard_command(now, &mut events),
            FlightMode::Guided => self.guided_command(now, &mut events),
            FlightMode::Orbit => {
                self.advance_orbit(dt_s, t_s);
                None
            }
            FlightMode::FollowTarget => self.follow_command(now),
            FlightMode::Goto => {
                self.advance_goto();
                None
            }
            // A user take-off in a stick mode climbs first; the sticks fly from its top.
            mode if mode.flown_by_sticks() && self.climbing_out => {
                self.complete_takeoff(x, yaw, t_s, &mut events);
                None
            }
            mode if mode.flown_by_sticks() => Some(self.stick_command(now)),
            _ => None,
        };
        if !self.armed() {
            return CommanderTick::idle(events);
        }
        self.pace_climb(x);
        let command = command.unwrap_or_else(|| match self.guidance.setpoint(t_s, x) {
            Some(sp) => FlightDemand::Flat(sp),
            None => FlightDemand::Idle,
        });
        let command = match command {
            FlightDemand::Flat(sp) if self.failsafe.descending_blind() => {
                FlightDemand::Flat(navigation_checks::without_horizontal(sp, x))
            }
            command => command,
        };
        let command = self.detect_landing(x, command, thrust_over_weight, t_s, &mut events);
        match command {
            FlightDemand::Flat(sp) => CommanderTick {
                setpoint: Some(sp),
                attitude: None,
                events,
            },
            FlightDemand::Attitude(target) => CommanderTick {
                setpoint: None,
                attitude: Some(target),
                events,
            },
            FlightDemand::Idle => CommanderTick::idle(events),
        }
    }

    /// Runs the land detector on this tick's `command` and applies its verdict: the command to
    /// fly, with touch-down, lift-off and auto-disarm events (only ever on the ground, so no
    /// path stops the motors in the air except a termination).
    fn detect_landing(
        &mut self,
        x: &VehicleState,
        command: FlightDemand,
        thrust_over_weight: f64,
        t_s: f64,
        events: &mut Vec<Event>,
    ) -> FlightDemand {
        let input = LandInput {
            armed: self.arming.armed(),
            descent_commanded: landing::descent_commanded(&command, x, thrust_over_weight, self.detector.ground_z_m()),
            thrust_over_weight,
        };
        match self.detector.update(&self.params.land_detector, &input, x, t_s) {
            Some(LandTransition::Landed) if self.arming.armed() => {
                self.climbing_out = false;
                events.push(Event::Landed);
            }
            Some(LandTransition::Airborne) => {
                self.arming.took_off();
                events.push(Event::Airborne);
                if self.guidance == Guidance::Idle && !matches!(command, FlightDemand::Attitude(_)) {
                    // Lifted with nothing to fly (idle in a hold mode): hold where it is.
                    self.guidance = Guidance::Hold {
                        pos_w: x.pos_w,
                        yaw_rad: euler_zyx(&x.r_wb).z,
                    };
                    return FlightDemand::Flat(FlatSetpoint::hold(x.pos_w, euler_zyx(&x.r_wb).z));
                }
            }
            _ => {}
        }
        if !self.arming.armed() {
            return FlightDemand::Idle;
        }
        if self.detector.landed() {
            let landed_at_s = self.detector.landed_at_s();
            if let Some(why) = self.arming.auto_disarm_reason(&self.params, landed_at_s, t_s) {
                self.disarm();
                events.push(Event::Disarmed(why));
                return FlightDemand::Idle;
            }
        }
        landing::near_ground(&self.detector, command, x, self.params.land_speed_m_s)
    }
}

#[cfg(test)]
mod tests {
    use super::script::{Script, GROUND_Z_M};
    use super::*;

    #[test]
    fn a_new_commander_is_disarmed_on_the_ground_in_auto_loiter_and_idles() {
        let mut s = Script::new(CommanderParams::default());
        assert!(!s.c.armed() && !s.c.in_air());
        assert_eq!(s.c.mode(), FlightMode::Loiter);
        assert_eq!(s.c.landed_state(), LandedState::OnGround);
        assert_eq!(s.c.land_stage(), LandStage::Landed);
        assert_eq!(s.c.home_w(), Vec3::zeros());
        assert_eq!(s.c.mission_progress(), (0, 0, MissionState::NoMission));
        assert!(s.fly(1.0).is_empty());
        assert_eq!(s.last.as_ref().map(|t| (t.setpoint, t.attitude)), Some((None, None)));
        assert_eq!(s.x.pos_w.z, GROUND_Z_M);
    }

    #[test]
    fn the_landed_state_follows_a_flight_and_the_battery_drains_while_armed() {
        let mut s = Script::new(CommanderParams::default());
        s.power_w = 300.0;
        s.fly(1.0);
        assert_eq!(s.c.battery().0.used_j(), 0.0, "nothing drawn disarmed");
        assert_eq!(s.request(Request::Takeoff { height_m: Some(4.0) }), Outcome::Accepted);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        let mut seen = vec![s.c.landed_state()];
        let mut record = |s: &Script| {
            if seen.last() != Some(&s.c.landed_state()) {
                seen.push(s.c.landed_state());
            }
        };
        assert!(s.fly_until(60.0, |s| {
            record(s);
            s.c.mode() == FlightMode::Loiter
        }));
        assert_eq!(s.request(Request::Land), Outcome::Accepted);
        assert!(s.fly_until(60.0, |s| {
            record(s);
            !s.c.armed()
        }));
        use LandedState::*;
        assert_eq!(seen, vec![OnGround, Takeoff, InAir, Landing, OnGround]);
        let (gauge, pack) = s.c.battery();
        assert!(gauge.used_j() > 0.0 && gauge.fraction(&pack) < 1.0);
    }

    #[test]
    fn events_of_a_request_come_first_in_the_next_tick_even_disarmed() {
        let mut s = Script::new(CommanderParams::default());
        s.c.pending.push(Event::Failsafe(FailsafeCause::Other, "queued".into()));
        assert_eq!(s.step(), vec![Event::Failsafe(FailsafeCause::Other, "queued".into())]);
        assert!(s.step().is_empty(), "announced once");
    }
}
