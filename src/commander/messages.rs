//! What goes in and out of the commander: ground-station requests, their outcomes, the events
//! it announces on its own, the landed state it reports and one tick's output.

use crate::control::{AttitudeTarget, FlatSetpoint};
use crate::guidance::{Geofence, Mission, OrbitYaw, RallyPoints, Sticks};
use crate::math::Vec3;
use crate::sensor_failure::SensorFailure;

use super::{FailsafeCause, FlightMode};

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
    /// ArduCopter's mode change (`Copter::set_mode`): armed, as [`Request::SetMode`]; disarmed,
    /// the mode is entered without the checks of what it needs to fly (a position, a mission),
    /// which arming in it then makes.
    SelectMode(FlightMode),
    /// NAV_TAKEOFF to `height_m` above home [m] (`None`: `MIS_TAKEOFF_ALT`).
    Takeoff {
        /// Target height above home [m].
        height_m: Option<f64>,
    },
    /// ArduCopter's CONDITION_YAW in GUIDED: turn to heading `yaw_rad` [rad] and keep it (the
    /// latest guided target's heading, or the hold's).
    TurnTo {
        /// Heading [rad].
        yaw_rad: f64,
    },
    /// ArduCopter's DO_REPOSITION: fly to `pos_w` [m, world NED] in GUIDED (switching to GUIDED
    /// first when in another mode), heading `yaw_rad` [rad] (`None`: the current one).
    GuidedGoto {
        /// Target position, world NED [m].
        pos_w: Vec3,
        /// Heading [rad].
        yaw_rad: Option<f64>,
    },
    /// ArduCopter's user take-off (NAV_TAKEOFF in GUIDED, LOITER, POSHOLD or ALT_HOLD): climb in
    /// place to `height_m` above home [m] and stay in the mode (armed, on the ground, in GUIDED,
    /// POSCTL or ALTCTL, to a height above the vehicle).
    UserTakeoff {
        /// Target height above home [m].
        height_m: f64,
    },
    /// ArduCopter's SET_ATTITUDE_TARGET in GUIDED: lean by `roll_rad` / `pitch_rad` [rad] at heading
    /// `yaw_rad` [rad] and climb at `climb` ∈ [−1, 1] of the AUTO descent / climb speed (the
    /// thrust read as a climb rate: 0.5 ↦ 0, holding the height), kept as the latest target.
    GuidedLean(Lean),
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
    /// Replace the uploaded geofence (zones about home; empty: none). Zones that home breaks,
    /// or (in flight, `GF_ACTION` set) the current position, are left out, as PX4 does.
    SetGeofence(Geofence),
    /// Replace the rally points RTL may return to (empty: none).
    SetRallyPoints(RallyPoints),
    /// MISSION_START: fly the stored mission from `first` (item index).
    StartMission {
        /// First item.
        first: usize,
    },
    /// MISSION_SET_CURRENT / DO_SET_MISSION_CURRENT: the mission goes on at item `seq` (at once
    /// when flying it, else when it starts; `None` keeps the current one); `reset` forgets the
    /// DO_JUMPs taken.
    SetMissionCurrent {
        /// Item index; `None`: unchanged.
        seq: Option<usize>,
        /// Start the DO_JUMP counts over.
        reset: bool,
    },
    /// DO_REPOSITION, as PX4's commander reads it: with `change_mode` (MAVLink's mode-change
    /// flag) a horizontal target flies in GOTO (so does a height or heading alone while in GOTO),
    /// anything else holds in AUTO.LOITER (all unset: hold here); without the flag the target is
    /// flown in the mode already running, AUTO.LOITER or GOTO, and refused in any other. Unset
    /// coordinates keep the current ones, `yaw_rad` `None` the heading (GOTO: towards its target),
    /// `speed_m_s` `None` the cruise speed (GOTO: `MPC_XY_CRUISE`, forgetting DO_CHANGE_SPEED's).
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
        /// MAV_DO_REPOSITION_FLAGS_CHANGE_MODE was set.
        change_mode: bool,
    },
    /// MAV_CMD_INJECT_FAILURE for motors (`SYS_FAILURE_EN` = 1): rotor `rotor` (1-based; 0 =
    /// every rotor) stops (`failed`) or works again. The flight controller stops its output
    /// and the plant its rotor; the commander hears of it through [`Commander::rotor_failed`]
    /// unless the failure is hard (`SYS_FAIL_MOT_OFF` 1).
    InjectRotorFailure {
        /// Rotor, 1-based; 0 = all.
        rotor: usize,
        /// Stop (true) or restore (false).
        failed: bool,
    },
    /// MAV_CMD_INJECT_FAILURE for a sensor (`SYS_FAILURE_EN` = 1): the vehicle applies it to
    /// the simulated sensor suite; the navigation filter notices what the sensor then reports.
    InjectSensorFailure(SensorFailure),
    /// DO_CHANGE_SPEED: horizontal speed of the AUTO modes [m/s] until changed again (a GOTO
    /// target forgets it); GOTO flies it at once, within `MPC_XY_CRUISE`.
    ChangeSpeed(f64),
    /// DO_CHANGE_SPEED's climb (`up`) or descent speed of the AUTO paths and guided targets
    /// [m/s] (ArduCopter's speed types 2 and 3), until changed again; within
    /// `MPC_Z_VEL_MAX_UP` / `_DN`.
    ChangeVerticalSpeed {
        /// The climb speed (else the descent speed).
        up: bool,
        /// The speed [m/s].
        speed_m_s: f64,
    },
    /// DO_SET_HOME: the local NED point RTL returns to [m]; `None`: the current position.
    SetHome(Option<Vec3>),
    /// No GCS heartbeat for `COM_DL_LOSS_T`: run `NAV_DLL_ACT` if flying.
    GcsLinkLost,
    /// The link heard nothing of `stream` for its loss time (`COM_OF_LOSS_T`, `COM_RC_LOSS_T`)
    /// by its rule (docs/mavlink.md §6): the stream is lost until its next message. The link
    /// alone judges the liveness of what clients stream; the commander runs the reaction.
    StreamLost(InputStream),
    /// MAV_CMD_DO_ORBIT: fly a circle; every `None` keeps the running orbit's value or takes
    /// the default.
    Orbit(OrbitRequest),
    /// ArduCopter's CIRCLE: circle the point `radius_m` ahead of the vehicle (so it is on the
    /// circle at once), clockwise, at `speed_m_s`; flown as an orbit.
    Circle {
        /// Radius [m].
        radius_m: f64,
        /// Speed along the circle [m/s].
        speed_m_s: f64,
    },
    /// A FOLLOW_TARGET report: where the target is and how it moves.
    FollowTarget {
        /// Target position, world NED [m].
        pos_w: Vec3,
        /// Target velocity, world NED [m/s] (zero when not reported).
        vel_w: Vec3,
    },
    /// One MANUAL_CONTROL sample (a joystick, QGroundControl's virtual one, MAVSDK's
    /// `manual_control`): the sticks of the stick modes.
    ManualControl(Sticks),
}

