//! The commander (PX4 semantics, mavlink.md §2–§3): armed state, flight mode, landed state,
//! take-off / hold / land / return, land detection and auto-disarm, all on simulated time.
//! Pure: requests and the vehicle state in, a result and a setpoint out.
//!
//! Home is the local NED origin. Wrong-state results follow mavlink.md §3.3.

mod battery;
mod failsafe;
mod mission_run;
mod mode;

pub use battery::{BatteryGauge, BatteryParams};
pub use failsafe::{BatteryLevel, Failsafe, FailsafeAction, FailsafeMonitor, FailsafeParams};
pub use mission_run::MissionState;
pub use mode::{FlightMode, ModeRefusal};

use mission_run::MissionRun;

use crate::allocation::FailedRotors;
use crate::control::{AttitudeTarget, FlatSetpoint, VehicleState};
use crate::math::{euler_zyx, Vec3};
use crate::navigation::{Guidance, Mission, SpeedLimits};

/// Speed below which a vehicle that is asked to descend counts as landed [m/s].
const LANDED_SPEED_M_S: f64 = 0.1;
/// How long it must stay that slow [s].
const LANDED_CONFIRM_S: f64 = 1.0;
/// Take-off is complete within this distance of the target [m].
const TAKEOFF_ACCEPT_M: f64 = 0.2;

/// Commander settings (PX4 parameter names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommanderParams {
    /// Take-off height above home [m] (`MIS_TAKEOFF_ALT`, 2.5).
    pub takeoff_alt_m: f64,
    /// Climb speed [m/s] (`MPC_Z_VEL_MAX_UP`, 3.0).
    pub climb_speed_m_s: f64,
    /// Landing descent speed [m/s] (`MPC_LAND_SPEED`, 0.7).
    pub land_speed_m_s: f64,
    /// Horizontal cruise speed of the AUTO modes [m/s] (`MPC_XY_CRUISE`, 5.0).
    pub cruise_speed_m_s: f64,
    /// Return altitude above home [m] (`RTL_RETURN_ALT`, 60).
    pub rtl_return_alt_m: f64,
    /// Disarm this long after landing [s] (`COM_DISARM_LAND`, 2.0; ≤ 0 never).
    pub disarm_land_s: f64,
    /// Disarm this long after arming without taking off [s] (`COM_DISARM_PRFLT`, 10; ≤ 0 never).
    pub disarm_preflight_s: f64,
    /// Offboard setpoints older than this are lost [s] (`COM_OF_LOSS_T`, 1.0).
    pub offboard_loss_s: f64,
    /// GCS link-loss action (`NAV_DLL_ACT`: 0 off, 1 hold, 2 return, 3 land, 5 terminate, 6 disarm).
    pub link_loss_action: i32,
    /// GCS silence that counts as link loss [s] (`COM_DL_LOSS_T`, 10).
    pub link_loss_s: f64,
    /// Geofence and battery failsafes.
    pub failsafe: FailsafeParams,
    /// The battery pack.
    pub battery: BatteryParams,
    /// Failure injection allowed (`SYS_FAILURE_EN`, 0).
    pub failure_injection: bool,
    /// Offboard-loss action (`COM_OBL_RC_ACT`: 0–2 hold position (no RC), 3 return, 4 land,
    /// 5 hold (AUTO.LOITER), 6 terminate, 7 disarm; default 0).
    pub offboard_loss_action: i32,
    /// Largest horizontal speed of any AUTO path [m/s] (`MPC_XY_VEL_MAX`, 12); caps cruise and
    /// DO_CHANGE_SPEED / DO_REPOSITION speeds.
    pub xy_vel_max_m_s: f64,
    /// Largest descent speed of any AUTO path [m/s] (`MPC_Z_VEL_MAX_DN`, 1.5); the final landing
    /// descends at `land_speed_m_s`.
    pub descent_speed_m_s: f64,
}

impl Default for CommanderParams {
    fn default() -> Self {
        Self {
            takeoff_alt_m: 2.5,
            climb_speed_m_s: 3.0,
            land_speed_m_s: 0.7,
            cruise_speed_m_s: 5.0,
            rtl_return_alt_m: 60.0,
            disarm_land_s: 2.0,
            disarm_preflight_s: 10.0,
            offboard_loss_s: 1.0,
            link_loss_action: 0,
            link_loss_s: 10.0,
            xy_vel_max_m_s: 12.0,
            descent_speed_m_s: 1.5,
            failsafe: FailsafeParams::default(),
            battery: BatteryParams::default(),
            failure_injection: false,
            offboard_loss_action: 0,
        }
    }
}

