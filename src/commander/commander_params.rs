//! The commander's settings, with PX4's parameter names and defaults.

use crate::guidance::{FollowParams, MotionLimits, StickShaping};

use super::{
    ActuatorFailureAction, BatteryParams, FailsafeParams, LandDetectorParams, LinkLossAction, ManualInputMode,
    ManualLossAction, OffboardLossAction, RtlType,
};

/// The stick modes and the loss of the sticks (PX4 names and defaults in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManualParams {
    /// Stick silence that counts as lost, in simulated and in wall time [s] (`COM_RC_LOSS_T`,
    /// 0.5).
    pub loss_s: f64,
    /// What the loss of the sticks does in flight (`NAV_RCL_ACT`, 2 return).
    pub loss_action: ManualLossAction,
    /// Which sources are flown (`COM_RC_IN_MODE`, 3 keep the first).
    pub input_mode: ManualInputMode,
    /// Modes in which the loss of the sticks is ignored, a bit mask (`COM_RCL_EXCEPT`, 0):
    /// 1 mission, 2 hold (and take-off), 4 offboard.
    pub loss_exceptions: u8,
    /// Where moving the sticks takes over in POSCTL, a bit mask (`COM_RC_OVERRIDE`, 1):
    /// 1 the AUTO modes, 2 OFFBOARD.
    pub override_bits: u8,
    /// Stick movement that takes over: the rate of change of any stick [1/s]
    /// (`COM_RC_STICK_OV`, 30 % of full travel per second).
    pub override_threshold: f64,
    /// How the sticks are read.
    pub shaping: StickShaping,
}

impl Default for ManualParams {
    fn default() -> Self {
        Self {
            loss_s: 0.5,
            loss_action: ManualLossAction::Return,
            input_mode: ManualInputMode::KeepFirst,
            loss_exceptions: 0,
            override_bits: 1,
            override_threshold: 0.3,
            shaping: StickShaping::default(),
        }
    }
}

/// The vertical speeds of the AUTO modes and of a take-off (PX4 names and defaults in brackets).
/// Each is capped by the matching `MotionLimits` speed (`MPC_Z_VEL_MAX_UP` / `_DN`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutoVertical {
    /// Climb speed of AUTO paths and of a take-off above `MPC_LAND_ALT1` [m/s]
    /// (`MPC_Z_V_AUTO_UP`, 3).
    pub up_m_s: f64,
    /// Descent speed of AUTO paths, and of a landing above `MPC_LAND_ALT1` [m/s]
    /// (`MPC_Z_V_AUTO_DN`, 1.5).
    pub down_m_s: f64,
    /// Climb speed of a take-off below `MPC_LAND_ALT1` [m/s] (`MPC_TKO_SPEED`, 1.5).
    pub takeoff_m_s: f64,
    /// Time a take-off takes to reach `MPC_TKO_SPEED` [s]: its upward acceleration is at most
    /// `MPC_TKO_SPEED / MPC_TKO_RAMP_T` (`MPC_TKO_RAMP_T`, 3).
    pub takeoff_ramp_s: f64,
}

impl Default for AutoVertical {
    fn default() -> Self {
        Self {
            up_m_s: 3.0,
            down_m_s: 1.5,
            takeoff_m_s: 1.5,
            takeoff_ramp_s: 3.0,
        }
    }
}

