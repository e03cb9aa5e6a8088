//! Sensor failures as the flight controller and its ground stations name them: MAVLink's
//! FAILURE_UNIT (gyro, accel, mag, baro, gps) and FAILURE_TYPE (ok, off, stuck, garbage, wrong,
//! slow, delayed, intermittent), injected by MAV_CMD_INJECT_FAILURE, a scenario's
//! `[[sensor_failure]]` or `--fail UNIT:TYPE@SECONDS`. What each does to a sensor is the
//! simulator's business (docs/model.md §10.6). Pure.

use serde::Serialize;

/// A sensor that can be failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureUnit {
    /// The IMU's gyroscope (FAILURE_UNIT 0).
    Gyro,
    /// The IMU's accelerometer (1).
    Accel,
    /// The magnetometer (2).
    Mag,
    /// The barometer (3).
    Baro,
    /// The GPS receiver (4).
    Gps,
}

/// How a sensor fails (FAILURE_TYPE, in its order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// Working again (0).
    Ok,
    /// No samples (1).
    Off,
    /// The last good sample, repeated (2).
    Stuck,
    /// Random values (3).
    Garbage,
    /// Plausible but wrong values (4).
    Wrong,
    /// Samples at a tenth of the rate (5).
    Slow,
    /// Samples late (6).
    Delayed,
    /// Samples on and off (7).
    Intermittent,
}

impl FailureUnit {
    /// Every unit, in FAILURE_UNIT order.
    pub const ALL: [Self; 5] = [Self::Gyro, Self::Accel, Self::Mag, Self::Baro, Self::Gps];

    /// The FAILURE_UNIT number.
    pub fn failure_unit(self) -> u8 {
        self as u8
    }

    /// The unit of FAILURE_UNIT `unit`, `None` for a unit that is not a simulated sensor.
    pub fn from_failure_unit(unit: u8) -> Option<Self> {
        Self::ALL.get(usize::from(unit)).copied()
    }

    /// PX4's name (`failure gps off`).
    pub fn name(self) -> &'static str {
        ["gyro", "accel", "mag", "baro", "gps"][self as usize]
    }
}

impl FailureKind {
    /// Every kind, in FAILURE_TYPE order.
    pub const ALL: [Self; 8] = [
        Self::Ok,
        Self::Off,
        Self::Stuck,
        Self::Garbage,
        Self::Wrong,
        Self::Slow,
        Self::Delayed,
        Self::Intermittent,
    ];

    /// The FAILURE_TYPE number.
    pub fn failure_type(self) -> u8 {
        self as u8
    }

    /// The kind of FAILURE_TYPE `kind`, `None` past the enum.
    pub fn from_failure_type(kind: u8) -> Option<Self> {
        Self::ALL.get(usize::from(kind)).copied()
    }

    /// PX4's name (`failure gps off`).
    pub fn name(self) -> &'static str {
        [
            "ok",
            "off",
            "stuck",
            "garbage",
            "wrong",
            "slow",
            "delayed",
            "intermittent",
        ][self as usize]
    }
}

/// One sensor failing (or recovering, [`FailureKind::Ok`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct SensorFailure {
    /// Which sensor.
    pub unit: FailureUnit,
    /// How.
    pub kind: FailureKind,
}

impl std::str::FromStr for SensorFailure {
    type Err = String;

    /// `UNIT:TYPE`, PX4's names: `gps:off`, `baro:stuck`, `mag:ok`.
    fn from_str(text: &str) -> Result<Self, String> {
        let (unit, kind) = text
            .split_once(':')
            .ok_or_else(|| format!("{text}: expected UNIT:TYPE, e.g. gps:off"))?;
        let unit = FailureUnit::ALL
            .into_iter()
            .find(|u| u.name() == unit.trim())
            .ok_or_else(|| format!("{text}: unknown sensor \"{unit}\"; expected gyro, accel, mag, baro or gps"))?;
        let kind = FailureKind::ALL.into_iter().find(|k| k.name() == kind.trim()).ok_or_else(|| {
            format!("{text}: unknown failure \"{kind}\"; expected ok, off, stuck, garbage, wrong, slow, delayed or intermittent")
        })?;
        Ok(Self { unit, kind })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_names_follow_mavlink_and_px4() {
        assert_eq!(FailureUnit::from_failure_unit(4), Some(FailureUnit::Gps));
        assert_eq!(FailureUnit::from_failure_unit(5), None, "optical flow is not simulated");
        assert_eq!(FailureKind::from_failure_type(7), Some(FailureKind::Intermittent));
        assert_eq!(FailureKind::from_failure_type(8), None);
        for u in FailureUnit::ALL {
            assert_eq!(FailureUnit::from_failure_unit(u.failure_unit()), Some(u));
        }
        assert_eq!(
            "gps:off".parse::<SensorFailure>(),
            Ok(SensorFailure {
                unit: FailureUnit::Gps,
                kind: FailureKind::Off
            })
        );
        let e = "lidar:off".parse::<SensorFailure>().unwrap_err();
        assert!(e.contains("unknown sensor \"lidar\""), "{e}");
        let e = "gps:broken".parse::<SensorFailure>().unwrap_err();
        assert!(e.contains("unknown failure \"broken\""), "{e}");
        assert!("gps".parse::<SensorFailure>().unwrap_err().contains("UNIT:TYPE"));
    }
}
