//! The sensor suite: IMU, GPS, barometer and magnetometer with injectable failures, read once per
//! plant tick (docs/model.md §10).
//!
//! Pure and deterministic: the suite owns one ChaCha8 stream per model and one per fault layer,
//! all from the seed given at construction (streams 1–10; the state sensor's generator is
//! stream 0), so the same seed and the same truth sequence give the same readings, and a fault on
//! one unit never changes what another unit reads. Everything is allocated in [`SensorSuite::new`];
//! [`SensorSuite::read`] allocates nothing.
//!
//! ```
//! use firmware_sim::{Plant, PlantParams, SensorSuite, SensorFault, SensorUnit, DEFAULT_DT_S};
//! let params = PlantParams::from_toml_str(include_str!("../../../airframes/quad_x.toml"), "quad_x").unwrap();
//! let home = firmware_sim::GeoSite::PX4_DEFAULT_HOME;
//! let mut sensors = SensorSuite::new(params.sensors, &home, 42).unwrap();
//! let plant = Plant::new(params);
//! sensors.set_fault(SensorUnit::Gps, SensorFault::Off);
//! let readings = sensors.read(&plant.truth());
//! assert!(readings.imu.is_some() && readings.gps.is_none());
//! ```

use super::baro::{BaroConfig, BaroModel, BaroSample};
use super::earth_field::{EarthFieldError, GeoSite};
use super::fault::{SensorFault, SensorUnit};
use super::fault_layer::FaultLayer;
use super::gauss::seeded_stream;
use super::gps::{GpsConfig, GpsModel, GpsSample};
use super::imu::{AxisReading, ImuConfig, ImuModel, ImuSample};
use super::mag::{MagConfig, MagModel, MagSample};
use crate::plant::TruthState;
use crate::DEFAULT_DT_S;

/// Configuration of every sensor of the suite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorSuiteConfig {
    /// Accelerometer and gyroscope.
    pub imu: ImuConfig,
    /// GPS receiver.
    pub gps: GpsConfig,
    /// Barometer.
    pub baro: BaroConfig,
    /// Magnetometer.
    pub mag: MagConfig,
}

impl SensorSuiteConfig {
    /// A small PX4 quadrotor's sensors as PX4 SITL simulates them (each model's `typical()`
    /// says where its values come from): the default.
    pub fn typical() -> Self {
        Self {
            imu: ImuConfig::typical(),
            gps: GpsConfig::typical(),
            baro: BaroConfig::typical(),
            mag: MagConfig::typical(),
        }
    }

    /// The same vehicle's real sensors: IMU biases, a receiver's wandering GPS error and a
    /// barometer under propeller wash ([`ImuConfig::hardware`], [`GpsConfig::hardware`],
    /// [`BaroConfig::hardware`]).
    pub fn hardware() -> Self {
        Self {
            imu: ImuConfig::hardware(),
            gps: GpsConfig::hardware(),
            baro: BaroConfig::hardware(),
            ..Self::typical()
        }
    }

    /// Every noise, bias, drift and latency zero: readings are exact functions of the truth.
    /// Rates, the magnetic field, the origin altitude and the GPS's reported figures stay typical.
    pub fn ideal() -> Self {
        Self {
            imu: ImuConfig::ideal(),
            gps: GpsConfig::ideal(),
            baro: BaroConfig::ideal(),
            mag: MagConfig::ideal(),
        }
    }
}

impl Default for SensorSuiteConfig {
    fn default() -> Self {
        Self::typical()
    }
}

/// What the sensors deliver at one plant tick; `None` for a sensor with nothing new.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorReadings {
    /// IMU sample; `None` only when neither half delivers.
    pub imu: Option<ImuSample>,
    /// GPS sample (10 Hz by default).
    pub gps: Option<GpsSample>,
    /// Barometer sample (50 Hz by default).
    pub baro: Option<BaroSample>,
    /// Magnetometer sample (50 Hz by default).
    pub mag: Option<MagSample>,
}

/// Random stream of each model and fault layer, from the suite's seed.
const STREAM_ACCEL: u64 = 1;
const STREAM_GYRO: u64 = 2;
const STREAM_GPS: u64 = 3;
const STREAM_BARO: u64 = 4;
const STREAM_MAG: u64 = 5;
/// Fault layers use 6 + the unit's MAVLink number (6–10).
const STREAM_FAULT_BASE: u64 = 6;

/// The simulated sensors of one vehicle. Owned next to the plant by the flight-controller side.
#[derive(Debug, Clone)]
pub struct SensorSuite {
    config: SensorSuiteConfig,
    imu: ImuModel,
    gps: GpsModel,
    baro: BaroModel,
    mag: MagModel,
    gyro_fault: FaultLayer<AxisReading>,
    accel_fault: FaultLayer<AxisReading>,
    gps_fault: FaultLayer<GpsSample>,
    baro_fault: FaultLayer<BaroSample>,
    mag_fault: FaultLayer<MagSample>,
}

