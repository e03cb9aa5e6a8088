//! The only seam between the flight controller and the simulated vehicle (`firmware_sim`).
//!
//! The plant parses the same airframe text with its own types; this module turns its sensor
//! samples into [`VehicleState`] (and the rest of the flight controller's inputs, [`Sensors`] and
//! [`EscReport`]) and
//! passes rotor commands and [`PlantChange`]s back. Nothing else in the flight controller names
//! `firmware_sim`. The plant is stepped in one place only: [`crate::lockstep::Lockstep::step`].

use firmware_sim::{
    rand_chacha_seed, ChaCha8Rng, EarthField, EarthFieldError, GeoSite, GpsFix, ParamsError, Plant, PlantParams,
    RigidBodyState, SensorReadings, SensorSuite, StepStatus,
};
use thiserror::Error;

use crate::airframe::AirframeSource;
use crate::control::VehicleState;
use crate::guidance::Home;
use crate::math::{UnitQuat, Vec3};
use crate::nav_filter::{BaroReading, GpsReading, ImuReading, MagReading};
use crate::params::WindParams;
use crate::sensor_failure::SensorFailure;

/// The plant refused the airframe, or the home.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SitlError {
    /// The airframe file's plant tables.
    #[error("plant: {0}")]
    Params(#[from] ParamsError),
    /// No Earth field at home: the World Magnetic Model covers heights from −1 km to 850 km.
    #[error("plant: the magnetometer's field at home: {0}")]
    EarthField(#[from] EarthFieldError),
}

/// `home` as the plant's place.
fn site(home: &Home) -> GeoSite {
    GeoSite {
        lat_deg: home.lat_deg,
        lon_deg: home.lon_deg,
        alt_m: home.alt_amsl_m,
    }
}

/// The World Magnetic Model's declination at `home` [rad] (east of true north positive), the
/// field the plant's magnetometer reads there unless the airframe file fixes it
/// (docs/model.md §10.5); `None` where the model gives none. What the navigation filter's
/// geo look-up finds (docs/navigation_filter.md §10, eq. (10.5)).
pub fn magnetic_declination_rad(home: &Home) -> Option<f64> {
    EarthField::at(&site(home)).ok().map(|f| f.declination_rad)
}

/// Plant step flags as the flight controller sees them.
pub type PlantStatus = StepStatus;

/// Which sensors the flight controller reads (docs/model.md §6, §10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SensorModel {
    /// The state sensor: the exact state plus the airframe's `[plant.noise]` (none by default),
    /// as the homework assumes. The navigation estimate is this reading.
    #[default]
    State,
    /// The sensor suite: IMU, GPS, barometer and magnetometer with their noise, biases, latency
    /// and failures; the navigation filter builds the estimate from them.
    Suite,
}

impl SensorModel {
    /// The name on the command line and in scenario files: `ideal` or `realistic`.
    pub fn name(self) -> &'static str {
        match self {
            Self::State => "ideal",
            Self::Suite => "realistic",
        }
    }

    /// The model named `name` (`ideal` or `realistic`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "ideal" => Some(Self::State),
            "realistic" => Some(Self::Suite),
            _ => None,
        }
    }
}

/// What the plant's sensors report at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensors {
    /// The state sensor's reading ([`SensorModel::State`]); `None` with the sensor suite.
    pub state: Option<VehicleState>,
    /// Specific force (accelerometer), body FRD [m/s²]: the state sensor's, or the IMU's latest.
    pub accel_b: Vec3,
    /// The IMU sample of this tick (sensor suite; `None` when both halves failed).
    pub imu: Option<ImuReading>,
    /// A GPS sample, when one arrived this tick.
    pub gps: Option<GpsReading>,
    /// A barometer sample, when one arrived this tick.
    pub baro: Option<BaroReading>,
    /// A magnetometer sample, when one arrived this tick.
    pub mag: Option<MagReading>,
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
    /// Fail (or restore) a sensor of the suite.
    Sensor(SensorFailure),
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

