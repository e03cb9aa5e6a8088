//! Rotors that stop and sensors that fail at a simulated time (`--fail-rotor ROTOR@SECONDS`,
//! `--fail UNIT:TYPE@SECONDS`, a scenario's `[[rotor_failure]]` and `[[sensor_failure]]`): faults
//! of the simulated hardware, so the lockstep applies them to the plant; the flight controller
//! only notices them in what its ESCs and sensors report. Pure.

use crate::sensor_failure::SensorFailure;
use crate::sitl::PlantChange;

/// A rotor that stops at a simulated time.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ScheduledFailure {
    /// Rotor, 1-based.
    pub rotor: usize,
    /// Simulated time it stops [s].
    pub at_s: f64,
}

impl std::str::FromStr for ScheduledFailure {
    type Err = String;

    /// `ROTOR@SECONDS`, e.g. `2@5.5`: rotor 2 stops 5.5 s after start (simulated time).
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = || format!("--fail-rotor {text}: expected ROTOR@SECONDS, e.g. 2@5.5");
        let (rotor, at) = text.split_once('@').ok_or_else(bad)?;
        let rotor: usize = rotor.trim().parse().map_err(|_| bad())?;
        let at_s: f64 = at.trim().parse().map_err(|_| bad())?;
        if rotor == 0 || !(at_s.is_finite() && at_s >= 0.0) {
            return Err(bad());
        }
        Ok(Self { rotor, at_s })
    }
}

/// A sensor that fails (or recovers) at a simulated time.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ScheduledSensorFailure {
    /// Which sensor and how.
    pub failure: SensorFailure,
    /// Simulated time it happens [s].
    pub at_s: f64,
}

impl std::str::FromStr for ScheduledSensorFailure {
    type Err = String;

    /// `UNIT:TYPE@SECONDS`, e.g. `gps:off@20`: the GPS goes off 20 s after start.
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = |why: String| format!("--fail {text}: {why}");
        let (failure, at) = text
            .split_once('@')
            .ok_or_else(|| bad("expected UNIT:TYPE@SECONDS, e.g. gps:off@20".into()))?;
        let failure: SensorFailure = failure.parse().map_err(bad)?;
        let at_s: f64 = at
            .trim()
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite() && *t >= 0.0)
            .ok_or_else(|| bad(format!("\"{at}\" is not a time >= 0 in seconds")))?;
        Ok(Self { failure, at_s })
    }
}

/// The rotor and sensor failures still to come for a vehicle of a given rotor count.
#[derive(Debug, Clone, Default)]
pub struct FailureSchedule {
    rotors: usize,
    scheduled: Vec<ScheduledFailure>,
    sensors: Vec<ScheduledSensorFailure>,
}

impl FailureSchedule {
    /// Nothing scheduled for a vehicle of `rotors` rotors.
    pub fn new(rotors: usize) -> Self {
        Self {
            rotors,
            scheduled: Vec::new(),
            sensors: Vec::new(),
        }
    }

    /// Schedules a sensor failure.
    pub fn schedule_sensor(&mut self, failure: ScheduledSensorFailure) {
        self.sensors.push(failure);
    }

    /// Schedules `failure`; refused naming what is wrong.
    pub fn schedule(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        if failure.rotor == 0 || failure.rotor > self.rotors {
            return Err(format!(
                "rotor {}: this vehicle has rotors 1 to {}",
                failure.rotor, self.rotors
            ));
        }
        if !(failure.at_s.is_finite() && failure.at_s >= 0.0) {
            return Err(format!(
                "rotor {} at {} s: the time must be >= 0",
                failure.rotor, failure.at_s
            ));
        }
        self.scheduled.push(failure);
        Ok(())
    }

    /// Nothing left to fail.
    pub fn is_empty(&self) -> bool {
        self.scheduled.is_empty() && self.sensors.is_empty()
    }

    /// Removes the failures due at simulated time `t_s` [s] and hands each to `apply` as the
    /// plant change that stops its rotor, in the order they were scheduled.
    pub fn take_due(&mut self, t_s: f64, mut apply: impl FnMut(PlantChange)) {
        self.scheduled.retain(|f| {
            let due = f.at_s <= t_s;
            if due {
                apply(PlantChange::Rotors {
                    rotors: f.rotor - 1..f.rotor,
                    failed: true,
                });
            }
            !due
        });
        self.sensors.retain(|f| {
            let due = f.at_s <= t_s;
            if due {
                apply(PlantChange::Sensor(f.failure));
            }
            !due
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_parse_and_are_checked_against_the_rotor_count() {
        assert_eq!(
            "2@5.5".parse::<ScheduledFailure>(),
            Ok(ScheduledFailure { rotor: 2, at_s: 5.5 })
        );
        for bad in ["2", "0@1", "x@1", "1@-2", "1@inf"] {
            let e = bad.parse::<ScheduledFailure>().unwrap_err();
            assert!(e.contains(bad) && e.contains("ROTOR@SECONDS"), "{e}");
        }
        let mut f = FailureSchedule::new(4);
        assert!(f.schedule(ScheduledFailure { rotor: 4, at_s: 1.0 }).is_ok());
        let e = f.schedule(ScheduledFailure { rotor: 5, at_s: 1.0 }).unwrap_err();
        assert_eq!(e, "rotor 5: this vehicle has rotors 1 to 4");
    }

    #[test]
    fn due_failures_are_handed_out_once() {
        let mut f = FailureSchedule::new(4);
        f.schedule(ScheduledFailure { rotor: 2, at_s: 1.0 }).unwrap();
        f.schedule(ScheduledFailure { rotor: 3, at_s: 2.0 }).unwrap();
        let mut changes = Vec::new();
        f.take_due(0.5, |c| changes.push(c));
        assert!(changes.is_empty());
        f.take_due(1.0, |c| changes.push(c));
        f.take_due(1.5, |c| changes.push(c));
        assert_eq!(
            changes,
            vec![PlantChange::Rotors {
                rotors: 1..2,
                failed: true
            }]
        );
        assert!(!f.is_empty());
        f.take_due(3.0, |_| {});
        assert!(f.is_empty());
    }

    #[test]
    fn sensor_failures_parse_and_fall_due() {
        let gps_off: ScheduledSensorFailure = "gps:off@20".parse().unwrap();
        assert_eq!(gps_off.at_s, 20.0);
        assert_eq!(gps_off.failure, "gps:off".parse().unwrap());
        for (bad, why) in [
            ("gps:off", "UNIT:TYPE@SECONDS"),
            ("gps:off@-1", "not a time"),
            ("sonar:off@1", "unknown sensor"),
        ] {
            let e = bad.parse::<ScheduledSensorFailure>().unwrap_err();
            assert!(e.starts_with(&format!("--fail {bad}: ")) && e.contains(why), "{e}");
        }
        let mut f = FailureSchedule::new(4);
        f.schedule_sensor(gps_off);
        let mut changes = Vec::new();
        f.take_due(19.9, |c| changes.push(c));
        assert!(changes.is_empty() && !f.is_empty());
        f.take_due(20.0, |c| changes.push(c));
        assert_eq!(changes, vec![PlantChange::Sensor(gps_off.failure)]);
        assert!(f.is_empty());
    }
}
