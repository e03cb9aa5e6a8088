//! Raw TOML schema of a scenario file (`rotorpilot sim SCENARIO.toml`). Unknown fields are
//! refused so a typo is an error, not a silently ignored setting.

use serde::Deserialize;

use crate::control::{ControllerKind, DesiredRateMode};
use crate::guidance::trajectory::TrajectorySpec;

/// Top level of a scenario file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ScenarioFile {
    pub name: Option<String>,
    pub description: Option<String>,
    /// [s]
    pub duration: f64,
    /// [s], default 0.001
    pub dt: Option<f64>,
    pub seed: Option<u64>,
    pub airframe: AirframeSpec,
    pub initial: Option<InitialSpec>,
    pub controller: ControllerSpec,
    pub estimator: Option<EstimatorSpec>,
    pub trajectory: TrajectorySpec,
    /// `[[rotor_failure]]` entries.
    pub rotor_failure: Option<Vec<RotorFailureSpec>>,
    /// `[sensors]`: which sensors the flight controller reads.
    pub sensors: Option<SensorsSpec>,
    /// `[[sensor_failure]]` entries.
    pub sensor_failure: Option<Vec<SensorFailureSpec>>,
    /// `[autopilot]`: fly with the flight controller in OFFBOARD.
    pub autopilot: Option<AutopilotSpec>,
}

/// `[autopilot]`: the flight controller of `rotorpilot run` flies the trajectory in OFFBOARD.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AutopilotSpec {
    /// Parameters by PX4 / RP_ name, set before the first tick.
    pub params: Option<toml::Table>,
}

/// `[[rotor_failure]]`: a rotor of the simulated vehicle stops.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RotorFailureSpec {
    /// 1-based rotor number.
    pub rotor: usize,
    /// [s] simulated time
    pub at: f64,
}

/// `[sensors]`: `model = "ideal"` (the state sensor, default) or `"realistic"` (the sensor
/// suite and the navigation filter).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SensorsSpec {
    pub model: String,
}

/// `[[sensor_failure]]`: a sensor of the suite fails (or recovers) at a simulated time.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SensorFailureSpec {
    /// gyro, accel, mag, baro or gps.
    pub sensor: String,
    /// ok, off, stuck, garbage, wrong, slow, delayed or intermittent.
    pub failure: String,
    /// [s] simulated time
    pub at: f64,
}

/// `[airframe]`: a preset or a file, and tables merged over it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AirframeSpec {
    pub preset: Option<String>,
    /// Relative to the scenario file's directory.
    pub path: Option<String>,
    /// Deep-merged over the airframe file: `vehicle` (true body), `fc` (beliefs), `plant`.
    pub overrides: Option<toml::Table>,
}

/// `[initial]`: the vehicle's state at t = 0 (default: resting on the ground).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct InitialSpec {
    /// [m] NED
    pub position: Option<[f64; 3]>,
    /// [m/s] NED
    pub velocity: Option<[f64; 3]>,
    /// roll, pitch, yaw (ZYX) [deg]
    pub attitude: Option<[f64; 3]>,
    /// body rates [deg/s]
    pub rates: Option<[f64; 3]>,
    /// Unit quaternion [w, x, y, z] body → world; overrides `attitude`.
    pub quaternion: Option<[f64; 4]>,
    /// Motors start at hover speed (default true when `position` is given).
    pub motors_at_hover: Option<bool>,
}

/// `[controller]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ControllerSpec {
    pub kind: ControllerKind,
    pub compensation: Option<bool>,
    pub desired_rate: Option<DesiredRateMode>,
    /// Partial [`ControllerGains`](crate::control::ControllerGains) merged over the airframe's defaults.
    pub gains: Option<toml::Table>,
}

/// `[estimator]`: Chebyshev design or gains given directly.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EstimatorSpec {
    pub enabled: Option<bool>,
    pub order: Option<usize>,
    /// [dB]
    pub ripple_db: Option<f64>,
    /// [rad/s]
    pub wp: Option<f64>,
    /// K_1 … K_r [1/s]
    pub gains: Option<Vec<f64>>,
}