/// What MAV_CMD_DO_ORBIT asks (NaN parameters are `None`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OrbitRequest {
    /// Radius [m], positive clockwise seen from above (p1).
    pub radius_m: Option<f64>,
    /// Tangential speed [m/s] (p2).
    pub speed_m_s: Option<f64>,
    /// Heading rule (p3).
    pub yaw: Option<OrbitYaw>,
    /// Centre north and east of home [m] (p5, p6; `None`: where the vehicle is).
    pub centre_ne_m: Option<(f64, f64)>,
    /// Centre z, NED [m] (p7 as altitude; `None`: the vehicle's height).
    pub centre_down_m: Option<f64>,
}

impl OrbitRequest {
    /// True when every number it carries is finite.
    pub fn is_finite(&self) -> bool {
        let opt = |v: Option<f64>| v.is_none_or(f64::is_finite);
        opt(self.radius_m)
            && opt(self.speed_m_s)
            && opt(self.centre_down_m)
            && self.centre_ne_m.is_none_or(|(n, e)| n.is_finite() && e.is_finite())
    }
}

/// ArduCopter's attitude target in GUIDED ([`Request::GuidedLean`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lean {
    /// Roll [rad].
    pub roll_rad: f64,
    /// Pitch [rad].
    pub pitch_rad: f64,
    /// Heading [rad].
    pub yaw_rad: f64,
    /// Climb demand ∈ [−1, 1]: a fraction of the AUTO climb (> 0) or descent (< 0) speed.
    pub climb: f64,
}

impl Lean {
    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        [self.roll_rad, self.pitch_rad, self.yaw_rad, self.climb]
            .iter()
            .all(|v| v.is_finite())
    }
}

/// A stream of messages whose silence the vehicle reacts to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InputStream {
    /// Offboard setpoints (`COM_OF_LOSS_T`, `COM_OBL_RC_ACT`).
    Offboard,
    /// Stick input (`COM_RC_LOSS_T`, `NAV_RCL_ACT`).
    ManualControl,
}

impl Request {
    /// The input stream this request is a message of (offboard setpoints, sticks), whose
    /// liveness the receiver judges ([`Request::StreamLost`]).
    pub fn input_stream(&self) -> Option<InputStream> {
        match self {
            Self::OffboardSetpoint { .. } | Self::OffboardAttitude(_) | Self::GuidedLean(_) => {
                Some(InputStream::Offboard)
            }
            Self::ManualControl(_) => Some(InputStream::ManualControl),
            _ => None,
        }
    }

    /// An offboard setpoint in the world frame (SET_POSITION_TARGET_LOCAL_NED in MAV_FRAME_LOCAL_NED).
    pub fn offboard(setpoint: FlatSetpoint) -> Self {
        Self::OffboardSetpoint {
            setpoint,
            body_frame: false,
        }
    }

