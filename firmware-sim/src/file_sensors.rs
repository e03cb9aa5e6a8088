//! Raw TOML schema of `[plant.sensors]`: the sensor suite's settings (docs/model.md §10.7).
//!
//! Every field is optional and overrides the set `base` names (`SensorSuiteConfig::typical()`,
//! PX4 SITL's, by default; `"hardware"`: `SensorSuiteConfig::hardware()`); unknown fields are
//! refused. Units are SI, angles in degrees; validation is in `sensor_params.rs`.

use serde::Deserialize;

/// `[plant.sensors]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileSensors {
    pub base: Option<String>,
    pub imu: Option<FileImu>,
    pub gps: Option<FileGps>,
    pub baro: Option<FileBaro>,
    pub mag: Option<FileMag>,
}

/// `[plant.sensors.imu]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileImu {
    pub accel_noise: Option<f64>,
    pub accel_bias_walk: Option<f64>,
    pub accel_turn_on_bias: Option<f64>,
    pub gyro_noise: Option<f64>,
    pub gyro_bias_walk: Option<f64>,
    pub gyro_turn_on_bias: Option<f64>,
}

/// `[plant.sensors.gps]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileGps {
    pub rate: Option<f64>,
    pub latency: Option<f64>,
    pub h_noise: Option<f64>,
    pub v_noise: Option<f64>,
    pub h_wander: Option<f64>,
    pub v_wander: Option<f64>,
    pub wander_tau: Option<f64>,
    pub vel_noise: Option<f64>,
    pub satellites: Option<i64>,
    pub h_acc: Option<f64>,
    pub v_acc: Option<f64>,
    pub speed_acc: Option<f64>,
}

/// `[plant.sensors.baro]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileBaro {
    pub rate: Option<f64>,
    pub origin_altitude: Option<f64>,
    pub noise: Option<f64>,
    pub drift: Option<f64>,
}

/// `[plant.sensors.mag]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileMag {
    pub rate: Option<f64>,
    pub strength: Option<f64>,
    pub declination: Option<f64>,
    pub inclination: Option<f64>,
    pub noise: Option<f64>,
    pub bias: Option<Vec<f64>>,
}