/// MAVLink landed state (EXTENDED_SYS_STATE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LandedState {
    /// On the ground.
    OnGround,
    /// Flying.
    InAir,
    /// Climbing out after take-off.
    Takeoff,
    /// Descending to land.
    Landing,
}

/// A request from a ground station.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// Arm; `force` skips the pre-arm checks.
    Arm {
        /// Force (21196 / 2989).
        force: bool,
    },
    /// Disarm; `force` also in the air.
    Disarm {
        /// Force (21196 / 2989).
        force: bool,
    },
    /// Switch mode.
    SetMode(FlightMode),
    /// NAV_TAKEOFF to `height_m` above home [m] (`None`: `MIS_TAKEOFF_ALT`).
    Takeoff {
        /// Target height above home [m].
        height_m: Option<f64>,
    },
    /// NAV_LAND here.
    Land,
    /// NAV_RETURN_TO_LAUNCH.
    ReturnToLaunch,
    /// An offboard setpoint (SET_POSITION_TARGET_*), kept as the latest; with `body_frame` its
    /// velocity and acceleration are in the heading frame (MAV_FRAME_BODY_NED).
    OffboardSetpoint {
        /// The setpoint.
        setpoint: FlatSetpoint,
        /// Velocity/acceleration in the heading frame.
        body_frame: bool,
    },
    /// An offboard attitude / rate target (SET_ATTITUDE_TARGET), kept as the latest.
    OffboardAttitude(AttitudeTarget),
    /// Replace the stored mission (a mission replaced during AUTO.MISSION switches to AUTO.LOITER).
    SetMission(Mission),
    /// MISSION_START: fly the stored mission from `first` (item index).
    StartMission {
        /// First item.
        first: usize,
    },
    /// DO_REPOSITION: go to `pos_w` and hold there in AUTO.LOITER; unset coordinates keep the
    /// current ones, `yaw_rad` `None` keeps the heading, `speed_m_s` `None` the cruise speed.
    Reposition {
        /// Target north [m], `None` = current.
        north_m: Option<f64>,
        /// Target east [m], `None` = current.
        east_m: Option<f64>,
        /// Target down [m], `None` = current.
        down_m: Option<f64>,
        /// Heading [rad].
        yaw_rad: Option<f64>,
        /// Ground speed [m/s].
        speed_m_s: Option<f64>,
    },
    /// MAV_CMD_INJECT_FAILURE for motors (`SYS_FAILURE_EN` = 1): rotor `rotor` (1-based; 0 =
    /// every rotor) stops (`failed`) or works again. The vehicle applies it to the plant; the
    /// commander hears of it through [`Commander::rotor_failed`].
    InjectRotorFailure {
        /// Rotor, 1-based; 0 = all.
        rotor: usize,
        /// Stop (true) or restore (false).
        failed: bool,
    },
    /// DO_CHANGE_SPEED: horizontal speed of the AUTO modes [m/s] until changed again.
    ChangeSpeed(f64),
    /// DO_SET_HOME: the local NED point RTL returns to [m]; `None`: the current position.
    SetHome(Option<Vec3>),
    /// No GCS heartbeat for `COM_DL_LOSS_T`: run `NAV_DLL_ACT` if flying.
    GcsLinkLost,
}

/// The result of a request (MAV_RESULT), with the reason of a refusal for STATUSTEXT.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// Valid and started.
    Accepted,
    /// Not now; fixable by waiting.
    TemporarilyRejected(String),
    /// Invalid.
    Denied(String),
    /// A coordinate frame the command cannot use (MAV_RESULT_UNSUPPORTED_MAV_FRAME).
    Unsupported(String),
    /// Understood but not possible on this vehicle (MAV_RESULT_FAILED).
    Failed(String),
}

