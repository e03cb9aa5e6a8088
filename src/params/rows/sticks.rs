//! The stick modes (POSCTL, ALTCTL, STABILIZED, ACRO): which sources are flown, what their loss
//! does, when the sticks take over an AUTO mode, and how each mode reads them.

use crate::commander::{ManualInputMode, ManualLossAction};
use crate::params::ParamDef;

/// Stick sources, their loss and the pilot's take-over (appended after the motion rows).
pub(super) static LOSS: &[ParamDef] = &[
    row!(
        "COM_RC_IN_MODE",
        Int32,
        [0.0, 4.0],
        "",
        Commander,
        "Which stick sources are flown; MANUAL_CONTROL is the only one here (0 and 4 ignore it, 3 keeps the first link heard)",
        action ManualInputMode commander.manual.input_mode
    ),
    row!(
        "COM_RC_LOSS_T",
        Real32,
        [0.0, 35.0],
        "s",
        Failsafe,
        "MANUAL_CONTROL silence (in wall and in simulated time) that counts as stick loss",
        value commander.manual.loss_s
    ),
    row!(
        "NAV_RCL_ACT",
        Int32,
        [0.0, 6.0],
        "",
        Failsafe,
        "What stick loss does in flight, once per loss, when the sticks were live at arming or fly the mode",
        action ManualLossAction commander.manual.loss_action
    ),
    row!(
        "COM_RCL_EXCEPT",
        Int32,
        [0.0, 7.0],
        "",
        Failsafe,
        "Modes where stick loss is ignored, a bit mask: 1 mission, 2 hold and take-off, 4 offboard",
        |s| f64::from(s.commander.manual.loss_exceptions),
        |s, v| {
            s.commander.manual.loss_exceptions = v as u8;
            Ok(())
        }
    ),
    row!(
        "COM_RC_OVERRIDE",
        Int32,
        [0.0, 3.0],
        "",
        Commander,
        "Where moving a roll, pitch or yaw stick takes over in POSCTL, a bit mask: 1 AUTO modes, 2 offboard",
        |s| f64::from(s.commander.manual.override_bits),
        |s, v| {
            s.commander.manual.override_bits = v as u8;
            Ok(())
        }
    ),
    row!(
        "COM_RC_STICK_OV",
        Real32,
        [5.0, 80.0],
        "%",
        Commander,
        "Stick movement that takes over (COM_RC_OVERRIDE): % of full travel per second, low-passed over 0.1 s",
        |s| s.commander.manual.override_threshold * 100.0,
        |s, v| {
            s.commander.manual.override_threshold = v / 100.0;
            Ok(())
        }
    ),
];

/// How the stick modes read the sticks.
pub(super) static SHAPING: &[ParamDef] = &[
    row!(
        "MPC_HOLD_DZ",
        Real32,
        [0.0, 1.0],
        "",
        Sticks,
        "Stick deadzone of POSCTL and ALTCTL: within it position and height hold",
        value commander.manual.shaping.deadzone
    ),
    row!(
        "MPC_XY_MAN_EXPO",
        Real32,
        [0.0, 1.0],
        "",
        Sticks,
        "Expo of the horizontal sticks in POSCTL (0 linear, 1 cubic)",
        value commander.manual.shaping.xy_expo
    ),
    row!(
        "MPC_Z_MAN_EXPO",
        Real32,
        [0.0, 1.0],
        "",
        Sticks,
        "Expo of the throttle stick's climb rate in POSCTL and ALTCTL",
        value commander.manual.shaping.z_expo
    ),
    row!(
        "MPC_YAW_EXPO",
        Real32,
        [0.0, 1.0],
        "",
        Sticks,
        "Expo of the yaw stick in POSCTL, ALTCTL and STABILIZED",
        value commander.manual.shaping.yaw_expo
    ),
    row!(
        "MPC_VEL_MANUAL",
        Real32,
        [1.0, 20.0],
        "m/s",
        Sticks,
        "Horizontal speed at full stick in POSCTL (never above MPC_XY_VEL_MAX)",
        value commander.manual.shaping.velocity_m_s
    ),
    row!(
        "MPC_MAN_TILT_MAX",
        Real32,
        [1.0, 90.0],
        "deg",
        Sticks,
        "Tilt at full stick in ALTCTL and STABILIZED",
        degrees commander.manual.shaping.tilt_max_rad
    ),
    row!(
        "MPC_MAN_Y_MAX",
        Real32,
        [0.0, 400.0],
        "deg/s",
        Sticks,
        "Heading rate at full yaw stick in POSCTL, ALTCTL and STABILIZED",
        degrees commander.manual.shaping.yaw_rate_max_rad_s
    ),
    row!(
        "MC_ACRO_R_MAX",
        Real32,
        [0.0, 1800.0],
        "deg/s",
        Sticks,
        "Roll rate at full stick in ACRO",
        degrees commander.manual.shaping.acro_rates_rad_s.x
    ),
    row!(
        "MC_ACRO_P_MAX",
        Real32,
        [0.0, 1800.0],
        "deg/s",
        Sticks,
        "Pitch rate at full stick in ACRO",
        degrees commander.manual.shaping.acro_rates_rad_s.y
    ),
    row!(
        "MC_ACRO_Y_MAX",
        Real32,
        [0.0, 1800.0],
        "deg/s",
        Sticks,
        "Yaw rate at full stick in ACRO",
        degrees commander.manual.shaping.acro_rates_rad_s.z
    ),
    row!(
        "MPC_MANTHR_MIN",
        Real32,
        [0.0, 1.0],
        "",
        Sticks,
        "Thrust with the throttle stick down in STABILIZED and ACRO, fraction of the maximum",
        value commander.manual.shaping.thrust_min
    ),
    row!(
        "MPC_THR_HOVER",
        Real32,
        [0.1, 0.8],
        "",
        Sticks,
        "Thrust with the throttle stick centred in STABILIZED and ACRO, fraction of the maximum (starts at the airframe's hover thrust)",
        value commander.manual.shaping.thrust_hover
    ),
];
