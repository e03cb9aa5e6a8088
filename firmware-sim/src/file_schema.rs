//! Raw TOML schema of an airframe file, as the plant reads it.
//!
//! Every field is an `Option` so that a missing field is reported by its dotted path
//! (`vehicle.mass`) in [`crate::params`] instead of by serde's generic message. Unknown
//! fields are refused, so a typo is an error rather than a silently ignored setting.
//! The `[fc]` table belongs to the flight controller and is skipped here.

use serde::Deserialize;

use crate::file_sensors::FileSensors;

/// Top level of an airframe file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileAirframe {
    pub name: Option<String>,
    /// Free text; not used by the plant.
    #[allow(dead_code)]
    pub description: Option<String>,
    pub vehicle: Option<FileVehicle>,
    pub rotors: Option<FileRotors>,
    /// Flight-controller beliefs; not read by the plant.
    #[allow(dead_code)]
    pub fc: Option<toml::Value>,
    pub plant: Option<FilePlant>,
}

/// `[vehicle]`: the true rigid body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileVehicle {
    pub mass: Option<f64>,
    pub inertia: Option<Vec<f64>>,
    pub gear_height: Option<f64>,
}

/// `[rotors]`: constants shared by every rotor, and the layout.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileRotors {
    pub radius: Option<f64>,
    pub c_t: Option<f64>,
    pub c_q: Option<f64>,
    pub omega_min: Option<f64>,
    pub omega_max: Option<f64>,
    pub tau_up: Option<f64>,
    pub tau_down: Option<f64>,
    pub ring: Option<FileRing>,
    pub rotor: Option<Vec<FileRotor>>,
}

/// `[rotors.ring]`: n evenly spaced rotors with alternating spins.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileRing {
    pub count: Option<i64>,
    pub arm: Option<f64>,
    pub first_angle: Option<f64>,
    pub first_spin: Option<String>,
    pub z: Option<f64>,
}

/// `[[rotors.rotor]]`: one rotor of an explicit layout.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileRotor {
    pub angle: Option<f64>,
    pub arm: Option<f64>,
    pub z: Option<f64>,
    pub spin: Option<String>,
}

/// `[plant]`: settings only the simulator uses.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FilePlant {
    pub ground: Option<FileGround>,
    pub ceiling: Option<FileCeiling>,
    pub drag: Option<FileDrag>,
    pub noise: Option<FileNoise>,
    pub sensors: Option<FileSensors>,
    pub disturbance: Option<Vec<FileDisturbance>>,
    pub initial: Option<FileInitial>,
    pub wind: Option<FileWind>,
}

/// `[plant.ground]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileGround {
    pub model: Option<String>,
    pub height: Option<f64>,
    pub spacing: Option<f64>,
    pub body_distance: Option<f64>,
    pub body_gain: Option<f64>,
    pub cap: Option<f64>,
    pub cutoff: Option<f64>,
}

/// `[plant.ceiling]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileCeiling {
    pub enabled: Option<bool>,
    pub height: Option<f64>,
    pub k1: Option<f64>,
    pub k2: Option<f64>,
    pub cap: Option<f64>,
    pub cutoff: Option<f64>,
}

/// `[plant.drag]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileDrag {
    pub linear: Option<Vec<f64>>,
    pub quadratic: Option<Vec<f64>>,
}

/// `[plant.wind]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileWind {
    pub velocity: Option<Vec<f64>>,
    pub turbulence: Option<f64>,
    pub gust: Option<Vec<FileGust>>,
}

/// `[[plant.wind.gust]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileGust {
    pub start: Option<f64>,
    pub duration: Option<f64>,
    pub velocity: Option<Vec<f64>>,
}

/// `[plant.noise]`: standard deviations.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileNoise {
    pub position: Option<f64>,
    pub velocity: Option<f64>,
    pub attitude: Option<f64>,
    pub gyro: Option<f64>,
    pub accel: Option<f64>,
}

/// `[[plant.disturbance]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileDisturbance {
    pub kind: Option<String>,
    pub force: Option<Vec<f64>>,
    pub torque: Option<Vec<f64>>,
    pub start: Option<f64>,
    pub frequency: Option<f64>,
    pub phase: Option<f64>,
}

/// `[plant.initial]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileInitial {
    pub position: Option<Vec<f64>>,
    pub yaw: Option<f64>,
}