/// Something the commander did on its own, to announce.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    /// Auto-disarm, with the reason.
    Disarmed(&'static str),
    /// The mode changed without a request (take-off done → loiter, landed → ...).
    ModeChanged(FlightMode),
    /// Touch-down detected.
    Landed,
    /// Offboard setpoints stopped for `COM_OF_LOSS_T`; the vehicle holds position.
    OffboardLost,
    /// A geofence or battery failsafe triggered (the announcement).
    Failsafe(String),
    /// Mission item `seq` reached (MISSION_ITEM_REACHED).
    MissionItemReached(u16),
    /// The current mission item changed (MISSION_CURRENT at once).
    MissionCurrent(u16),
}

/// What NAV_DLL_ACT did, for the announcement.
fn link_loss_text(action: i32) -> &'static str {
    match action {
        1 => "GCS link lost: holding",
        2 => "GCS link lost: returning",
        3 => "GCS link lost: landing",
        5 => "GCS link lost: terminating",
        6 => "GCS link lost: disarming",
        _ => "GCS link lost",
    }
}

impl Event {
    /// The STATUSTEXT announcing it.
    pub fn describe(&self) -> String {
        match self {
            Self::Disarmed(why) => format!("Disarmed: {why}"),
            Self::ModeChanged(mode) => format!("Mode {}", mode.name()),
            Self::Landed => "Landing detected".to_string(),
            Self::OffboardLost => "Offboard lost".to_string(),
            Self::Failsafe(text) => text.clone(),
            Self::MissionItemReached(seq) => format!("Mission item {seq} reached"),
            Self::MissionCurrent(seq) => format!("Mission item {seq}"),
        }
    }
}

/// One tick's output.
#[derive(Debug, Clone, PartialEq)]
pub struct CommanderTick {
    /// Setpoint to fly; `None`: motors off (or `attitude` flies).
    pub setpoint: Option<FlatSetpoint>,
    /// Offboard attitude / rate target to fly instead of `setpoint`.
    pub attitude: Option<AttitudeTarget>,
    /// What happened on its own this tick.
    pub events: Vec<Event>,
}

/// The latest offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
enum OffboardKind {
    /// Position / velocity / acceleration, with the body-frame flag.
    Flat(FlatSetpoint, bool),
    /// Attitude or rates with thrust.
    Attitude(AttitudeTarget),
}

/// RTL phases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RtlPhase {
    Climb,
    Return,
    Descend,
}

/// Armed state, mode and guidance of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Commander {
    /// Settings.
    pub params: CommanderParams,
    armed: bool,
    mode: FlightMode,
    landed: LandedState,
    guidance: Guidance,
    takeoff_target_w: Option<Vec3>,
    rtl_phase: RtlPhase,
    armed_at_s: f64,
    slow_since_s: Option<f64>,
    landed_at_s: Option<f64>,
    took_off: bool,
    offboard: Option<(OffboardKind, f64)>,
    mission: MissionRun,
    speed_override: Option<f64>,
    home_w: Vec3,
    failsafes: FailsafeMonitor,
    battery: BatteryGauge,
}

impl Commander {
    /// Disarmed on the ground in AUTO.LOITER (PX4's default "Hold").
    pub fn new(params: CommanderParams) -> Self {
        Self {
            params,
            armed: false,
            mode: FlightMode::Loiter,
            landed: LandedState::OnGround,
            guidance: Guidance::Idle,
            takeoff_target_w: None,
            rtl_phase: RtlPhase::Climb,
            armed_at_s: 0.0,
            slow_since_s: None,
            landed_at_s: None,
            took_off: false,
            offboard: None,
            mission: MissionRun::default(),
            speed_override: None,
            home_w: Vec3::zeros(),
            failsafes: FailsafeMonitor::default(),
            battery: BatteryGauge::default(),
        }
    }

    /// Horizontal speed of the AUTO modes [m/s]: DO_CHANGE_SPEED's, else `MPC_XY_CRUISE`.
    fn cruise_speed(&self) -> f64 {
        self.speed_override.unwrap_or(self.params.cruise_speed_m_s)
    }

    /// Path speed limits for a horizontal speed of `horizontal_m_s` [m/s], capped at
    /// `MPC_XY_VEL_MAX`; climbs at `MPC_Z_VEL_MAX_UP`, descents at `MPC_Z_VEL_MAX_DN`.
    fn limits(&self, horizontal_m_s: f64) -> SpeedLimits {
        SpeedLimits {
            horizontal_m_s: horizontal_m_s.min(self.params.xy_vel_max_m_s),
            up_m_s: self.params.climb_speed_m_s,
            down_m_s: self.params.descent_speed_m_s,
        }
    }