/// The simulated vehicle with its own seeded RNG and its sensors.
#[derive(Debug, Clone)]
pub struct SimPlant {
    plant: Plant,
    rng: ChaCha8Rng,
    accel_b: Vec3,
    model: SensorModel,
    suite: SensorSuite,
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
    /// Builds the plant at PX4's default home ([`Home::default`]) from an airframe text with
    /// sensor noise seeded by `seed`.
    pub fn from_source(src: &AirframeSource, seed: u64) -> Result<Self, SitlError> {
        Self::at_home(src, &Home::default(), seed)
    }

    /// Builds the plant at `home` (its magnetometer reads the World Magnetic Model's field
    /// there; docs/model.md §10.5) from an airframe text with sensor noise seeded by `seed`.
    pub fn at_home(src: &AirframeSource, home: &Home, seed: u64) -> Result<Self, SitlError> {
        let params = PlantParams::from_toml_str(&src.text, &src.origin)?;
        let suite = SensorSuite::new(params.sensors, &site(home), seed)?;
        let mut plant = Plant::new(params);
        plant.seed_wind(seed);
        Ok(Self {
            plant,
            rng: rand_chacha_seed(seed),
            accel_b: Vec3::zeros(),
            model: SensorModel::State,
            suite,
        })
    }

    /// The same plant read through `model`'s sensors.
    pub fn with_sensor_model(mut self, model: SensorModel) -> Self {
        self.model = model;
        self
    }

    /// Which sensors the flight controller reads.
    pub fn sensor_model(&self) -> SensorModel {
        self.model
    }

    /// Start-up warnings of the plant configuration.
    pub fn warnings(&self) -> Vec<String> {
        self.plant.params().warnings()
    }

    /// The state sensor: the exact state with the airframe's noise.
    fn sense_state(&mut self) -> VehicleState {
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

    /// One tick's readings for the flight controller: the state sensor's, or the suite's
    /// samples converted to the flight controller's types.
    pub fn read_sensors(&mut self) -> Sensors {
        match self.model {
            SensorModel::State => {
                let state = self.sense_state();
                Sensors {
                    state: Some(state),
                    accel_b: self.accel_b,
                    imu: None,
                    gps: None,
                    baro: None,
                    mag: None,
                }
            }
            SensorModel::Suite => {
                let readings = self.suite.read(&self.plant.truth());
                self.convert(&readings)
            }
        }
    }

    /// The suite's samples as the flight controller reads them.
    fn convert(&mut self, r: &SensorReadings) -> Sensors {
        let imu = r.imu.and_then(|s| {
            Some(ImuReading {
                t_s: s.t_s,
                accel_b: s.accel_b?,
                gyro_b: s.gyro_b?,
            })
        });
        if let Some(a) = r.imu.and_then(|s| s.accel_b) {
            self.accel_b = a;
        }
        Sensors {
            state: None,
            accel_b: self.accel_b,
            imu,
            gps: r.gps.map(|g| GpsReading {
                t_s: g.t_s,
                pos_w: g.pos_w,
                vel_w: g.vel_w,
                h_acc_m: g.h_acc_m,
                v_acc_m: g.v_acc_m,
                speed_acc_m_s: g.speed_acc_m_s,
                fix_3d: g.fix == GpsFix::Fix3d,
                satellites: g.satellites,
            }),
            baro: r.baro.map(|b| BaroReading {
                t_s: b.t_s,
                pressure_pa: b.pressure_pa,
                temperature_c: b.temperature_c,
            }),
            mag: r.mag.map(|m| MagReading {
                t_s: m.t_s,
                field_b: m.field_b,
            }),
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
            PlantChange::Sensor(failure) => {
                let unit = firmware_sim::SensorUnit::from_failure_unit(u32::from(failure.unit.failure_unit()));
                let fault = firmware_sim::SensorFault::from_failure_type(u32::from(failure.kind.failure_type()));
                if let (Some(unit), Some(fault)) = (unit, fault) {
                    self.suite.set_fault(unit, fault);
                }
            }
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

    /// The exact state now, as a vehicle state: where a headless run starts its navigation
    /// filter (never a controller input).
    pub fn true_state(&self) -> VehicleState {
        let t = self.plant.truth();
        VehicleState {
            t_s: t.t_s,
            pos_w: t.body.pos_w,
            vel_w: t.body.vel_w,
            r_wb: t.body.q_wb.to_rotation_matrix().into_inner(),
            omega_b: t.body.omega_b,
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
