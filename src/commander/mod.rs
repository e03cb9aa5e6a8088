//! The commander (PX4 semantics): armed state, flight mode, landed state, take-off / hold /
//! land / return / mission / offboard, all on simulated time. Pure: requests and the vehicle
//! state in, a result and a setpoint out.
//!
//! # Layout
//! - `mod.rs`: requests, modes and their guidance, the tick.
//! - `messages.rs`: requests, outcomes, events, landed state; `params.rs`: the settings.
//! - [`land_detector`]: on the ground or in the air, from what the vehicle does.
//! - `landing.rs`: what the verdict changes: touch-down thrust cut, idle on the ground,
//!   hold after a lift-off, auto-disarm (only ever on the ground).
//! - `offboard.rs`: the offboard setpoint stream, its limiter and its loss.
//! - `mission_run.rs`: AUTO.MISSION, item by item.
//! - `reactions.rs`: failsafes, rotor failures and GCS link loss.
//! - `failsafe.rs`, `battery.rs`, `mode.rs`: geofence/battery monitor, energy gauge, PX4 modes.
//! - `actions.rs`: the failsafe parameters' actions (`NAV_DLL_ACT`, `COM_OBL_RC_ACT`,
//!   `GF_ACTION`, `COM_LOW_BAT_ACT`) as enums with PX4's codes.
//!
//! Home is the local NED origin. Wrong-state results follow PX4 (TEMPORARILY_REJECTED when
//! waiting can fix it, DENIED for bad values).

mod actions;
mod battery;
mod failsafe;
pub mod land_detector;
mod landing;
mod messages;
mod mission_run;
mod mode;
mod offboard;
mod params;
mod reactions;

pub use actions::{GeofenceAction, LinkLossAction, LowBatteryAction, OffboardLossAction, UnknownAction};
pub use battery::{BatteryGauge, BatteryParams};
pub use failsafe::{BatteryLevel, Failsafe, FailsafeAction, FailsafeMonitor, FailsafeParams};
pub use land_detector::{LandDetectorParams, LandStage};
pub use messages::{CommanderTick, Event, LandedState, Outcome, Request};
pub use mission_run::MissionState;
pub use mode::{FlightMode, ModeRefusal};
pub use params::CommanderParams;

use land_detector::LandDetector;
use landing::Command;
use mission_run::MissionRun;
use offboard::{Offboard, OffboardTarget};

use crate::control::VehicleState;
use crate::math::{euler_zyx, Vec3};
use crate::navigation::{DescentProfile, Guidance, MotionLimits};

/// Tick length assumed before the second tick [s].
const DEFAULT_DT_S: f64 = 0.001;
/// Take-off is complete within this distance of the target [m].
const TAKEOFF_ACCEPT_M: f64 = 0.2;

/// Armed state, mode and guidance of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Commander {
    /// Settings.
    pub params: CommanderParams,
    armed: bool,
    mode: FlightMode,
    detector: LandDetector,
    /// A take-off climb is under way (AUTO.TAKEOFF, a mission's take-off or first climb).
    climbing_out: bool,
    guidance: Guidance,
    takeoff_target_w: Option<Vec3>,
    rtl_phase: RtlPhase,
    armed_at_s: f64,
    /// The vehicle has been in the air since it was armed.
    took_off: bool,
    offboard: Offboard,
    mission: MissionRun,
    speed_override: Option<f64>,
    home_w: Vec3,
    failsafes: FailsafeMonitor,
    battery: BatteryGauge,
    last_update_s: Option<f64>,
}

/// RTL phases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RtlPhase {
    Climb,
    Return,
    Descend,
}

impl Commander {
    /// Disarmed on the ground in AUTO.LOITER (PX4's default "Hold").
    pub fn new(params: CommanderParams) -> Self {
        Self {
            params,
            armed: false,
            mode: FlightMode::Loiter,
            detector: LandDetector::default(),
            climbing_out: false,
            guidance: Guidance::Idle,
            takeoff_target_w: None,
            rtl_phase: RtlPhase::Climb,
            armed_at_s: 0.0,
            took_off: false,
            offboard: Offboard::default(),
            mission: MissionRun::default(),
            speed_override: None,
            home_w: Vec3::zeros(),
            failsafes: FailsafeMonitor::default(),
            battery: BatteryGauge::default(),
            last_update_s: None,
        }
    }

    /// Horizontal speed of the AUTO modes [m/s]: DO_CHANGE_SPEED's, else `MPC_XY_CRUISE`.
    fn cruise_speed(&self) -> f64 {
        self.speed_override.unwrap_or(self.params.cruise_speed_m_s)
    }

    /// Path limits for a horizontal speed of `horizontal_m_s` [m/s], capped at
    /// `MPC_XY_VEL_MAX`; every other limit as set.
    fn limits(&self, horizontal_m_s: f64) -> MotionLimits {
        MotionLimits {
            horizontal_m_s: horizontal_m_s.min(self.params.motion.horizontal_m_s),
            ..self.params.motion
        }
    }

