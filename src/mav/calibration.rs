//! MAV_CMD_PREFLIGHT_CALIBRATION (241) answered as PX4 SITL answers it, with the `[cal]`
//! STATUSTEXT protocol QGroundControl and MAVSDK parse (PX4's `calibration_messages.h`,
//! version 2): `[cal] calibration started: 2 <sensor>`, `[cal] progress <n>`, then
//! `[cal] calibration done: <sensor>` or `[cal] calibration failed: <reason>`.
//!
//! Parameters as PX4 reads them: p1 = 1 gyro, p2 = 1 mag, p3 = 1 baro, p4 = 1/2 RC, p5 = 1
//! accel, 2 level horizon, 4 quick accel, p6 = 1/2 airspeed, p7 = 1 ESC; all zero ends an RC
//! calibration or cancels (PX4 accepts it). The simulated sensors are exact, so gyro, baro and
//! level calibration finish at once. Accelerometer and magnetometer calibration need the vehicle
//! turned onto its sides / rotated by hand, which nothing here can do: they start and fail with
//! the reason, never stay silent. RC, airspeed and ESC calibration concern hardware this vehicle
//! lacks: ACK UNSUPPORTED. Refused while armed (PX4: TEMPORARILY_REJECTED). Pure.

use mavlink::dialects::ardupilotmega::COMMAND_LONG_DATA;

use crate::commander::Outcome;

/// One calibration PREFLIGHT_CALIBRATION can start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Calibration {
    /// Gyroscope offsets (p1 = 1).
    Gyro,
    /// Magnetometer (p2 = 1): needs the vehicle rotated.
    Mag,
    /// Barometer (p3 = 1).
    Baro,
    /// Accelerometer, six sides or quick (p5 = 1 or 4): needs the vehicle turned over.
    Accel,
    /// Level horizon (p5 = 2).
    Level,
    /// All parameters zero: end of an RC calibration, or cancel.
    Cancel,
}

/// What PREFLIGHT_CALIBRATION asks for: a calibration, or `None` for one of hardware this
/// vehicle lacks (RC, airspeed, ESC, temperature) or parameters PX4 does not read.
pub fn decode(cmd: &COMMAND_LONG_DATA) -> Option<Calibration> {
    let p = |x: f32| if x.is_nan() { 0 } else { x.round() as i32 };
    let params = [
        cmd.param1, cmd.param2, cmd.param3, cmd.param4, cmd.param5, cmd.param6, cmd.param7,
    ]
    .map(p);
    match params {
        [1, 0, 0, 0, 0, 0, 0] => Some(Calibration::Gyro),
        [0, 1, 0, 0, 0, 0, 0] => Some(Calibration::Mag),
        [0, 0, 1, 0, 0, 0, 0] => Some(Calibration::Baro),
        [0, 0, 0, 0, 1 | 4, 0, 0] => Some(Calibration::Accel),
        [0, 0, 0, 0, 2, 0, 0] => Some(Calibration::Level),
        [0, 0, 0, 0, 0, 0, 0] => Some(Calibration::Cancel),
        _ => None,
    }
}

/// A STATUSTEXT line of the calibration, with whether it reports a failure (sent at severity
/// CRITICAL as PX4's `calibration_log_critical`, else INFO).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CalText {
    /// The text (at most 50 bytes).
    pub text: String,
    /// True for a failure.
    pub critical: bool,
}

/// The answer to `calibration` while `armed`: the refusal, or (after ACK ACCEPTED) the
/// STATUSTEXT lines in order (module docs).
pub fn run(calibration: Calibration, armed: bool) -> Result<Vec<CalText>, Outcome> {
    if armed && calibration != Calibration::Cancel {
        return Err(Outcome::TemporarilyRejected("Calibration denied: disarm first".into()));
    }
    let info = |text: String| CalText { text, critical: false };
    let (sensor, failure) = match calibration {
        Calibration::Cancel => return Ok(Vec::new()),
        Calibration::Gyro => ("gyro", None),
        Calibration::Baro => ("baro", None),
        Calibration::Level => ("level", None),
        Calibration::Accel => ("accel", Some("accel not simulated")),
        Calibration::Mag => ("mag", Some("mag not simulated")),
    };
    let mut texts = vec![
        info(format!("[cal] calibration started: 2 {sensor}")),
        info("[cal] progress <0>".into()),
    ];
    match failure {
        None => {
            texts.push(info("[cal] progress <100>".into()));
            texts.push(info(format!("[cal] calibration done: {sensor}")));
        }
        Some(why) => texts.push(CalText {
            text: format!("[cal] calibration failed: {why}"),
            critical: true,
        }),
    }
    Ok(texts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::command_long;
    use mavlink::dialects::ardupilotmega::MavCmd;

    fn cal(params: [f32; 7]) -> Option<Calibration> {
        decode(&command_long((1, 1), MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION, params))
    }

    #[test]
    fn parameters_pick_the_calibration_as_px4_reads_them() {
        assert_eq!(cal([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]), Some(Calibration::Gyro));
        assert_eq!(cal([0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]), Some(Calibration::Mag));
        assert_eq!(cal([0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]), Some(Calibration::Accel));
        assert_eq!(cal([0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0]), Some(Calibration::Accel));
        assert_eq!(cal([0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0]), Some(Calibration::Level));
        assert_eq!(cal([0.0; 7]), Some(Calibration::Cancel));
        assert_eq!(cal([f32::NAN; 7]), Some(Calibration::Cancel));
        // RC, airspeed, ESC: hardware this vehicle lacks.
        assert_eq!(cal([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]), None);
        assert_eq!(cal([0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]), None);
        assert_eq!(cal([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]), None);
    }

    #[test]
    fn gyro_and_level_finish_with_the_messages_qgc_parses() {
        let texts: Vec<String> = run(Calibration::Gyro, false)
            .unwrap()
            .into_iter()
            .map(|t| t.text)
            .collect();
        assert_eq!(
            texts,
            [
                "[cal] calibration started: 2 gyro",
                "[cal] progress <0>",
                "[cal] progress <100>",
                "[cal] calibration done: gyro"
            ]
        );
        let level = run(Calibration::Level, false).unwrap();
        assert_eq!(
            level.last().map(|t| t.text.as_str()),
            Some("[cal] calibration done: level")
        );
        assert!(level.iter().all(|t| !t.critical));
    }

    #[test]
    fn accel_and_mag_start_then_fail_with_the_reason() {
        for (c, sensor) in [(Calibration::Accel, "accel"), (Calibration::Mag, "mag")] {
            let texts = run(c, false).unwrap();
            assert_eq!(texts[0].text, format!("[cal] calibration started: 2 {sensor}"));
            let last = texts.last().unwrap();
            assert!(last.critical);
            assert_eq!(last.text, format!("[cal] calibration failed: {sensor} not simulated"));
        }
    }

    #[test]
    fn armed_vehicles_refuse_and_cancel_is_quiet() {
        assert!(matches!(
            run(Calibration::Gyro, true),
            Err(Outcome::TemporarilyRejected(_))
        ));
        assert_eq!(run(Calibration::Cancel, true), Ok(Vec::new()));
    }
}
