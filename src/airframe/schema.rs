//! The airframe file as the flight controller reads it: `[vehicle]`, `[rotors]` and the `[fc]`
//! beliefs; `[plant]` belongs to the simulator and is skipped.

use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AirframeFile {
    pub name: Option<String>,
    #[allow(dead_code)]
    pub description: Option<String>,
    pub vehicle: Option<VehicleTable>,
    pub rotors: Option<RotorsTable>,
    pub fc: Option<BeliefTable>,
    #[allow(dead_code)]
    pub plant: Option<toml::Value>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VehicleTable {
    pub mass: Option<f64>,
    pub inertia: Option<Vec<f64>>,
    #[allow(dead_code)]
    pub gear_height: Option<f64>,
}

/// `[fc]`: what the flight controller believes where it differs from the true vehicle.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BeliefTable {
    pub mass: Option<f64>,
    pub inertia: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RotorsTable {
    pub radius: Option<f64>,
    pub c_t: Option<f64>,
    pub c_q: Option<f64>,
    pub omega_min: Option<f64>,
    pub omega_max: Option<f64>,
    #[allow(dead_code)]
    pub tau_up: Option<f64>,
    #[allow(dead_code)]
    pub tau_down: Option<f64>,
    pub ring: Option<RingTable>,
    pub rotor: Option<Vec<RotorEntry>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RingTable {
    pub count: Option<i64>,
    pub arm: Option<f64>,
    pub first_angle: Option<f64>,
    pub first_spin: Option<String>,
    pub z: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RotorEntry {
    pub angle: Option<f64>,
    pub arm: Option<f64>,
    pub z: Option<f64>,
    pub spin: Option<String>,
}
