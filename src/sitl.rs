//! The only seam between the flight controller and the simulated vehicle (`firmware_sim`).
//!
//! The plant parses the same airframe text with its own types; this module turns its sensor
//! samples into [`VehicleState`] (and the rest of the flight controller's inputs, [`Sensors`] and
//! [`EscReport`]) and
//! passes rotor commands and [`PlantChange`]s back. Nothing else in the flight controller names
//! `firmware_sim`. The plant is stepped in one place only: [`crate::lockstep::Lockstep::step`].

use firmware_sim::{rand_chacha_seed, ChaCha8Rng, ParamsError, Plant, PlantParams, RigidBodyState, StepStatus};
use thiserror::Error;

use crate::airframe::AirframeSource;
use crate::control::VehicleState;
use crate::math::{UnitQuat, Vec3};
use crate::params::WindParams;

/// The plant refused the airframe.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("plant: {0}")]
pub struct SitlError(#[from] pub ParamsError);

/// Plant step flags as the flight controller sees them.
pub type PlantStatus = StepStatus;

/// What the plant's sensors report at one tick: the sensed state and the accelerometer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensors {
    /// Sensed state (position, velocity, attitude, body rates).
    pub state: VehicleState,
    /// Specific force (accelerometer), body FRD [m/s²].
    pub accel_b: Vec3,
}

/// What the ESCs and the battery's current sensor report, read from the plant on demand (only
/// the flight controller reads them).
#[derive(Debug, Clone, Copy)]
pub struct EscReport<'a> {
    plant: &'a SimPlant,
}

impl EscReport<'_> {
    /// Which rotors have failed (one entry per rotor).
    pub fn failed_rotors(&self) -> &[bool] {
        self.plant.failed_rotors()
    }

    /// Electrical power the rotors draw [W]: shaft power Σ c_q·|ω_i|³ of the actual motor
    /// speeds over a motor-and-ESC efficiency of 0.7.
    pub fn power_w(&self) -> f64 {
        self.plant.electrical_power_w()
    }
}

/// What a flight-controller decision changes in the simulated hardware.
#[derive(Debug, Clone, PartialEq)]
pub enum PlantChange {
    /// Stop (`failed`) or restore the rotors `rotors` (0-based indices).
    Rotors {
        /// Rotor indices, 0-based.
        rotors: std::ops::Range<usize>,
        /// Stop (`true`) or restore.
        failed: bool,
    },
    /// Set the mean wind's horizontal components and the turbulence (gusts and the vertical
    /// mean wind of the airframe file stay).
    Wind(WindParams),
    /// Switch the plant's ground and ceiling effects (contact stays).
    ProximityEffects {
        /// Ground effect on.
        ground: bool,
        /// Ceiling effect on.
        ceiling: bool,
    },
}

/// The simulated vehicle with its own seeded RNG.
#[derive(Debug, Clone)]
pub struct SimPlant {
    plant: Plant,
    rng: ChaCha8Rng,
    accel_b: Vec3,
}

/// Exact plant quantities for logs (never fed to the controller).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantTruth {
    /// True position, world NED [m].
    pub pos_w: Vec3,
    /// True velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// True attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
    /// True body rates, FRD [rad/s].
    pub omega_b: Vec3,
    /// Resting on the ground.
    pub on_ground: bool,
    /// Scripted external force over the last step, world NED [N].
    pub external_force_w: Vec3,
    /// Scripted external torque over the last step, body FRD [N·m].
    pub external_torque_b: Vec3,
    /// Acceleration over the last step, world NED [m/s²].
    pub accel_w: Vec3,
    /// The air's velocity at the vehicle, world NED [m/s].
    pub wind_w: Vec3,
    /// Aerodynamic drag, wind included, world NED [N] (docs/model.md §5.1, eq. (5.2)).
    pub drag_force_w: Vec3,
}

impl PlantTruth {
    /// The whole external force a wrench estimator should recover: the scripted force plus
    /// the drag, wind included (world NED [N]).
    pub fn external_and_drag_force_w(&self) -> Vec3 {
        self.external_force_w + self.drag_force_w
    }

    /// The truth of a vehicle resting in `state` in calm air (tests).
    #[cfg(test)]
    pub(crate) fn at_rest(state: &VehicleState) -> Self {
        Self {
            pos_w: state.pos_w,
            vel_w: state.vel_w,
            q_wb: UnitQuat::from_matrix(&state.r_wb),
            omega_b: state.omega_b,
            on_ground: true,
            external_force_w: Vec3::zeros(),
            external_torque_b: Vec3::zeros(),
            accel_w: Vec3::zeros(),
            wind_w: Vec3::zeros(),
            drag_force_w: Vec3::zeros(),
        }
    }
}

