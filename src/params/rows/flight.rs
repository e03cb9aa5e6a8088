//! How the vehicle flies its paths (PX4's `MIS_`, `MPC_`, `MC_`, `RTL_` parameters), when it
//! disarms by itself (`COM_DISARM_*`) and how it decides it has landed (`LNDMC_*`).

use crate::commander::RtlType;
use crate::params::ParamDef;

/// Take-off, return and auto-disarm (indices 0–6).
pub(super) static TAKEOFF_AND_RETURN: &[ParamDef] = &[
    row!(
        "MIS_TAKEOFF_ALT",
        Real32,
        [0.5, 1000.0],
        "m",
        Commander,
        "Height above home a take-off climbs to when the command names none",
        value commander.takeoff_alt_m
    ),
    row!(
        "MPC_Z_VEL_MAX_UP",
        Real32,
        [0.5, 20.0],
        "m/s",
        Navigation,
        "Climb speed cap of every AUTO path and offboard setpoint (AUTO paths climb at MPC_Z_V_AUTO_UP within it)",
        value commander.motion.up_m_s
    ),
    row!(
        "MPC_LAND_SPEED",
        Real32,
        [0.1, 5.0],
        "m/s",
        Navigation,
        "Final descent speed of every landing, below MPC_LAND_ALT2 down to touch-down",
        value commander.land_speed_m_s
    ),
    row!(
        "MPC_XY_CRUISE",
        Real32,
        [0.5, 30.0],
        "m/s",
        Navigation,
        "Horizontal speed of the AUTO modes (never above MPC_XY_VEL_MAX)",
        value commander.cruise_speed_m_s
    ),
    row!(
        "RTL_RETURN_ALT",
        Real32,
        [1.0, 500.0],
        "m",
        Navigation,
        "Height above home a return climbs to, when lower, before it flies home",
        value commander.rtl_return_alt_m
    ),
    row!(
        "COM_DISARM_LAND",
        Real32,
        [-1.0, 20.0],
        "s",
        Commander,
        "Disarm this long after a touch-down is detected (≤ 0: never)",
        value commander.disarm_land_s
    ),
    row!(
        "COM_DISARM_PRFLT",
        Real32,
        [-1.0, 60.0],
        "s",
        Commander,
        "Disarm this long after arming when the vehicle has not taken off (≤ 0: never)",
        value commander.disarm_preflight_s
    ),
];

/// Speed caps of every path (indices 58–59).
pub(super) static SPEED_CAPS: &[ParamDef] = &[
    row!(
        "MPC_XY_VEL_MAX",
        Real32,
        [0.5, 50.0],
        "m/s",
        Navigation,
        "Horizontal speed cap of every AUTO path and offboard setpoint; also caps MPC_XY_CRUISE, DO_CHANGE_SPEED and DO_REPOSITION",
        value commander.motion.horizontal_m_s
    ),
    row!(
        "MPC_Z_VEL_MAX_DN",
        Real32,
        [0.1, 10.0],
        "m/s",
        Navigation,
        "Descent speed cap of every AUTO path and offboard setpoint (AUTO paths and landings descend at MPC_Z_V_AUTO_DN within it)",
        value commander.motion.down_m_s
    ),
];

/// Accelerations, heading rates, land detector and landing profile (indices 71–81).
pub(super) static MOTION: &[ParamDef] = &[
    row!(
        "MPC_ACC_HOR",
        Real32,
        [0.5, 15.0],
        "m/s²",
        Navigation,
        "Horizontal acceleration limit of every AUTO path and offboard setpoint",
        value commander.motion.acc_horizontal_m_s2
    ),
    row!(
        "MPC_ACC_UP_MAX",
        Real32,
        [1.0, 15.0],
        "m/s²",
        Navigation,
        "Upward acceleration limit of every AUTO path and offboard setpoint",
        value commander.motion.acc_up_m_s2
    ),
    row!(
        "MPC_ACC_DOWN_MAX",
        Real32,
        [1.0, 15.0],
        "m/s²",
        Navigation,
        "Downward acceleration limit of every AUTO path and offboard setpoint; a landing starts from rest at it",
        value commander.motion.acc_down_m_s2
    ),
    row!(
        "MPC_YAWRAUTO_MAX",
        Real32,
        [5.0, 360.0],
        "deg/s",
        Navigation,
        "Heading rate towards a commanded heading (AUTO paths, offboard yaw)",
        degrees commander.motion.yaw_rate_auto_rad_s
    ),
    row!(
        "MC_YAWRATE_MAX",
        Real32,
        [5.0, 1800.0],
        "deg/s",
        Navigation,
        "Largest commanded yaw rate (offboard yaw rate)",
        degrees commander.motion.yaw_rate_max_rad_s
    ),
    row!(
        "LNDMC_Z_VEL_MAX",
        Real32,
        [0.05, 1.0],
        "m/s",
        LandDetector,
        "Ground contact needs a slower vertical speed; an armed vehicle climbing faster has lifted off",
        value commander.land_detector.z_vel_max_m_s
    ),
    row!(
        "LNDMC_XY_VEL_MAX",
        Real32,
        [0.1, 5.0],
        "m/s",
        LandDetector,
        "Ground contact needs a slower horizontal speed",
        value commander.land_detector.xy_vel_max_m_s
    ),
    row!(
        "LNDMC_ROT_MAX",
        Real32,
        [5.0, 360.0],
        "deg/s",
        LandDetector,
        "Maybe landed needs every body rate below this",
        degrees commander.land_detector.rot_max_rad_s
    ),
    row!(
        "LNDMC_TRIG_TIME",
        Real32,
        [0.1, 10.0],
        "s",
        LandDetector,
        "Time spent through the detector's stages before the vehicle counts as landed",
        value commander.land_detector.trigger_time_s
    ),
    row!(
        "MPC_LAND_ALT1",
        Real32,
        [0.0, 122.0],
        "m",
        Navigation,
        "Landings descend at MPC_Z_VEL_MAX_DN above this height and slow down linearly below it",
        value commander.land_alt1_m
    ),
    row!(
        "MPC_LAND_ALT2",
        Real32,
        [0.0, 122.0],
        "m",
        Navigation,
        "Landings reach MPC_LAND_SPEED at this height and keep it to touch-down",
        value commander.land_alt2_m
    ),
];