impl SensorSuite {
    /// Healthy sensors at `home` (the magnetometer reads the Earth field there,
    /// [`super::MagConfig::field_at`]; the barometer's z = 0 is at its altitude unless the
    /// configuration fixes one) drawing from ChaCha8 streams of `seed`: turn-on biases and
    /// the GPS's initial wandering error are drawn here. Fails when the World Magnetic Model
    /// cannot give the field at `home`.
    pub fn new(config: SensorSuiteConfig, home: &GeoSite, seed: u64) -> Result<Self, EarthFieldError> {
        let mag_field = config.mag.field_at(home)?;
        let fault_rng = |unit: SensorUnit| seeded_stream(seed, STREAM_FAULT_BASE + u64::from(unit.failure_unit()));
        let imu_rate_hz = 1.0 / DEFAULT_DT_S;
        Ok(Self {
            config,
            imu: ImuModel::new(
                config.imu,
                seeded_stream(seed, STREAM_ACCEL),
                seeded_stream(seed, STREAM_GYRO),
            ),
            gps: GpsModel::new(config.gps, seeded_stream(seed, STREAM_GPS)),
            baro: BaroModel::new(
                config.baro,
                config.baro.origin_alt_m.unwrap_or(home.alt_m),
                seeded_stream(seed, STREAM_BARO),
            ),
            mag: MagModel::new(config.mag, &mag_field, seeded_stream(seed, STREAM_MAG)),
            gyro_fault: FaultLayer::new(
                SensorUnit::Gyro,
                imu_rate_hz,
                fault_rng(SensorUnit::Gyro),
                AxisReading::ZERO,
            ),
            accel_fault: FaultLayer::new(
                SensorUnit::Accel,
                imu_rate_hz,
                fault_rng(SensorUnit::Accel),
                AxisReading::ZERO,
            ),
            gps_fault: FaultLayer::new(
                SensorUnit::Gps,
                config.gps.rate_hz,
                fault_rng(SensorUnit::Gps),
                GpsSample::ZERO,
            ),
            baro_fault: FaultLayer::new(
                SensorUnit::Baro,
                config.baro.rate_hz,
                fault_rng(SensorUnit::Baro),
                BaroSample::ZERO,
            ),
            mag_fault: FaultLayer::new(
                SensorUnit::Mag,
                config.mag.rate_hz,
                fault_rng(SensorUnit::Mag),
                MagSample::ZERO,
            ),
        })
    }

    /// The readings of this plant tick; call once per tick, with time increasing. The IMU samples
    /// at every call, the other sensors on their own grids (docs/model.md §10.1).
    pub fn read(&mut self, truth: &TruthState) -> SensorReadings {
        let t = truth.t_s;
        let (accel, gyro) = self.imu.sample(truth);
        let accel = self.accel_fault.apply(t, Some(accel));
        let gyro = self.gyro_fault.apply(t, Some(gyro));
        let imu = (accel.is_some() || gyro.is_some()).then_some(ImuSample {
            t_s: t,
            accel_b: accel.map(|a| a.v_b),
            gyro_b: gyro.map(|g| g.v_b),
        });
        let gps = self.gps.read(truth);
        let baro = self.baro.read(truth);
        let mag = self.mag.read(truth);
        SensorReadings {
            imu,
            gps: self.gps_fault.apply(t, gps),
            baro: self.baro_fault.apply(t, baro),
            mag: self.mag_fault.apply(t, mag),
        }
    }

    /// Injects `fault` into `unit` (brought into range by [`SensorFault::sanitized`]); a fault
    /// other than the active one starts at the next [`Self::read`]. [`SensorFault::Ok`] repairs.
    pub fn set_fault(&mut self, unit: SensorUnit, fault: SensorFault) {
        match unit {
            SensorUnit::Gyro => self.gyro_fault.set(fault),
            SensorUnit::Accel => self.accel_fault.set(fault),
            SensorUnit::Mag => self.mag_fault.set(fault),
            SensorUnit::Baro => self.baro_fault.set(fault),
            SensorUnit::Gps => self.gps_fault.set(fault),
        }
    }

    /// The fault active on `unit`.
    pub fn fault(&self, unit: SensorUnit) -> SensorFault {
        match unit {
            SensorUnit::Gyro => self.gyro_fault.fault(),
            SensorUnit::Accel => self.accel_fault.fault(),
            SensorUnit::Mag => self.mag_fault.fault(),
            SensorUnit::Baro => self.baro_fault.fault(),
            SensorUnit::Gps => self.gps_fault.fault(),
        }
    }

    /// The configuration the suite was built with.
    pub fn config(&self) -> &SensorSuiteConfig {
        &self.config
    }

    /// The sensors' hidden errors right now, for logs and tests (never for the controller).
    pub fn errors(&self) -> SensorErrors {
        let (accel_bias_b, gyro_bias_b) = self.imu.biases();
        SensorErrors {
            accel_bias_b,
            gyro_bias_b,
            gps_wander_w: self.gps.wander_w(),
            baro_drift_m: self.baro.drift_m(),
        }
    }
}

/// The slowly varying errors inside the sensor models (truth, for logs and tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorErrors {
    /// Accelerometer bias, body FRD [m/s²].
    pub accel_bias_b: nalgebra::Vector3<f64>,
    /// Gyroscope bias, body FRD [rad/s].
    pub gyro_bias_b: nalgebra::Vector3<f64>,
    /// GPS wandering position error, NED [m].
    pub gps_wander_w: nalgebra::Vector3<f64>,
    /// Barometer altitude offset [m].
    pub baro_drift_m: f64,
}

#[cfg(test)]
#[path = "suite_tests.rs"]
mod tests;
