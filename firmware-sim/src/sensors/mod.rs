//! What the flight controller measures (docs/model.md §6, §10).
//!
//! Two kinds of sensor live here:
//!
//! - the **state sensor** ([`NoiseParams`], [`SensorSample`], `state.rs`): the exact state with
//!   optional white noise, what the homework scenarios fly on (docs/model.md §6);
//! - the **sensor suite** ([`SensorSuite`], `suite.rs`): an IMU at every plant tick, GPS,
//!   barometer and magnetometer at their own rates, with bias, drift, latency and injectable
//!   failures ([`SensorFault`]) (docs/model.md §10).
//!
//! # Layout
//!
//! - `state.rs`: the state sensor.
//! - `gauss.rs`: Box–Muller normals and uniforms from ChaCha8 streams, shared by every model.
//! - [`earth_field`]: the World Magnetic Model's field at a place ([`earth_field::EarthField`]),
//!   the field the magnetometer reads.
//! - [`imu`], [`gps`], [`baro`], [`mag`]: one model per sensor with its configuration, sample
//!   type and the meaning of its `Wrong` and `Garbage` faults.
//! - [`fault`]: [`SensorUnit`], [`SensorFault`]; `fault_layer.rs` applies a fault to a model's
//!   samples.
//! - `suite.rs`: [`SensorSuite`], [`SensorSuiteConfig`], [`SensorReadings`].
//! - `ring.rs`, `schedule.rs`: a fixed ring buffer and the k / rate sampling grid.

pub mod baro;
pub mod earth_field;
pub mod fault;
mod fault_layer;
pub(crate) mod gauss;
pub mod gps;
pub mod imu;
pub mod mag;
mod ring;
mod schedule;
mod state;
mod suite;
#[cfg(test)]
mod test_support;

pub use baro::{BaroConfig, BaroSample};
pub use fault::{SensorFault, SensorUnit, MAX_EXTRA_DELAY_S};
pub use gps::{GpsConfig, GpsFix, GpsSample, MAX_GPS_LATENCY_S};
pub use imu::{ImuConfig, ImuSample};
pub use mag::{MagConfig, MagSample};
pub use state::{NoiseParams, SensorSample};
pub use suite::{SensorErrors, SensorReadings, SensorSuite, SensorSuiteConfig};