    /// The local NED point RTL returns to [m].
    pub fn home_w(&self) -> Vec3 {
        self.home_w
    }

    /// Current mission item, item count and mission state (MISSION_CURRENT).
    pub fn mission_progress(&self) -> (usize, usize, MissionState) {
        (self.mission.seq, self.mission.mission.len(), self.mission.state)
    }

    /// Draws `power_w` [W] from the battery for `dt_s` [s], then runs the geofence and battery
    /// failsafes for state `x` at `t_s` [s]: each announces itself and switches the mode (hold,
    /// return, land) or terminates, which the next heartbeat shows.
    pub fn check_failsafes(&mut self, x: &VehicleState, power_w: f64, dt_s: f64, t_s: f64) -> Vec<Event> {
        self.battery.draw(power_w, dt_s);
        let rel = x.pos_w - self.home_w;
        let in_air = self.armed && self.landed != LandedState::OnGround;
        let fired = self.failsafes.check(
            &self.params.failsafe,
            [rel.x, rel.y, rel.z],
            self.battery.fraction(&self.params.battery),
            in_air,
        );
        let mut events = Vec::new();
        for failsafe in fired {
            events.push(Event::Failsafe(failsafe.text));
            let mode = match failsafe.action {
                FailsafeAction::Warn => None,
                FailsafeAction::Hold => Some(FlightMode::Loiter),
                FailsafeAction::Return => Some(FlightMode::ReturnToLaunch),
                FailsafeAction::Land => Some(FlightMode::Land),
                FailsafeAction::Terminate => {
                    self.disarm();
                    events.push(Event::Disarmed("flight termination"));
                    None
                }
            };
            // Never step back from landing to a return, nor restart a mode already running.
            let landing = self.mode == FlightMode::Land;
            if let Some(mode) = mode.filter(|m| *m != self.mode && !landing) {
                self.enter(mode, x, t_s);
                events.push(Event::ModeChanged(mode));
            }
        }
        events
    }

    /// Rotor `rotor` (1-based) has failed; `control` says what the allocation can still do
    /// (`None`: nothing useful). In flight the vehicle lands where it is, as well as it can.
    pub fn rotor_failed(
        &mut self,
        rotor: usize,
        control: Option<FailedRotors>,
        x: &VehicleState,
        t_s: f64,
    ) -> Vec<Event> {
        let what = match control {
            Some(FailedRotors::FullControl) => "",
            Some(FailedRotors::YawUncontrolled) => ", yaw lost",
            None => ", no allocation left",
        };
        let in_air = self.armed && self.landed != LandedState::OnGround;
        let mut events = vec![Event::Failsafe(format!(
            "Motor {rotor} failed{what}{}",
            if in_air { ": landing" } else { "" }
        ))];
        if in_air && self.mode != FlightMode::Land {
            self.enter(FlightMode::Land, x, t_s);
            events.push(Event::ModeChanged(FlightMode::Land));
        }
        events
    }

    /// The battery gauge and the pack it measures.
    pub fn battery(&self) -> (BatteryGauge, BatteryParams) {
        (self.battery, self.params.battery)
    }

    /// Restamps the latest offboard setpoint at `t_s` [s]: the runtime calls this while the
    /// setpoint stream is alive in wall time, so a ground station streaming in wall time does not
    /// lose offboard just because simulated time runs faster (mavlink.md §11.2). A stream that
    /// stops is lost once it is silent for `COM_OF_LOSS_T` in both clocks.
    pub fn refresh_offboard(&mut self, t_s: f64) {
        if let Some((_, t)) = &mut self.offboard {
            *t = t.max(t_s);
        }
    }

    /// True when an offboard setpoint arrived within `COM_OF_LOSS_T` of `t_s`.
    fn offboard_alive(&self, t_s: f64) -> bool {
        self.offboard
            .is_some_and(|(_, t)| t_s - t < self.params.offboard_loss_s)
    }

    /// Armed.
    pub fn armed(&self) -> bool {
        self.armed
    }

    /// Current mode.
    pub fn mode(&self) -> FlightMode {
        self.mode
    }

    /// Landed state.
    pub fn landed_state(&self) -> LandedState {
        self.landed
    }