/// Where a return goes (index 82).
pub(super) static RETURN: &[ParamDef] = &[row!(
    "RTL_TYPE",
    Int32,
    [0.0, 6.0],
    "",
    Navigation,
    "Where AUTO.RTL flies to and lands: home or an uploaded rally point (one more than 2 m nearer than the alternative and, unless 5, over 10 m from home); 6 is 0 here, as PX4 without a battery time remaining",
    action RtlType commander.rtl_type
)];

/// Mission waypoints: acceptance radii and the corner speed (indices after the filter's).
pub(super) static MISSION: &[ParamDef] = &[
    row!(
        "NAV_ACC_RAD",
        Real32,
        [0.05, 200.0],
        "m",
        Navigation,
        "Horizontal acceptance radius of a mission waypoint that gives none (PX4 SITL multicopter: 2 m)",
        value commander.mission.accept_m
    ),
    row!(
        "NAV_MC_ALT_RAD",
        Real32,
        [0.05, 200.0],
        "m",
        Navigation,
        "Vertical acceptance radius of a multicopter mission waypoint",
        value commander.mission.alt_accept_m
    ),
    row!(
        "MPC_XY_TRAJ_P",
        Real32,
        [0.1, 1.0],
        "",
        Navigation,
        "Share of MPC_ACC_HOR a waypoint flown through may turn with: sets the speed at its corner",
        value commander.mission.corner_gain
    ),
];

/// The heading acceleration of AUTO turns and offboard yaw (appended after the failsafe delay).
pub(super) static HEADING: &[ParamDef] = &[row!(
    "MPC_YAWRAUTO_ACC",
    Real32,
    [5.0, 1000.0],
    "deg/s^2",
    Navigation,
    "Heading acceleration towards a commanded heading (AUTO paths, offboard yaw); an offboard yaw rate is flown at once",
    degrees commander.motion.yaw_acc_auto_rad_s2
)];

/// The return altitude's cone (appended after the heading acceleration).
pub(super) static RETURN_CONE: &[ParamDef] = &[
    row!(
        "RTL_CONE_ANG",
        Int32,
        [0.0, 90.0],
        "deg",
        Navigation,
        "Half-angle of the cone above the return destination: close to it the return climbs no higher than the cone (0: always RTL_RETURN_ALT)",
        |s| s.commander.rtl_cone_rad.to_degrees().round(),
        |s, v| {
            s.commander.rtl_cone_rad = v.to_radians();
            Ok(())
        }
    ),
    row!(
        "RTL_MIN_DIST",
        Real32,
        [0.5, 100.0],
        "m",
        Navigation,
        "Horizontal distance from the return destination within which the cone lowers the return altitude",
        value commander.rtl_min_dist_m
    ),
];

/// The AUTO modes' vertical speeds and the take-off's (appended after the air mode).
pub(super) static AUTO_VERTICAL: &[ParamDef] = &[
    row!(
        "MPC_Z_V_AUTO_UP",
        Real32,
        [0.5, 8.0],
        "m/s",
        Navigation,
        "Climb speed of AUTO paths (take-off above MPC_LAND_ALT1, return climb, missions, GOTO), within MPC_Z_VEL_MAX_UP",
        value commander.auto_vertical.up_m_s
    ),
    row!(
        "MPC_Z_V_AUTO_DN",
        Real32,
        [0.5, 4.0],
        "m/s",
        Navigation,
        "Descent speed of AUTO paths and of landings above MPC_LAND_ALT1, within MPC_Z_VEL_MAX_DN",
        value commander.auto_vertical.down_m_s
    ),
    row!(
        "MPC_TKO_SPEED",
        Real32,
        [1.0, 5.0],
        "m/s",
        Navigation,
        "Take-off climb speed below MPC_LAND_ALT1",
        value commander.auto_vertical.takeoff_m_s
    ),
    row!(
        "MPC_TKO_RAMP_T",
        Real32,
        [0.0, 5.0],
        "s",
        Navigation,
        "Time a take-off takes to reach MPC_TKO_SPEED (its upward acceleration is at most MPC_TKO_SPEED over it; 0: MPC_ACC_UP_MAX)",
        value commander.auto_vertical.takeoff_ramp_s
    ),
];

/// The return's land approach (appended after the AUTO vertical speeds).
pub(super) static RETURN_APPROACH: &[ParamDef] = &[row!(
    "RTL_APPR_FORCE",
    Int32,
    [0.0, 1.0],
    "",
    Navigation,
    "1 makes a return fly a land approach when one exists (PX4); none are stored here, so it changes nothing: the return flies round the geofence either way",
    flag commander.rtl_approach_force
)];
