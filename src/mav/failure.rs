//! MAV_CMD_INJECT_FAILURE (420) decoded as PX4 answers it: param1 the FAILURE_UNIT, param2 the
//! FAILURE_TYPE, param3 the instance (0: all, PX4's `failure ... -i`). Simulated, and allowed by
//! `SYS_FAILURE_EN`: a motor switched off (1) or back on (0) ([`Request::InjectRotorFailure`]),
//! and every failure type of the gyro, accelerometer, magnetometer, barometer and GPS
//! ([`Request::InjectSensorFailure`]; one instance each, 0 or 1). Every other unit MAVSDK's
//! `FailureUnit` names is understood and answered as PX4 answers a unit its simulation does not
//! model: COMMAND_ACK UNSUPPORTED, with a STATUSTEXT naming the unit. Pure.

use mavlink::dialects::ardupilotmega::COMMAND_LONG_DATA;

use super::translate::CommandDecision;
use crate::commander::{Outcome, Request};
use crate::sensor_failure::{FailureKind, FailureUnit, SensorFailure};

/// FAILURE_UNIT SYSTEM_MOTOR.
const MOTOR_UNIT: u8 = 101;
/// FAILURE_TYPE OK (restore) and OFF.
const TYPE_OK: u8 = 0;
const TYPE_OFF: u8 = 1;

/// The name PX4's `failure` command gives FAILURE_UNIT `unit`, `None` for a number the enum
/// does not define.
pub fn unit_name(unit: u8) -> Option<&'static str> {
    Some(match unit {
        0 => "gyro",
        1 => "accel",
        2 => "mag",
        3 => "baro",
        4 => "gps",
        5 => "optical_flow",
        6 => "vio",
        7 => "distance_sensor",
        8 => "airspeed",
        100 => "battery",
        101 => "motor",
        102 => "servo",
        103 => "avoidance",
        104 => "rc_signal",
        105 => "mavlink_signal",
        _ => return None,
    })
}

/// The name of FAILURE_TYPE `kind`, `None` for a number the enum does not define.
fn type_name(kind: u8) -> Option<&'static str> {
    FailureKind::from_failure_type(kind).map(FailureKind::name)
}

/// An integer parameter in `0..=255`, `None` when NaN, fractional or out of range.
fn small_int(x: f32) -> Option<u8> {
    (x.fract() == 0.0 && (0.0..=255.0).contains(&x)).then_some(x as u8)
}

