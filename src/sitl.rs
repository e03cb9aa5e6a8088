//! The only seam between the flight controller and the simulated vehicle (`firmware_sim`).
//!
//! The plant parses the same airframe text with its own types; this module turns its sensor
//! samples into [`VehicleState`] and passes rotor commands back. Nothing else in the flight
//! controller names `firmware_sim`.

use firmware_sim::{rand_chacha_seed, ChaCha8Rng, ParamsError, Plant, PlantParams, StepStatus};
use thiserror::Error;

use crate::airframe::AirframeSource;
use crate::control::VehicleState;
use crate::math::Vec3;

/// The plant refused the airframe.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("plant: {0}")]
pub struct SitlError(#[from] pub ParamsError);

/// Plant step flags as the flight controller sees them.
pub type PlantStatus = StepStatus;

/// The simulated vehicle with its own seeded RNG.
#[derive(Debug, Clone)]
pub struct SimPlant {
    plant: Plant,
    rng: ChaCha8Rng,
}

/// Exact plant quantities for logs (never fed to the controller).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantTruth {
    /// True position, world NED [m].
    pub pos_w: Vec3,
    /// Resting on the ground.
    pub on_ground: bool,
}

impl SimPlant {
    /// Builds the plant from an airframe text with sensor noise seeded by `seed`.
    pub fn from_source(src: &AirframeSource, seed: u64) -> Result<Self, SitlError> {
        let params = PlantParams::from_toml_str(&src.text, &src.origin)?;
        Ok(Self {
            plant: Plant::new(params),
            rng: rand_chacha_seed(seed),
        })
    }

    /// Start-up warnings of the plant configuration.
    pub fn warnings(&self) -> Vec<String> {
        self.plant.params().warnings()
    }

    /// Sensor sample as the controller's state.
    pub fn sense(&mut self) -> VehicleState {
        let s = self.plant.sense(&mut self.rng);
        VehicleState {
            t_s: s.t_s,
            pos_w: s.pos_w,
            vel_w: s.vel_w,
            r_wb: s.q_wb.to_rotation_matrix().into_inner(),
            omega_b: s.omega_b,
        }
    }

    /// Advances the plant by `dt_s` [s] with rotor speeds `omega_rad_s` [rad/s].
    pub fn step(&mut self, omega_rad_s: &[f64], dt_s: f64) -> PlantStatus {
        self.plant.step(omega_rad_s, dt_s)
    }

    /// Current true motor speeds [rad/s].
    pub fn motor_speeds(&self) -> &[f64] {
        self.plant.motor_speeds()
    }

    /// Exact state for logs.
    pub fn truth(&self) -> PlantTruth {
        let t = self.plant.truth();
        PlantTruth {
            pos_w: t.body.pos_w,
            on_ground: t.on_ground,
        }
    }
}
