//! Motor failures: what a failure in flight does (`COM_ACT_FAIL_ACT`), the ESC check that finds
//! one (`FD_ACT_*`), the allocation around it (`CA_FAILURE_MODE`) and what an injected one is
//! (`SYS_FAIL_MOT_OFF`).

use crate::commander::ActuatorFailureAction;
use crate::params::ParamDef;

/// Motor failures (appended after the heading's).
pub(super) static MOTOR_FAILURE: &[ParamDef] = &[
    row!(
        "COM_ACT_FAIL_ACT",
        Int32,
        [0.0, 4.0],
        "",
        Failsafe,
        "What a motor failure in flight does, after a critical STATUSTEXT; return and land first hold COM_FAIL_ACT_T",
        action ActuatorFailureAction commander.actuator_failure_action
    ),
    row!(
        "FD_ACT_EN",
        Int32,
        [0.0, 1.0],
        "",
        Failsafe,
        "1: a motor the ESCs show stopped while commanded above FD_ACT_MOT_THR for FD_ACT_MOT_TOUT is reported failed",
        flag motors.detect
    ),
    row!(
        "FD_ACT_MOT_THR",
        Real32,
        [0.0, 1.0],
        "",
        Failsafe,
        "Thrust command (fraction of full thrust) above which the ESC check suspects a stopped motor",
        value motors.detect_thrust
    ),
    row!(
        "FD_ACT_MOT_TOUT",
        Int32,
        [10.0, 10000.0],
        "ms",
        Failsafe,
        "How long a motor stays suspected before the ESC check reports it failed",
        |s| (s.motors.detect_time_s * 1e3).round(),
        |s, v| {
            s.motors.detect_time_s = v * 1e-3;
            Ok(())
        }
    ),
    row!(
        "CA_FAILURE_MODE",
        Int32,
        [0.0, 1.0],
        "",
        Failsafe,
        "1: the allocation leaves out the first failed motor and its opposite when that turns the other way and the vehicle stays controllable (PX4's default is 0)",
        flag motors.reallocate
    ),
    row!(
        "SYS_FAIL_MOT_OFF",
        Int32,
        [0.0, 1.0],
        "",
        Commander,
        "An injected motor failure: 0 soft (stopped and reported failed), 1 hard (only stopped, nothing is told)",
        flag motors.hard_injection
    ),
];
