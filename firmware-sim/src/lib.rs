//! `firmware_sim`: the simulated multirotor that rotorpilot flies.
//!
//! The plant is the world the flight controller lives in, not part of it: this crate never
//! depends on the flight-controller crate, parses airframe files with its own types and derives
//! rotor geometry with its own code, so a sign error in either side shows up in closed-loop tests
//! instead of being shared. Frames are NED world and FRD body throughout; units are SI.
//!
//! # Layout
//!
//! - [`params`]: the plant's view of an airframe file, validated ([`PlantParams`], [`ParamsError`]).
//! - `file_schema`, `layout`, `validate`: raw TOML schema, rotor positions from a ring or a list,
//!   field checks.
//! - [`rigid_body`]: 6-DoF Newton–Euler in NED/FRD, fixed-step RK4, quaternion renormalisation.
//! - [`rotor`]: thrust and drag torque per rotor, first-order motor lag with up/down constants.
//! - [`proximity`]: ground and ceiling thrust factors (Cheeseman–Bennett, multirotor, ceiling).
//! - [`contact`]: resting on the ground without sinking or bouncing; ceiling stop.
//! - [`disturbance`]: scripted external wrench (constant, step, sinusoid) and aerodynamic drag.
//! - [`wind`]: mean wind, discrete gusts and Dryden turbulence, seeded.
//! - [`sensors`]: the state sensor (exact state with seeded ChaCha noise, zero by default) and the
//!   sensor suite: IMU, GPS, barometer and magnetometer with bias, drift, latency and injectable
//!   failures ([`SensorSuite`], [`SensorFault`]; docs/model.md §10).
//! - `file_sensors`, `sensor_params`: the `[plant.sensors]` tables and their validation.
//! - [`plant`]: [`Plant::step`], [`Plant::truth`], [`Plant::sense`].
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod contact;
pub mod disturbance;
mod file_schema;
mod file_sensors;
mod layout;
pub mod params;
pub mod plant;
pub mod proximity;
pub mod rigid_body;
pub mod rotor;
mod sensor_params;
pub mod sensors;
mod validate;
pub mod wind;

pub use layout::{MAX_ROTORS, MIN_ROTORS};
pub use params::{ParamsError, PlantParams};
pub use plant::{Plant, StepStatus, TruthState};
pub use rand_chacha::ChaCha8Rng;
pub use rigid_body::RigidBodyState;
pub use sensors::earth_field::{EarthField, EarthFieldError, GeoSite};
pub use sensors::{
    BaroConfig, BaroSample, GpsConfig, GpsFix, GpsSample, ImuConfig, ImuSample, MagConfig, MagSample, NoiseParams,
    SensorErrors, SensorFault, SensorReadings, SensorSample, SensorSuite, SensorSuiteConfig, SensorUnit,
};

/// Standard gravity used by plant and controller alike [m/s²] (docs/model.md §1).
pub const GRAVITY_M_S2: f64 = 9.81;

/// Default integration step [s] (1 kHz).
pub const DEFAULT_DT_S: f64 = 1e-3;

/// A ChaCha8 RNG seeded from `seed`; the one way this crate's users make the noise source.
pub fn rand_chacha_seed(seed: u64) -> ChaCha8Rng {
    use rand_chacha::rand_core::SeedableRng;
    ChaCha8Rng::seed_from_u64(seed)
}