/// What to do with MAV_CMD_INJECT_FAILURE `cmd` (module docs).
pub(super) fn inject_failure(cmd: &COMMAND_LONG_DATA) -> CommandDecision {
    let (Some(unit), Some(kind)) = (small_int(cmd.param1), small_int(cmd.param2)) else {
        return CommandDecision::Refuse(Outcome::Denied("Failure injection: bad unit or type".into()));
    };
    let (Some(name), Some(kind_name)) = (unit_name(unit), type_name(kind)) else {
        return CommandDecision::Unsupported;
    };
    let instance = if cmd.param3.is_nan() {
        Some(0)
    } else {
        small_int(cmd.param3)
    };
    if let (Some(unit), Some(kind)) = (
        FailureUnit::from_failure_unit(unit),
        FailureKind::from_failure_type(kind),
    ) {
        return match instance {
            Some(0 | 1) => CommandDecision::Execute(Request::InjectSensorFailure(SensorFailure { unit, kind })),
            _ => CommandDecision::Refuse(Outcome::Denied(format!(
                "Failure injection: no {name} {} (one instance)",
                cmd.param3
            ))),
        };
    }
    if unit != MOTOR_UNIT {
        return CommandDecision::NotSimulated(format!("Failure injection: {name} not simulated"));
    }
    let failed = match kind {
        TYPE_OK => false,
        TYPE_OFF => true,
        _ => return CommandDecision::NotSimulated(format!("Failure injection: motor {kind_name} not simulated")),
    };
    match instance {
        Some(rotor) => CommandDecision::Execute(Request::InjectRotorFailure {
            rotor: usize::from(rotor),
            failed,
        }),
        None => CommandDecision::Refuse(Outcome::Denied(format!("Failure injection: bad motor {}", cmd.param3))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::command_long;
    use mavlink::dialects::ardupilotmega::MavCmd;

    fn inject(unit: f32, kind: f32, instance: f32) -> CommandDecision {
        let params = [unit, kind, instance, 0.0, 0.0, 0.0, 0.0];
        inject_failure(&command_long((1, 1), MavCmd::MAV_CMD_INJECT_FAILURE, params))
    }

    #[test]
    fn motors_are_switched_off_and_back_on() {
        let off = CommandDecision::Execute(Request::InjectRotorFailure { rotor: 2, failed: true });
        assert_eq!(inject(101.0, 1.0, 2.0), off);
        let on = CommandDecision::Execute(Request::InjectRotorFailure {
            rotor: 0,
            failed: false,
        });
        assert_eq!(inject(101.0, 0.0, f32::NAN), on);
        assert!(matches!(
            inject(101.0, 1.0, 1.5),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
    }

    #[test]
    fn every_other_unit_is_named_in_its_refusal() {
        // MAVSDK's FailureUnit: SENSOR_GYRO 0 … SENSOR_AIRSPEED 8, SYSTEM_BATTERY 100 … 105;
        // the five simulated sensors (0–4) and the motors (101) are simulated.
        for unit in (5..=8).chain(100..=105).filter(|u| *u != 101) {
            let CommandDecision::NotSimulated(why) = inject(f32::from(unit), 1.0, 0.0) else {
                panic!("unit {unit} not refused as not simulated")
            };
            let name = unit_name(unit).unwrap_or_default();
            assert_eq!(why, format!("Failure injection: {name} not simulated"));
            assert!(why.len() <= 50, "{why} fits one STATUSTEXT");
        }
        assert_eq!(
            inject(5.0, 1.0, 0.0),
            CommandDecision::NotSimulated("Failure injection: optical_flow not simulated".into())
        );
        assert_eq!(
            inject(101.0, 2.0, 0.0),
            CommandDecision::NotSimulated("Failure injection: motor stuck not simulated".into())
        );
    }

    #[test]
    fn sensors_fail_in_every_way_one_instance_each() {
        let gps_off = SensorFailure {
            unit: FailureUnit::Gps,
            kind: FailureKind::Off,
        };
        assert_eq!(
            inject(4.0, 1.0, 0.0),
            CommandDecision::Execute(Request::InjectSensorFailure(gps_off))
        );
        assert_eq!(
            inject(4.0, 1.0, f32::NAN),
            CommandDecision::Execute(Request::InjectSensorFailure(gps_off))
        );
        let baro_stuck = SensorFailure {
            unit: FailureUnit::Baro,
            kind: FailureKind::Stuck,
        };
        assert_eq!(
            inject(3.0, 2.0, 1.0),
            CommandDecision::Execute(Request::InjectSensorFailure(baro_stuck))
        );
        assert!(matches!(
            inject(2.0, 1.0, 2.0),
            CommandDecision::Refuse(Outcome::Denied(why)) if why == "Failure injection: no mag 2 (one instance)"
        ));
    }

    #[test]
    fn unknown_numbers_are_unsupported_and_bad_ones_denied() {
        assert_eq!(inject(9.0, 1.0, 0.0), CommandDecision::Unsupported);
        assert_eq!(inject(4.0, 8.0, 0.0), CommandDecision::Unsupported);
        assert!(matches!(inject(f32::NAN, 1.0, 0.0), CommandDecision::Refuse(_)));
        assert!(matches!(inject(4.0, -1.0, 0.0), CommandDecision::Refuse(_)));
    }
}