    /// Handles `request` at simulated time `t_s` [s] with the vehicle in state `x`.
    pub fn request(&mut self, request: Request, x: &VehicleState, t_s: f64) -> Outcome {
        match request {
            Request::Arm { force } => self.arm(force, x, t_s),
            Request::Disarm { force } => {
                if self.armed && self.landed != LandedState::OnGround && !force {
                    return Outcome::TemporarilyRejected("Disarm refused: vehicle in the air".into());
                }
                self.disarm();
                Outcome::Accepted
            }
            Request::SetMode(mode) => self.set_mode(mode, x, t_s),
            Request::Takeoff { height_m } => {
                if self.armed && self.landed != LandedState::OnGround {
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
                self.offboard = Some((OffboardKind::Flat(setpoint, body_frame), t_s));
                Outcome::Accepted
            }
            Request::OffboardAttitude(target) => {
                self.offboard = Some((OffboardKind::Attitude(target), t_s));
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
                if !self.armed || self.landed == LandedState::OnGround {
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
                self.guidance = Guidance::path(x.pos_w, target, yaw, self.limits(speed), t_s);
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
            Request::GcsLinkLost => {
                let action = self.params.link_loss_action;
                if action == 0 || !self.armed || self.landed == LandedState::OnGround {
                    return Outcome::Accepted;
                }
                match action {
                    1 => self.enter(FlightMode::Loiter, x, t_s),
                    2 => self.enter(FlightMode::ReturnToLaunch, x, t_s),
                    3 => self.enter(FlightMode::Land, x, t_s),
                    5 | 6 => self.disarm(),
                    _ => {}
                }
                Outcome::TemporarilyRejected(link_loss_text(action).to_string())
            }
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
        self.took_off = false;
        self.landed_at_s = None;
        self.enter(self.mode, x, t_s);
        Outcome::Accepted
    }

    fn disarm(&mut self) {
        self.armed = false;
        self.guidance = Guidance::Idle;
        self.landed = LandedState::OnGround;
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
            FlightMode::Takeoff if self.takeoff_target_w.is_none() || self.landed != LandedState::OnGround => {
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
        let yaw = euler_zyx(&x.r_wb).z;
        let on_ground = self.landed == LandedState::OnGround;
        self.slow_since_s = None;
        self.guidance = if !self.armed {
            Guidance::Idle
        } else {
            match mode {
                FlightMode::Takeoff => {
                    let target = self
                        .takeoff_target_w
                        .unwrap_or(x.pos_w - Vec3::new(0.0, 0.0, self.params.takeoff_alt_m));
                    self.landed = LandedState::Takeoff;
                    self.took_off = true;
                    Guidance::path(x.pos_w, target, yaw, self.limits(self.cruise_speed()), t_s)
                }
                FlightMode::Land => {
                    if !on_ground {
                        self.landed = LandedState::Landing;
                    }
                    self.descend(x, yaw, t_s)
                }
                FlightMode::ReturnToLaunch => {
                    self.rtl_phase = RtlPhase::Climb;
                    let z = x.pos_w.z.min(self.home_w.z - self.params.rtl_return_alt_m);
                    Guidance::path(
                        x.pos_w,
                        Vec3::new(x.pos_w.x, x.pos_w.y, z),
                        yaw,
                        self.limits(self.cruise_speed()),
                        t_s,
                    )
                }
                FlightMode::Mission => {
                    // The mission's first tick sets the item's guidance.
                    self.mission.start();
                    if on_ground {
                        Guidance::Idle
                    } else {
                        Guidance::Hold {
                            pos_w: x.pos_w,
                            yaw_rad: yaw,
                        }
                    }
                }
                // Armed on the ground in a hold mode: motors idle until a take-off.
                _ if on_ground => Guidance::Idle,
                _ => Guidance::Hold {
                    pos_w: x.pos_w,
                    yaw_rad: yaw,
                },
            }
        };
    }

    fn descend(&self, x: &VehicleState, yaw: f64, t_s: f64) -> Guidance {
        Guidance::Descend {
            xy_w: x.pos_w,
            yaw_rad: yaw,
            z_start_m: x.pos_w.z,
            start_s: t_s,
            speed_m_s: self.params.land_speed_m_s,
        }
    }

    /// One tick at simulated time `t_s` [s]: mode progress, land detection, auto-disarm, setpoint.
    pub fn update(&mut self, x: &VehicleState, t_s: f64) -> CommanderTick {
        let mut events = Vec::new();
        if !self.armed {
            return CommanderTick {
                setpoint: None,
                attitude: None,
                events,
            };
        }
        let yaw = euler_zyx(&x.r_wb).z;
        match self.mode {
            FlightMode::Takeoff => {
                let near = self
                    .takeoff_target_w
                    .is_none_or(|p| (x.pos_w - p).norm() < TAKEOFF_ACCEPT_M);
                if self.guidance.finished(t_s) && near {
                    self.landed = LandedState::InAir;
                    self.mode = FlightMode::Loiter;
                    self.guidance = Guidance::Hold {
                        pos_w: self.takeoff_target_w.unwrap_or(x.pos_w),
                        yaw_rad: yaw,
                    };
                    events.push(Event::ModeChanged(FlightMode::Loiter));
                }
            }
            FlightMode::ReturnToLaunch => self.advance_rtl(x, yaw, t_s),
            FlightMode::Mission => self.advance_mission(x, yaw, t_s, &mut events),
            FlightMode::Offboard => match self.offboard {
                Some((kind, _)) if self.offboard_alive(t_s) => {
                    self.took_off = true;
                    self.landed = LandedState::InAir;
                    return match kind {
                        OffboardKind::Flat(sp, body_frame) => CommanderTick {
                            setpoint: Some(if body_frame { heading_to_world(sp, yaw) } else { sp }),
                            attitude: None,
                            events,
                        },
                        OffboardKind::Attitude(target) => CommanderTick {
                            setpoint: None,
                            attitude: Some(target),
                            events,
                        },
                    };
                }
                _ => {
                    // COM_OBL_RC_ACT (mavlink.md §6); without RC the stick modes hold position.
                    events.push(Event::OffboardLost);
                    let mode = match self.params.offboard_loss_action {
                        3 => Some(FlightMode::ReturnToLaunch),
                        4 => Some(FlightMode::Land),
                        5 => Some(FlightMode::Loiter),
                        6 | 7 => None,
                        _ => Some(FlightMode::Position),
                    };
                    match mode {
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
            },
            _ => {}
        }
        // Land detection: asked to descend, but no longer moving.
        if matches!(self.guidance, Guidance::Descend { .. }) && self.landed != LandedState::OnGround {
            if x.vel_w.norm() < LANDED_SPEED_M_S {
                let since = *self.slow_since_s.get_or_insert(t_s);
                if t_s - since >= LANDED_CONFIRM_S {
                    self.landed = LandedState::OnGround;
                    self.landed_at_s = Some(t_s);
                    events.push(Event::Landed);
                }
            } else {
                self.slow_since_s = None;
            }
        }
        if self.landed == LandedState::OnGround {
            let p = &self.params;
            let landed_for = self.landed_at_s.map(|l| t_s - l);
            if p.disarm_land_s > 0.0 && landed_for.is_some_and(|d| d >= p.disarm_land_s) {
                self.disarm();
                events.push(Event::Disarmed("landed"));
                return CommanderTick {
                    setpoint: None,
                    attitude: None,
                    events,
                };
            }
            if p.disarm_preflight_s > 0.0 && !self.took_off && t_s - self.armed_at_s >= p.disarm_preflight_s {
                self.disarm();
                events.push(Event::Disarmed("no takeoff"));
                return CommanderTick {
                    setpoint: None,
                    attitude: None,
                    events,
                };
            }
        }
        CommanderTick {
            setpoint: self.guidance.setpoint(t_s, x),
            attitude: None,
            events,
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
                self.guidance = Guidance::path(x.pos_w, home_at_alt, yaw, self.limits(self.cruise_speed()), t_s);
            }
            RtlPhase::Return => {
                self.rtl_phase = RtlPhase::Descend;
                self.landed = LandedState::Landing;
                self.guidance = self.descend(x, yaw, t_s);
            }
            RtlPhase::Descend => {}
        }
    }
}

/// Rotates a heading-frame velocity and acceleration into world NED by heading `yaw` [rad].
fn heading_to_world(sp: FlatSetpoint, yaw: f64) -> FlatSetpoint {
    let (s, c) = yaw.sin_cos();
    let rot = |v: Vec3| Vec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
    FlatSetpoint {
        vel_w: sp.vel_w.map(rot),
        acc_w: sp.acc_w.map(rot),
        ..sp
    }
}