    /// True when every number the request carries is finite (a request with a non-finite
    /// number is never accepted).
    pub fn is_finite(&self) -> bool {
        let opt = |v: &Option<f64>| v.is_none_or(f64::is_finite);
        match self {
            Self::Arm { .. }
            | Self::Disarm { .. }
            | Self::SetMode(_)
            | Self::SelectMode(_)
            | Self::Land
            | Self::ReturnToLaunch
            | Self::StartMission { .. }
            | Self::SetMissionCurrent { .. }
            | Self::GcsLinkLost
            | Self::StreamLost(_)
            | Self::InjectRotorFailure { .. }
            | Self::InjectSensorFailure(_) => true,
            Self::Takeoff { height_m } => opt(height_m),
            Self::OffboardSetpoint { setpoint, .. } => setpoint.is_finite(),
            Self::OffboardAttitude(t) => t.is_finite(),
            Self::ManualControl(sticks) => sticks.is_finite(),
            Self::Orbit(orbit) => orbit.is_finite(),
            Self::Circle { radius_m, speed_m_s } => radius_m.is_finite() && speed_m_s.is_finite(),
            Self::FollowTarget { pos_w, vel_w } => pos_w.iter().chain(vel_w.iter()).all(|v| v.is_finite()),
            Self::SetMission(m) => m.is_finite(),
            Self::SetGeofence(f) => f.is_finite(),
            Self::SetRallyPoints(r) => r.is_finite(),
            Self::Reposition {
                north_m,
                east_m,
                down_m,
                yaw_rad,
                speed_m_s,
                ..
            } => [north_m, east_m, down_m, yaw_rad, speed_m_s].iter().all(|v| opt(v)),
            Self::ChangeSpeed(v) => v.is_finite(),
            Self::ChangeVerticalSpeed { speed_m_s, .. } => speed_m_s.is_finite(),
            Self::TurnTo { yaw_rad } => yaw_rad.is_finite(),
            Self::GuidedLean(lean) => lean.is_finite(),
            Self::UserTakeoff { height_m } => height_m.is_finite(),
            Self::GuidedGoto { pos_w, yaw_rad } => pos_w.iter().all(|v| v.is_finite()) && opt(yaw_rad),
            Self::SetHome(p) => p.as_ref().is_none_or(|p| p.iter().all(|c| c.is_finite())),
        }
    }
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
    /// Lift-off detected.
    Airborne,
    /// Offboard setpoints stopped for `COM_OF_LOSS_T`; the vehicle holds position.
    OffboardLost,
    /// A failsafe triggered or ended: what it is about (for a face that words failsafes its own
    /// way) and the commander's announcement.
    Failsafe(FailsafeCause, String),
    /// The navigation's sensors changed: a sensor lost (`warning`) or back, the height source
    /// switched (the announcement).
    Navigation {
        /// The announcement.
        text: String,
        /// A loss (warning) rather than news (information).
        warning: bool,
    },
    /// News of a mode's plan (a return's way round the geofence).
    Notice {
        /// The announcement.
        text: String,
        /// Critical (the plan fell back on something unsafe) rather than information.
        critical: bool,
    },
    /// Mission item `seq` reached (MISSION_ITEM_REACHED).
    MissionItemReached(u16),
    /// The current mission item changed (MISSION_CURRENT at once).
    MissionCurrent(u16),
}

impl Event {
    /// The severity of its announcement (MAVLink / syslog levels): critical (2) for a failsafe
    /// or a critical notice, warning (4) for a lost sensor, information (6) for the rest.
    pub fn severity(&self) -> u8 {
        match self {
            Self::Failsafe(..) | Self::Notice { critical: true, .. } => 2,
            Self::Navigation { warning: true, .. } => 4,
            _ => 6,
        }
    }

    /// The STATUSTEXT announcing it.
    pub fn describe(&self) -> String {
        match self {
            Self::Disarmed(why) => format!("Disarmed: {why}"),
            Self::ModeChanged(mode) => format!("Mode {}", mode.name()),
            Self::Landed => "Landing detected".to_string(),
            Self::Airborne => "Takeoff detected".to_string(),
            Self::OffboardLost => "Offboard lost".to_string(),
            Self::Failsafe(_, text) | Self::Navigation { text, .. } | Self::Notice { text, .. } => text.clone(),
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

impl CommanderTick {
    /// Motors off (disarmed, or idle on the ground).
    pub(super) fn idle(events: Vec<Event>) -> Self {
        Self {
            setpoint: None,
            attitude: None,
            events,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_with_a_non_finite_number_are_not_finite() {
        assert!(Request::Takeoff { height_m: None }.is_finite());
        assert!(!Request::Takeoff {
            height_m: Some(f64::NAN)
        }
        .is_finite());
        assert!(!Request::ChangeSpeed(f64::INFINITY).is_finite());
        let reposition = |east_m| Request::Reposition {
            north_m: Some(1.0),
            east_m,
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        };
        assert!(reposition(None).is_finite());
        assert!(!reposition(Some(f64::NEG_INFINITY)).is_finite());
        assert!(!Request::SetHome(Some(Vec3::new(0.0, f64::NAN, 0.0))).is_finite());
    }
}