impl SimPlant {
    /// Builds the plant from an airframe text with sensor noise seeded by `seed`.
    pub fn from_source(src: &AirframeSource, seed: u64) -> Result<Self, SitlError> {
        let params = PlantParams::from_toml_str(&src.text, &src.origin)?;
        let mut plant = Plant::new(params);
        plant.seed_wind(seed);
        Ok(Self {
            plant,
            rng: rand_chacha_seed(seed),
            accel_b: Vec3::zeros(),
        })
    }

    /// Start-up warnings of the plant configuration.
    pub fn warnings(&self) -> Vec<String> {
        self.plant.params().warnings()
    }

    /// Sensor sample as the controller's state.
    pub fn sense(&mut self) -> VehicleState {
        let s = self.plant.sense(&mut self.rng);
        self.accel_b = s.accel_b;
        VehicleState {
            t_s: s.t_s,
            pos_w: s.pos_w,
            vel_w: s.vel_w,
            r_wb: s.q_wb.to_rotation_matrix().into_inner(),
            omega_b: s.omega_b,
        }
    }

    /// One sensor reading for the flight controller ([`Self::sense`] and the accelerometer).
    pub fn read_sensors(&mut self) -> Sensors {
        let state = self.sense();
        Sensors {
            state,
            accel_b: self.accel_b,
        }
    }

    /// The ESC report and the battery's current sensor.
    pub fn esc(&self) -> EscReport<'_> {
        EscReport { plant: self }
    }

    /// Carries out `change`.
    pub fn apply(&mut self, change: &PlantChange) {
        match change {
            PlantChange::Rotors { rotors, failed } => {
                for i in rotors.clone() {
                    self.plant.set_rotor_failed(i, *failed);
                }
            }
            PlantChange::ProximityEffects { ground, ceiling } => self.plant.set_proximity_effects(*ground, *ceiling),
            PlantChange::Wind(w) => {
                let mut wind = self.plant.wind().clone();
                wind.mean_w.x = w.north_m_s;
                wind.mean_w.y = w.east_m_s;
                wind.turbulence_w20_m_s = Some(w.turbulence_w20_m_s).filter(|w20| *w20 > 0.0);
                self.plant.set_wind(wind);
            }
        }
    }

    /// Which rotors have failed, as the ESCs report it.
    pub fn failed_rotors(&self) -> &[bool] {
        self.plant.failed_rotors()
    }

    /// [`EscReport::power_w`].
    fn electrical_power_w(&self) -> f64 {
        const EFFICIENCY: f64 = 0.7;
        let c_q = self.plant.params().rotor.c_q;
        self.plant
            .motor_speeds()
            .iter()
            .map(|w| c_q * w.abs().powi(3))
            .sum::<f64>()
            / EFFICIENCY
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
            vel_w: t.body.vel_w,
            q_wb: t.body.q_wb,
            omega_b: t.body.omega_b,
            on_ground: t.on_ground,
            external_force_w: t.external_force_w,
            external_torque_b: t.external_torque_b,
            accel_w: t.accel_w,
            wind_w: t.wind_w,
            drag_force_w: t.drag_force_w,
        }
    }

    /// True mass of the simulated vehicle [kg] (for reports, never for the controller).
    pub fn true_mass_kg(&self) -> f64 {
        self.plant.params().mass_kg
    }

    /// Places the vehicle: position `pos_w` [m] (`None` keeps the file's start), velocity
    /// `vel_w` [m/s], attitude `q_wb`, body rates `omega_b` [rad/s]; with `motors_at_hover` every
    /// motor starts at the speed that holds the true weight.
    pub fn set_initial_state(
        &mut self,
        pos_w: Option<Vec3>,
        vel_w: Vec3,
        q_wb: UnitQuat,
        omega_b: Vec3,
        motors_at_hover: bool,
    ) {
        let current = self.plant.truth().body;
        self.plant.set_body_state(RigidBodyState {
            pos_w: pos_w.unwrap_or(current.pos_w),
            vel_w,
            q_wb,
            omega_b,
        });
        if motors_at_hover {
            let hover = self.plant.params().hover_speed_rad_s();
            let speeds = vec![hover; self.plant.motor_speeds().len()];
            self.plant.set_motor_speeds(&speeds);
        }
    }
}