/// Commander settings (PX4 parameter names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommanderParams {
    /// Take-off height above home [m] (`MIS_TAKEOFF_ALT`, 2.5).
    pub takeoff_alt_m: f64,
    /// Landing descent speed [m/s] (`MPC_LAND_SPEED`, 0.7).
    pub land_speed_m_s: f64,
    /// A landing descends at `MPC_Z_V_AUTO_DN` above this height, slowing below [m]
    /// (`MPC_LAND_ALT1`, 10).
    pub land_alt1_m: f64,
    /// ... and at `MPC_LAND_SPEED` below this one [m] (`MPC_LAND_ALT2`, 5).
    pub land_alt2_m: f64,
    /// Horizontal cruise speed of the AUTO modes [m/s] (`MPC_XY_CRUISE`, 5.0).
    pub cruise_speed_m_s: f64,
    /// Return altitude above home [m] (`RTL_RETURN_ALT`, 60).
    pub rtl_return_alt_m: f64,
    /// Half-angle of the cone above the destination that lowers the return altitude close to it
    /// [rad] (`RTL_CONE_ANG`, 45°; 0: no cone).
    pub rtl_cone_rad: f64,
    /// Within this horizontal distance of the destination the cone applies [m] (`RTL_MIN_DIST`, 10).
    pub rtl_min_dist_m: f64,
    /// Where a return goes: home or a rally point (`RTL_TYPE`, 0).
    pub rtl_type: RtlType,
    /// Fly a land approach on a return when one exists (`RTL_APPR_FORCE`, 0). No land approaches
    /// are stored here, so it is kept for clients and changes nothing.
    pub rtl_approach_force: bool,
    /// Disarm this long after landing [s] (`COM_DISARM_LAND`, 2.0; ≤ 0 never).
    pub disarm_land_s: f64,
    /// Disarm this long after arming without taking off [s] (`COM_DISARM_PRFLT`, 10; ≤ 0 never).
    pub disarm_preflight_s: f64,
    /// Offboard setpoints older than this are lost [s] (`COM_OF_LOSS_T`, 1.0).
    pub offboard_loss_s: f64,
    /// GCS link-loss action (`NAV_DLL_ACT`: 0 off, 1 hold, 2 return, 3 land, 5 terminate,
    /// 6 disarm; default 0).
    pub link_loss_action: LinkLossAction,
    /// GCS silence that counts as link loss [s] (`COM_DL_LOSS_T`, 10).
    pub link_loss_s: f64,
    /// Geofence and battery failsafes.
    pub failsafe: FailsafeParams,
    /// The battery pack.
    pub battery: BatteryParams,
    /// Failure injection allowed (`SYS_FAILURE_EN`; 1, PX4 SITL's boot value: the firmware's is 0).
    pub failure_injection: bool,
    /// A position lost in POSCTL lands (descends) instead of falling back to ALTCTL with the
    /// sticks (`COM_POSCTL_NAVL`: 0 altitude, 1 land; default 0). The AUTO modes always descend.
    pub position_loss_lands: bool,
    /// Arming is allowed without a position estimate in the modes that do not need one
    /// (`COM_ARM_WO_GPS`: 0 a valid position is required to arm in any mode, 1 allowed;
    /// default 1).
    pub arm_without_gps: bool,
    /// Arming checks the sticks and the geofence first (`RP_ARM_CHECKS` 1, the default); 0
    /// skips them, as ArduCopter's `ARMING_CHECK` 0 keeps only its mandatory checks: the
    /// estimate and the mode's needs are always checked.
    pub arming_checks: bool,
    /// Offboard-loss action (`COM_OBL_RC_ACT`: 0–2 hold position (no RC), 3 return, 4 land,
    /// 5 hold (AUTO.LOITER), 6 terminate, 7 disarm; default 0).
    pub offboard_loss_action: OffboardLossAction,
    /// Limits of every AUTO path and every offboard setpoint (`MPC_XY_VEL_MAX` caps cruise,
    /// DO_CHANGE_SPEED and DO_REPOSITION speeds; the final landing descends at `land_speed_m_s`).
    pub motion: MotionLimits,
    /// Vertical speeds of the AUTO modes and of a take-off.
    pub auto_vertical: AutoVertical,
    /// Land detector.
    pub land_detector: LandDetectorParams,
    /// Stick modes and stick loss.
    pub manual: ManualParams,
    /// Follow-me.
    pub follow: FollowParams,
    /// Mission waypoints.
    pub mission: MissionParams,
    /// The hold before a failsafe's return or landing [s] (`COM_FAIL_ACT_T`, 5; 0 or less than
    /// 0.1 s: none).
    pub fail_action_delay_s: f64,
    /// What a motor failure in flight does (`COM_ACT_FAIL_ACT`: 0 warning, 1 hold, 2 land,
    /// 3 return, 4 terminate; default 0).
    pub actuator_failure_action: ActuatorFailureAction,
}

/// How mission waypoints are reached and flown through (PX4's navigator and AUTO trajectory).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MissionParams {
    /// Horizontal acceptance radius of a waypoint that gives none [m] (`NAV_ACC_RAD`; 2 m as
    /// PX4 SITL's multicopter defaults set it).
    pub accept_m: f64,
    /// Vertical acceptance radius [m] (`NAV_MC_ALT_RAD`, 0.8).
    pub alt_accept_m: f64,
    /// Share of the horizontal acceleration a waypoint flown through turns with [-]
    /// (`MPC_XY_TRAJ_P`, 0.5).
    pub corner_gain: f64,
}

impl Default for MissionParams {
    fn default() -> Self {
        Self {
            accept_m: 2.0,
            alt_accept_m: 0.8,
            corner_gain: 0.5,
        }
    }
}

impl Default for CommanderParams {
    fn default() -> Self {
        Self {
            takeoff_alt_m: 2.5,
            land_speed_m_s: 0.7,
            land_alt1_m: 10.0,
            land_alt2_m: 5.0,
            cruise_speed_m_s: 5.0,
            rtl_return_alt_m: 60.0,
            rtl_cone_rad: 45f64.to_radians(),
            rtl_min_dist_m: 10.0,
            rtl_type: RtlType::HomeOrRally,
            rtl_approach_force: false,
            disarm_land_s: 2.0,
            disarm_preflight_s: 10.0,
            offboard_loss_s: 1.0,
            link_loss_action: LinkLossAction::Disabled,
            link_loss_s: 10.0,
            motion: MotionLimits::default(),
            auto_vertical: AutoVertical::default(),
            land_detector: LandDetectorParams::default(),
            failsafe: FailsafeParams::default(),
            battery: BatteryParams::default(),
            failure_injection: true,
            offboard_loss_action: OffboardLossAction::Position,
            position_loss_lands: false,
            arm_without_gps: true,
            arming_checks: true,
            manual: ManualParams::default(),
            follow: FollowParams::default(),
            mission: MissionParams::default(),
            fail_action_delay_s: 5.0,
            actuator_failure_action: ActuatorFailureAction::Warn,
        }
    }
}