    /// A path at the cruise speed from where the vehicle is to `to_w` [m], ending at heading
    /// `to_yaw_rad` [rad] (turned the short way within `MPC_YAWRAUTO_MAX`).
    fn path_to(&self, x: &VehicleState, to_w: Vec3, to_yaw_rad: f64, speed_m_s: f64, t_s: f64) -> Guidance {
        let yaw = euler_zyx(&x.r_wb).z;
        Guidance::path(x.pos_w, to_w, yaw, to_yaw_rad, &self.limits(speed_m_s), t_s)
    }

    /// The local NED point RTL returns to [m].
    pub fn home_w(&self) -> Vec3 {
        self.home_w
    }

    /// Current mission item, item count and mission state (MISSION_CURRENT).
    pub fn mission_progress(&self) -> (usize, usize, MissionState) {
        (self.mission.seq, self.mission.mission.len(), self.mission.state)
    }

    /// The battery gauge and the pack it measures.
    pub fn battery(&self) -> (BatteryGauge, BatteryParams) {
        (self.battery, self.params.battery)
    }

    /// Armed.
    pub fn armed(&self) -> bool {
        self.armed
    }

    /// Current mode.
    pub fn mode(&self) -> FlightMode {
        self.mode
    }

    /// Armed and not on the ground (the land detector's verdict).
    pub fn in_air(&self) -> bool {
        self.armed && !self.detector.landed()
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

    /// Handles `request` at simulated time `t_s` [s] with the vehicle in state `x`.
    pub fn request(&mut self, request: Request, x: &VehicleState, t_s: f64) -> Outcome {
        match request {
            Request::Arm { force } => self.arm(force, x, t_s),
            Request::Disarm { force } => {
                if self.in_air() && !force {
                    return Outcome::TemporarilyRejected("Disarm refused: vehicle in the air".into());
                }
                self.disarm();
                Outcome::Accepted
            }
            Request::SetMode(mode) => self.set_mode(mode, x, t_s),
            Request::Takeoff { height_m } => {
                if self.in_air() {
                    return Outcome::TemporarilyRejected("Takeoff refused: already flying".into());
                }
                let h = height_m.unwrap_or(self.params.takeoff_alt_m);
                if !(h.is_finite() && h > 0.0 && h <= 1000.0) {
                    return Outcome::Denied(format!("Takeoff refused: height {h} m"));
                }
                self.takeoff_target_w = Some(Vec3::new(x.pos_w.x, x.pos_w.y, -h));
                self.enter(FlightMode::Takeoff, x, t_s);
                Outcome::Accepted
            }
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
            Request::SetMission(mission) => {
                self.mission.replace(mission);
                if self.mode == FlightMode::Mission {
                    self.enter(FlightMode::Loiter, x, t_s);
                }
                Outcome::Accepted
            }
            Request::Reposition {
                north_m,
                east_m,
                down_m,
                yaw_rad,
                speed_m_s,
            } => {
                if !self.in_air() {
                    return Outcome::TemporarilyRejected("Reposition refused: not flying".into());
                }
                let target = Vec3::new(
                    north_m.unwrap_or(x.pos_w.x),
                    east_m.unwrap_or(x.pos_w.y),
                    down_m.unwrap_or(x.pos_w.z),
                );
                if !target.iter().all(|v| v.is_finite()) {
                    return Outcome::Denied("Reposition refused: bad target".into());
                }
                self.enter(FlightMode::Loiter, x, t_s);
                let yaw = yaw_rad.unwrap_or(euler_zyx(&x.r_wb).z);
                let speed = speed_m_s.filter(|v| *v > 0.0).unwrap_or(self.cruise_speed());
                self.guidance = self.path_to(x, target, yaw, speed, t_s);
                Outcome::Accepted
            }
            Request::ChangeSpeed(v) => {
                if !(v.is_finite() && v > 0.0 && v <= 30.0) {
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
            Request::InjectRotorFailure { .. } => {
                Outcome::Denied("Failure injection is applied by the vehicle, not the commander".into())
            }
            Request::StartMission { first } => {
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
    }

    fn arm(&mut self, force: bool, x: &VehicleState, t_s: f64) -> Outcome {
        if self.armed {
            return Outcome::Accepted;
        }
        if !force {
            match self.mode {
                FlightMode::Mission if self.mission.mission.is_empty() => {
                    return Outcome::TemporarilyRejected("Arming denied: no mission".into())
                }
                FlightMode::Offboard if !self.offboard_alive(t_s) => {
                    return Outcome::TemporarilyRejected("Arming denied: no offboard setpoints".into())
                }
                FlightMode::Land | FlightMode::ReturnToLaunch => {
                    return Outcome::TemporarilyRejected(format!("Arming denied: not in {}", self.mode.name()))
                }
                _ => {}
            }
        }
        self.armed = true;
        self.armed_at_s = t_s;
        self.took_off = !self.detector.landed();
        self.enter(self.mode, x, t_s);
        Outcome::Accepted
    }

    /// Motors off (explicit disarm, auto-disarm on the ground, or a termination).
    fn disarm(&mut self) {
        self.armed = false;
        self.guidance = Guidance::Idle;
        self.climbing_out = false;
        if matches!(
            self.mode,
            FlightMode::Takeoff | FlightMode::Land | FlightMode::ReturnToLaunch
        ) {
            self.mode = FlightMode::Loiter;
        }
    }

    fn set_mode(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64) -> Outcome {
        match mode {
            FlightMode::Mission if self.mission.mission.is_empty() => {
                Outcome::TemporarilyRejected("Mode AUTO.MISSION: no mission".into())
            }
            FlightMode::Offboard if !self.offboard_alive(t_s) => {
                Outcome::TemporarilyRejected("Mode OFFBOARD: no setpoint stream".into())
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
    fn enter(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64) {
        if self.mode == FlightMode::Mission && mode != FlightMode::Mission && self.mission.state == MissionState::Active
        {
            self.mission.state = MissionState::Paused;
        }
        self.mode = mode;
        self.climbing_out = false;
        self.offboard.limiter = None;
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
                    self.path_to(x, target, yaw, self.cruise_speed(), t_s)
                }
                FlightMode::Land => self.descend(x, yaw, t_s),
                FlightMode::ReturnToLaunch => {
                    self.rtl_phase = RtlPhase::Climb;
                    let z = x.pos_w.z.min(self.home_w.z - self.params.rtl_return_alt_m);
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

    fn descend(&self, x: &VehicleState, yaw: f64, t_s: f64) -> Guidance {
        Guidance::Descend {
            xy_w: x.pos_w,
            yaw_rad: yaw,
            z_start_m: x.pos_w.z,
            start_s: t_s,
            profile: DescentProfile {
                fast_m_s: self.params.motion.down_m_s,
                land_m_s: self.params.land_speed_m_s,
                slow_from_m: self.params.land_alt1_m,
                land_from_m: self.params.land_alt2_m,
                acc_m_s2: self.params.motion.acc_down_m_s2,
            },
        }
    }

    /// One tick at simulated time `t_s` [s] with the vehicle in state `x` and the last tick's
    /// collective thrust over the believed weight `thrust_over_weight` [-]: mode progress, then
    /// land detection, touch-down and auto-disarm (see [`land_detector`]), then what to fly.
    pub fn update(&mut self, x: &VehicleState, thrust_over_weight: f64, t_s: f64) -> CommanderTick {
        let dt_s = self
            .last_update_s
            .map_or(DEFAULT_DT_S, |last| (t_s - last).clamp(1e-6, 0.1));
        self.last_update_s = Some(t_s);
        let mut events = Vec::new();
        if !self.armed {
            self.detect_landing(x, Command::Idle, thrust_over_weight, t_s, &mut events);
            return CommanderTick::idle(events);
        }
        let yaw = euler_zyx(&x.r_wb).z;
        let command = match self.mode {
            FlightMode::Takeoff => {
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
                None
            }
            FlightMode::ReturnToLaunch => {
                self.advance_rtl(x, yaw, t_s);
                None
            }
            FlightMode::Mission => {
                self.advance_mission(x, yaw, t_s, &mut events);
                None
            }
            FlightMode::Offboard => self.offboard_command(x, yaw, dt_s, t_s, &mut events),
            _ => None,
        };
        if !self.armed {
            return CommanderTick::idle(events);
        }
        let command = command.unwrap_or_else(|| match self.guidance.setpoint(t_s, x) {
            Some(sp) => Command::Flat(sp),
            None => Command::Idle,
        });
        let command = self.detect_landing(x, command, thrust_over_weight, t_s, &mut events);
        match command {
            Command::Flat(sp) => CommanderTick {
                setpoint: Some(sp),
                attitude: None,
                events,
            },
            Command::Attitude(target) => CommanderTick {
                setpoint: None,
                attitude: Some(target),
                events,
            },
            Command::Idle => CommanderTick::idle(events),
        }
    }

    fn advance_rtl(&mut self, x: &VehicleState, yaw: f64, t_s: f64) {
        if !self.guidance.finished(t_s) {
            return;
        }
        match self.rtl_phase {
            RtlPhase::Climb => {
                self.rtl_phase = RtlPhase::Return;
                let home_at_alt = Vec3::new(self.home_w.x, self.home_w.y, x.pos_w.z);
                self.guidance = self.path_to(x, home_at_alt, yaw, self.cruise_speed(), t_s);
            }
            RtlPhase::Return => {
                self.rtl_phase = RtlPhase::Descend;
                self.guidance = self.descend(x, yaw, t_s);
            }
            RtlPhase::Descend => {}
        }
    }
}
