//! A vehicle of the runtime (the flight controller and the plant at 1 kHz, stepped tick by tick)
//! as the closed-loop tests build it: the geometric law at the default home, one call instead of
//! a constructor repeated in every test module.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::airframe::AirframeSource;
use rotorpilot::control::ControllerKind;
use rotorpilot::guidance::Home;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;

/// The tick [s].
pub const DT_S: f64 = 1e-3;

/// Airframe preset `preset` on `sensors`, noise seed `seed`, with `params` (name, value) set.
pub fn vehicle(preset: &str, sensors: SensorModel, seed: u64, params: &[(&str, f64)]) -> Vehicle {
    let mut v = vehicle_from(&AirframeSource::resolve(preset).unwrap(), sensors, seed);
    for (name, value) in params {
        v.set_param(name, *value).unwrap();
    }
    v
}

/// The airframe `src` on `sensors`, noise seed `seed`.
pub fn vehicle_from(src: &AirframeSource, sensors: SensorModel, seed: u64) -> Vehicle {
    Vehicle::new(src, ControllerKind::Geometric, Home::default(), sensors, seed, DT_S).unwrap()
}
