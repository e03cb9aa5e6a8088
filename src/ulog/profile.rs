//! How often each topic is logged: the default profile of `rotorpilot run` (rates near PX4's
//! default logger profile, the estimator's inputs together at 50 Hz) and the full profile of `sim`
//! and `fly --log` (every 1 kHz tick for the state the controllers fly on, the control and the
//! estimate; the rest at PX4's rates or faster, the plant's true state at 100 Hz as PX4 SITL logs
//! its `*_groundtruth` topics). Topics that change seldom (status, land detector, the true wrench)
//! are also logged whenever they change. Pure.

use std::str::FromStr;

use super::topics::Topic;

/// A logging profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Profile {
    /// PX4-like rates (tens of Hz); `rotorpilot run`'s flight logs.
    #[default]
    Default,
    /// Every tick for the state, control and estimate topics; `sim` and `fly --log`.
    Full,
}

impl FromStr for Profile {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "default" => Ok(Self::Default),
            "full" => Ok(Self::Full),
            other => Err(format!("{other:?}: expected default or full")),
        }
    }
}

impl Profile {
    /// The name on the command line and in the log's info.
    pub fn name(self) -> &'static str {
        match self {
            Self::Default => "default",
            Self::Full => "full",
        }
    }

    /// Least time between two records of `topic` [µs]; 0 logs every tick.
    pub fn interval_us(self, topic: Topic) -> u64 {
        use Topic::*;
        let ms = match (self, topic) {
            (Self::Full, VehicleAttitude | VehicleAngularVelocity | VehicleLocalPosition) => 0,
            // PX4 SITL logs the true attitude and rates at 100 Hz; the truth at every tick would
            // be a third of the file (on the exact state, a copy of the topics above).
            (
                Self::Full,
                VehicleAttitudeGroundtruth | VehicleAngularVelocityGroundtruth | VehicleLocalPositionGroundtruth,
            ) => 10,
            (Self::Full, ControllerErrors | AllocationStatus | ExternalWrenchEstimate) => 0,
            (Self::Full, VehicleThrustSetpoint | VehicleTorqueSetpoint | VehicleAttitudeSetpoint) => 10,
            (Self::Full, VehicleLocalPositionSetpoint | SensorCombined | ActuatorMotors) => 10,
            (Self::Full, VehicleGlobalPosition | BatteryStatus | ExternalWrenchTruth) => 100,
            // The estimator's inputs share one rate, so `estimate --ts 0.02` replays a flight.
            (Self::Default, VehicleAttitude | VehicleAngularVelocity | VehicleLocalPosition) => 20,
            (
                Self::Default,
                VehicleAttitudeGroundtruth | VehicleAngularVelocityGroundtruth | VehicleLocalPositionGroundtruth,
            ) => 20,
            (Self::Default, ControllerErrors | AllocationStatus | ExternalWrenchEstimate) => 20,
            (Self::Default, VehicleThrustSetpoint | VehicleTorqueSetpoint) => 20,
            (Self::Default, VehicleAttitudeSetpoint) => 50,
            (Self::Default, VehicleLocalPositionSetpoint) => 100,
            (Self::Default, SensorCombined | ActuatorMotors) => 100,
            (Self::Default, VehicleGlobalPosition | BatteryStatus) => 200,
            (Self::Default, ExternalWrenchTruth) => 1000,
            (_, VehicleStatus | VehicleLandDetected) => 1000,
        };
        ms * 1000
    }

    /// True for topics also logged as soon as their value changes.
    pub fn on_change(topic: Topic) -> bool {
        matches!(
            topic,
            Topic::VehicleStatus | Topic::VehicleLandDetected | Topic::ExternalWrenchTruth
        )
    }

    /// Least time between two looks for a change of an on-change topic [µs]: every tick for
    /// the status and the land detector; for the true wrench every 10 ms in the full profile and
    /// every 20 ms, on the estimate's grid, in the default one (a disturbance that varies all the
    /// time, drag in a moving vehicle, is logged at 100 or 50 Hz, not at every tick).
    pub fn change_interval_us(self, topic: Topic) -> u64 {
        match (self, topic) {
            (Self::Full, Topic::ExternalWrenchTruth) => 10_000,
            (Self::Default, Topic::ExternalWrenchTruth) => 20_000,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_full_profile_logs_the_state_every_tick() {
        for t in [
            Topic::VehicleAttitude,
            Topic::VehicleLocalPosition,
            Topic::AllocationStatus,
        ] {
            assert_eq!(Profile::Full.interval_us(t), 0);
            assert!(Profile::Default.interval_us(t) >= 20_000);
        }
    }

    #[test]
    fn the_full_profile_logs_the_truth_at_100_hz() {
        for t in [
            Topic::VehicleAttitudeGroundtruth,
            Topic::VehicleAngularVelocityGroundtruth,
            Topic::VehicleLocalPositionGroundtruth,
        ] {
            assert_eq!(Profile::Full.interval_us(t), 10_000);
        }
    }

    #[test]
    fn a_true_wrench_that_always_changes_is_logged_with_the_estimate_by_default() {
        let truth = Topic::ExternalWrenchTruth;
        assert_eq!(
            Profile::Default.change_interval_us(truth),
            Profile::Default.interval_us(Topic::ExternalWrenchEstimate)
        );
        assert_eq!(Profile::Full.change_interval_us(truth), 10_000);
        assert_eq!(
            Profile::Full.change_interval_us(Topic::VehicleStatus),
            0,
            "status: every tick"
        );
    }

    #[test]
    fn profiles_parse_by_name() {
        assert_eq!("full".parse::<Profile>(), Ok(Profile::Full));
        assert!("fast".parse::<Profile>().unwrap_err().contains("default or full"));
    }
}
