//! Sensor failures that can be injected into the sensor suite, one per [`SensorUnit`]
//! (docs/model.md §10.6).
//!
//! The kinds follow MAVLink's `FAILURE_TYPE` (as used by `MAV_CMD_INJECT_FAILURE` and PX4's
//! `failure <unit> <type>` shell command); what `Wrong` and `Garbage` do is chosen per sensor and
//! documented beside each model ([`super::imu`], [`super::gps`], [`super::baro`], [`super::mag`]).

/// Longest extra latency a [`SensorFault::Delayed`] adds [s]; longer requests are clamped.
pub const MAX_EXTRA_DELAY_S: f64 = 1.0;

/// A sensor that can fail on its own. The IMU's gyroscope and accelerometer are separate units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SensorUnit {
    /// The IMU's gyroscope.
    Gyro,
    /// The IMU's accelerometer.
    Accel,
    /// The magnetometer.
    Mag,
    /// The barometer.
    Baro,
    /// The GPS receiver.
    Gps,
}

impl SensorUnit {
    /// Every unit, in MAVLink `FAILURE_UNIT` order.
    pub const ALL: [SensorUnit; 5] = [Self::Gyro, Self::Accel, Self::Mag, Self::Baro, Self::Gps];

    /// The unit of a MAVLink `FAILURE_UNIT` value (0 gyro, 1 accel, 2 mag, 3 baro, 4 GPS);
    /// `None` for units this suite does not simulate.
    pub fn from_failure_unit(failure_unit: u32) -> Option<Self> {
        Self::ALL.get(usize::try_from(failure_unit).ok()?).copied()
    }

    /// The MAVLink `FAILURE_UNIT` value of this unit.
    pub fn failure_unit(self) -> u8 {
        match self {
            Self::Gyro => 0,
            Self::Accel => 1,
            Self::Mag => 2,
            Self::Baro => 3,
            Self::Gps => 4,
        }
    }
}

/// What a failed sensor does (docs/model.md §10.6). Times count from the first
/// [`crate::SensorSuite::read`] after the fault was set (its onset).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum SensorFault {
    /// Healthy.
    #[default]
    Ok,
    /// No samples at all.
    Off,
    /// The last healthy sample before the onset (the first one after it, if there was none) is
    /// repeated at the sensor's rate, with fresh timestamps.
    Stuck,
    /// Random values over the sensor's range (the GPS: a lost, then degraded fix).
    Garbage,
    /// Plausible but wrong values: a constant offset (the GPS: a slow drift with a healthy fix).
    Wrong,
    /// Only every `divisor`-th sample is delivered (the rate divided).
    Slow {
        /// Rate divisor [-], at least 1.
        divisor: u32,
    },
    /// Each sample arrives `extra_s` later than it would: the sample delivered at t is the one
    /// the healthy sensor delivered at t − extra_s, time-stamped t.
    Delayed {
        /// Added latency [s], in [0, [`MAX_EXTRA_DELAY_S`]].
        extra_s: f64,
    },
    /// On and off in windows of `period_s`; each window is on with probability `availability`,
    /// drawn from the suite's seed.
    Intermittent {
        /// Window length [s], positive.
        period_s: f64,
        /// Probability that a window delivers samples [-], in [0, 1].
        availability: f64,
    },
}

impl SensorFault {
    /// [`SensorFault::Slow`] with the rate divided by 10.
    pub const SLOW: Self = Self::Slow { divisor: 10 };
    /// [`SensorFault::Delayed`] by 0.3 s (almost three times EKF2_GPS_DELAY).
    pub const DELAYED: Self = Self::Delayed { extra_s: 0.3 };
    /// [`SensorFault::Intermittent`] in 0.5 s windows, half of them on.
    pub const INTERMITTENT: Self = Self::Intermittent {
        period_s: 0.5,
        availability: 0.5,
    };

    /// The fault of a MAVLink `FAILURE_TYPE` value (0 ok, 1 off, 2 stuck, 3 garbage, 4 wrong,
    /// 5 slow, 6 delayed, 7 intermittent), with the default magnitudes [`Self::SLOW`],
    /// [`Self::DELAYED`] and [`Self::INTERMITTENT`].
    pub fn from_failure_type(failure_type: u32) -> Option<Self> {
        Some(match failure_type {
            0 => Self::Ok,
            1 => Self::Off,
            2 => Self::Stuck,
            3 => Self::Garbage,
            4 => Self::Wrong,
            5 => Self::SLOW,
            6 => Self::DELAYED,
            7 => Self::INTERMITTENT,
            _ => return None,
        })
    }

    /// The MAVLink `FAILURE_TYPE` value of this fault.
    pub fn failure_type(&self) -> u8 {
        match self {
            Self::Ok => 0,
            Self::Off => 1,
            Self::Stuck => 2,
            Self::Garbage => 3,
            Self::Wrong => 4,
            Self::Slow { .. } => 5,
            Self::Delayed { .. } => 6,
            Self::Intermittent { .. } => 7,
        }
    }

    /// The fault with its magnitudes brought into range: divisor at least 1, extra delay in
    /// [0, [`MAX_EXTRA_DELAY_S`]], period positive (0.5 s when not), availability in [0, 1]
    /// (0.5 when not a number).
    pub fn sanitized(self) -> Self {
        match self {
            Self::Slow { divisor } => Self::Slow {
                divisor: divisor.max(1),
            },
            Self::Delayed { extra_s } => Self::Delayed {
                extra_s: if extra_s.is_nan() {
                    0.0
                } else {
                    extra_s.clamp(0.0, MAX_EXTRA_DELAY_S)
                },
            },
            Self::Intermittent { period_s, availability } => Self::Intermittent {
                period_s: if period_s.is_finite() && period_s > 0.0 {
                    period_s
                } else {
                    0.5
                },
                availability: if availability.is_nan() {
                    0.5
                } else {
                    availability.clamp(0.0, 1.0)
                },
            },
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mavlink_numbers_round_trip() {
        for t in 0..8 {
            let fault = SensorFault::from_failure_type(t).unwrap();
            assert_eq!(u32::from(fault.failure_type()), t);
        }
        assert_eq!(SensorFault::from_failure_type(8), None);
        for unit in SensorUnit::ALL {
            assert_eq!(
                SensorUnit::from_failure_unit(u32::from(unit.failure_unit())),
                Some(unit)
            );
        }
        assert_eq!(SensorUnit::from_failure_unit(5), None);
        assert_eq!(SensorUnit::from_failure_unit(u32::MAX), None);
    }

    #[test]
    fn magnitudes_are_brought_into_range() {
        assert_eq!(
            SensorFault::Slow { divisor: 0 }.sanitized(),
            SensorFault::Slow { divisor: 1 }
        );
        assert_eq!(
            SensorFault::Delayed { extra_s: 5.0 }.sanitized(),
            SensorFault::Delayed {
                extra_s: MAX_EXTRA_DELAY_S
            }
        );
        assert_eq!(
            SensorFault::Delayed { extra_s: f64::NAN }.sanitized(),
            SensorFault::Delayed { extra_s: 0.0 }
        );
        assert_eq!(
            SensorFault::Intermittent {
                period_s: -1.0,
                availability: 2.0
            }
            .sanitized(),
            SensorFault::Intermittent {
                period_s: 0.5,
                availability: 1.0
            }
        );
        assert_eq!(SensorFault::Wrong.sanitized(), SensorFault::Wrong);
    }
}
