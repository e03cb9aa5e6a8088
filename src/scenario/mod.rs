//! Scenario files for headless runs (`rotorpilot sim SCENARIO.toml --out DIR`): airframe with
//! plant mismatch and disturbances, initial state, controller, estimator, trajectory and rotor
//! failures, validated into a [`Scenario`]. Pure apart from reading the airframe file it names.
//!
//! ```toml
//! name = "hover"
//! duration = 5.0                      # [s]
//! [airframe]
//! preset = "fsr_quad"                 # or path = "my_airframe.toml" (relative to this file)
//! overrides = { vehicle = { mass = 1.7 }, fc = { mass = 1.5 } }   # true 1.7 kg, believed 1.5 kg
//! [initial]
//! position = [0.0, 0.0, -1.0]         # [m] NED; omit to start on the ground
//! [controller]
//! kind = "geometric"                  # geometric | hierarchical | passivity
//! compensation = true                 # subtract the estimated wrench
//! [estimator]
//! order = 1
//! ripple_db = 3.0                     # [dB]
//! wp = 2.0                            # [rad/s]
//! [trajectory]
//! kind = "hover"
//! position = [0.0, 0.0, -1.0]
//! [sensors]
//! model = "ideal"                     # the exact state (default) | "realistic": IMU, GPS, baro,
//!                                     # mag through the navigation filter
//! [[sensor_failure]]                  # optional, repeatable; realistic sensors only
//! sensor = "gps"                      # gyro | accel | mag | baro | gps
//! failure = "off"                     # ok | off | stuck | garbage | wrong | slow | delayed | intermittent
//! at = 20.0                           # [s] simulated time
//! [[rotor_failure]]                   # optional, repeatable
//! rotor = 2                           # 1-based
//! at = 3.0                            # [s] simulated time
//! ```
//!
//! With `[autopilot]` the flight controller flies the trajectory in OFFBOARD (battery, failsafes
//! and rotor-failure reactions included); gains, compensation and estimator are then its `RP_*`
//! parameters, so `[controller]` names the law only and `[estimator]` is refused:
//!
//! ```toml
//! [autopilot]
//! params = { BAT1_CAPACITY = 300, COM_LOW_BAT_ACT = 3 }   # set first (PX4 / RP_ names)
//! ```

pub mod estimate_stats;
mod merge;
mod spec;
pub mod summary;

use std::path::Path;

use thiserror::Error;

use crate::airframe::{Airframe, AirframeSource};
use crate::control::{ControllerGains, ControllerKind, DesiredRateMode};
use crate::flight::{vehicle_model, CoreError, FlightController, FlightCore};
use crate::guidance::trajectory::Trajectory;
use crate::guidance::Home;
use crate::lockstep::{FailureSchedule, ScheduledFailure, ScheduledSensorFailure};
use crate::math::{UnitQuat, Vec3};
use crate::sitl::SensorModel;
use crate::wrench_estimator::{ChebyshevDesign, WrenchObserver};

pub use merge::merge_tables;

/// A refused scenario: which file, which field, and why.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{origin}: {}{reason}", if field.is_empty() { String::new() } else { format!("{field}: ") })]
pub struct ScenarioError {
    /// Scenario file.
    pub origin: String,
    /// Dotted field path (empty when the whole file is at fault).
    pub field: String,
    /// What is wrong.
    pub reason: String,
}

/// The vehicle's state at t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialCondition {
    /// Position, world NED [m]; `None` rests on the ground.
    pub pos_w: Option<Vec3>,
    /// Velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Attitude body → world.
    pub q_wb: UnitQuat,
    /// Body rates, FRD [rad/s].
    pub omega_b: Vec3,
    /// Motors start at hover speed instead of stopped.
    pub motors_at_hover: bool,
}

/// Wrench-estimator settings.
#[derive(Debug, Clone, PartialEq)]
pub struct EstimatorSettings {
    /// Chebyshev design the gains came from, if any.
    pub design: Option<ChebyshevDesign>,
    /// K_1 … K_r [1/s].
    pub gains: Vec<f64>,
}

/// A validated scenario.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Name (file stem if not given).
    pub name: String,
    /// Free text.
    pub description: String,
    /// Simulated duration [s].
    pub duration_s: f64,
    /// Control and integration step [s].
    pub dt_s: f64,
    /// Sensor-noise seed.
    pub seed: u64,
    /// Airframe text after the overrides, for the plant.
    pub airframe_source: AirframeSource,
    /// The FC's view of the airframe.
    pub airframe: Airframe,
    /// Initial state.
    pub initial: InitialCondition,
    /// Control law.
    pub controller: ControllerKind,
    /// Compensation of the estimated wrench.
    pub compensation: bool,
    /// How the geometric law obtains ω_{b,d}.
    pub desired_rate: DesiredRateMode,
    /// Controller gains.
    pub gains: ControllerGains,
    /// Estimator, when on.
    pub estimator: Option<EstimatorSettings>,
    /// Reference trajectory.
    pub trajectory: Trajectory,
    /// Rotors that stop and sensors that fail during the run (`[[rotor_failure]]`,
    /// `[[sensor_failure]]`).
    pub rotor_failures: FailureSchedule,
    /// Which sensors the flight controller reads (`[sensors] model`, ideal by default).
    pub sensors: SensorModel,
    /// `[autopilot]`: the flight controller flies the trajectory in OFFBOARD, with these
    /// parameters set first (name, value); `None`: the bare control law follows it.
    pub autopilot: Option<Vec<(String, f64)>>,
}

impl Scenario {
    /// Reads and validates a scenario file.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError {
            origin: origin.clone(),
            field: String::new(),
            reason: format!("cannot read the file: {e}"),
        })?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Self::from_toml_str(&text, &origin, &stem, path.parent().unwrap_or(Path::new(".")))
    }

    /// Checks that `text` has a scenario file's fields and value types only (unknown fields
    /// refused with the closest name, the line given), without checking values or reading the
    /// airframe: what a sweep checks of each axis before flying (docs/sweep.md §4).
    pub fn check_fields(text: &str, origin: &str) -> Result<(), ScenarioError> {
        toml::from_str::<spec::ScenarioFile>(text).map(|_| ()).map_err(|e| {
            let (field, reason) = crate::suggest::toml_error(text, &e);
            ScenarioError {
                origin: origin.to_string(),
                field,
                reason,
            }
        })
    }

    /// Parses scenario `text`; `origin` names it in errors, `default_name` is used when the
    /// file has no `name`, `base_dir` resolves a relative airframe path.
    pub fn from_toml_str(text: &str, origin: &str, default_name: &str, base_dir: &Path) -> Result<Self, ScenarioError> {
        let err = |field: &str, reason: String| ScenarioError {
            origin: origin.to_string(),
            field: field.to_string(),
            reason,
        };
        let file: spec::ScenarioFile = toml::from_str(text).map_err(|e| {
            let (place, reason) = crate::suggest::toml_error(text, &e);
            err(&place, reason)
        })?;
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(file.duration) && file.duration <= 1e6) {
            return Err(err(
                "duration",
                format!("must be a positive number of seconds up to 1e6, got {}", file.duration),
            ));
        }
        let dt_s = file.dt.unwrap_or(1e-3);
        if !(positive(dt_s) && dt_s <= 0.01) {
            return Err(err("dt", format!("must be in (0, 0.01] s, got {dt_s}")));
        }
        let airframe_source = airframe_source(&file.airframe, base_dir).map_err(|(f, r)| err(&f, r))?;
        let airframe = Airframe::from_source(&airframe_source).map_err(|e| err("airframe", e.to_string()))?;
        let core = FlightCore::for_airframe(&airframe, file.controller.kind, dt_s)
            .map_err(|e| err("airframe", e.to_string()))?;
        let model = vehicle_model(&airframe, core.allocator());
        let gains = merged_gains(ControllerGains::for_vehicle(&model), file.controller.gains.as_ref())
            .map_err(|r| err("controller.gains", r))?;
        let estimator = match &file.estimator {
            Some(e) if e.enabled.unwrap_or(true) => Some(estimator(e, dt_s).map_err(|(f, r)| err(&f, r))?),
            _ => None,
        };
        let initial =
            initial(file.initial.as_ref().unwrap_or(&spec::InitialSpec::default())).map_err(|(f, r)| err(&f, r))?;
        let trajectory = file.trajectory.build().map_err(|e| err("trajectory", e.to_string()))?;
        let mut rotor_failures = FailureSchedule::new(core.allocator().rotor_count());
        for (k, f) in file.rotor_failure.iter().flatten().enumerate() {
            let failure = ScheduledFailure {
                rotor: f.rotor,
                at_s: f.at,
            };
            rotor_failures
                .schedule(failure)
                .map_err(|r| err(&format!("rotor_failure[{k}]"), r))?;
        }
        let sensors = match &file.sensors {
            Some(s) => SensorModel::from_name(&s.model).ok_or_else(|| {
                err(
                    "sensors.model",
                    format!("unknown model \"{}\"; expected \"ideal\" or \"realistic\"", s.model),
                )
            })?,
            None => SensorModel::State,
        };
        for (k, f) in file.sensor_failure.iter().flatten().enumerate() {
            let field = format!("sensor_failure[{k}]");
            if sensors != SensorModel::Suite {
                return Err(err(
                    &field,
                    "sensor failures need [sensors] model = \"realistic\"".into(),
                ));
            }
            let failure = format!("{}:{}@{}", f.sensor, f.failure, f.at)
                .parse::<ScheduledSensorFailure>()
                .map_err(|r| err(&field, r.trim_start_matches("--fail ").to_string()))?;
            rotor_failures.schedule_sensor(failure);
        }
        let autopilot = match &file.autopilot {
            Some(a) => Some(autopilot_params(&file, a).map_err(|(f, r)| err(&f, r))?),
            None => None,
        };
        let scenario = Self {
            name: file.name.unwrap_or_else(|| default_name.to_string()),
            description: file.description.unwrap_or_default(),
            duration_s: file.duration,
            dt_s,
            seed: file.seed.unwrap_or(0),
            airframe_source,
            airframe,
            initial,
            controller: file.controller.kind,
            compensation: file.controller.compensation.unwrap_or(false),
            desired_rate: file.controller.desired_rate.unwrap_or_default(),
            gains,
            estimator,
            trajectory,
            rotor_failures,
            sensors,
            autopilot,
        };
        scenario.flight_controller().map_err(|(f, r)| err(&f, r))?;
        Ok(scenario)
    }

    /// The flight controller of an `[autopilot]` scenario, its parameters set (`None` for a
    /// bare control law); a refused parameter is named with its field.
    pub fn flight_controller(&self) -> Result<Option<FlightController>, (String, String)> {
        let Some(params) = &self.autopilot else {
            return Ok(None);
        };
        let mut fc = FlightController::new(&self.airframe, self.controller, Home::default(), self.dt_s)
            .map_err(|e| ("airframe".to_string(), e.to_string()))?;
        for (name, value) in params {
            fc.set_param(name, *value)
                .answer
                .map_err(|e| (format!("autopilot.params.{name}"), e.to_string()))?;
        }
        Ok(Some(fc))
    }

    /// The flight core this scenario flies.
    pub fn flight_core(&self) -> Result<FlightCore, CoreError> {
        let mut core = FlightCore::for_airframe(&self.airframe, self.controller, self.dt_s)?;
        core.controller.set_gains(self.gains)?;
        core.controller.set_compensation(self.compensation);
        core.controller.set_desired_rate_mode(self.desired_rate, self.dt_s);
        if let Some(e) = &self.estimator {
            let observer = WrenchObserver::new(
                self.airframe.mass_kg,
                self.airframe.inertia_kg_m2,
                e.gains.clone(),
                self.dt_s,
            )
            .map_err(|e| CoreError::Controller(crate::control::ControllerError::Gains(e.to_string())))?;
            core.set_observer(Some(observer));
        }
        Ok(core)
    }
}

/// The parameters of `[autopilot]`, by name; the law's gains, compensation and estimator are
/// then parameters too (RP_*), so `[controller]` may only name the law and `[estimator]` is
/// refused; the vehicle boots resting on the ground, so `[initial]` is refused too.
fn autopilot_params(
    file: &spec::ScenarioFile,
    a: &spec::AutopilotSpec,
) -> Result<Vec<(String, f64)>, (String, String)> {
    let c = &file.controller;
    let by_params = |field: &str| {
        Err((
            field.to_string(),
            "with [autopilot] set it by its parameter (RP_*) in autopilot.params".to_string(),
        ))
    };
    if c.gains.is_some() || c.compensation.is_some() || c.desired_rate.is_some() {
        return by_params("controller");
    }
    if file.estimator.is_some() {
        return by_params("estimator");
    }
    if file.initial.is_some() {
        // The land detector takes the ground to be where the vehicle rested at boot.
        return Err((
            "initial".into(),
            "with [autopilot] the vehicle starts resting on the ground, as a flight controller boots".into(),
        ));
    }
    let mut params = Vec::new();
    for (name, value) in a.params.iter().flatten() {
        let v = match value {
            toml::Value::Integer(i) => *i as f64,
            toml::Value::Float(x) => *x,
            other => {
                return Err((
                    format!("autopilot.params.{name}"),
                    format!("must be a number, got {other}"),
                ))
            }
        };
        params.push((name.clone(), v));
    }
    Ok(params)
}

/// The airframe text with `[airframe.overrides]` merged in.
fn airframe_source(spec: &spec::AirframeSpec, base_dir: &Path) -> Result<AirframeSource, (String, String)> {
    let name = match (&spec.preset, &spec.path) {
        (Some(p), None) => p.clone(),
        (None, Some(p)) => base_dir.join(p).display().to_string(),
        _ => return Err(("airframe".into(), "give exactly one of `preset` or `path`".into())),
    };
    let src = AirframeSource::resolve(&name).map_err(|e| ("airframe".to_string(), e.to_string()))?;
    let Some(over) = &spec.overrides else {
        return Ok(src);
    };
    let mut table: toml::Table =
        toml::from_str(&src.text).map_err(|e| ("airframe".to_string(), format!("{}: {e}", src.origin)))?;
    merge_tables(&mut table, over);
    let text = toml::to_string(&table).map_err(|e| ("airframe.overrides".to_string(), e.to_string()))?;
    Ok(AirframeSource {
        origin: format!("{} with scenario overrides", src.origin),
        text,
    })
}

/// Default gains with the file's partial table merged over them.
fn merged_gains(defaults: ControllerGains, over: Option<&toml::Table>) -> Result<ControllerGains, String> {
    let Some(over) = over else {
        return Ok(defaults);
    };
    let mut table = toml::Table::try_from(defaults).map_err(|e| e.to_string())?;
    merge_tables(&mut table, over);
    let gains: ControllerGains = table.try_into().map_err(|e: toml::de::Error| e.message().to_string())?;
    gains.validate()?;
    Ok(gains)
}

fn estimator(e: &spec::EstimatorSpec, dt_s: f64) -> Result<EstimatorSettings, (String, String)> {
    if let Some(gains) = &e.gains {
        if e.order.is_some() || e.wp.is_some() || e.ripple_db.is_some() {
            return Err((
                "estimator".into(),
                "give either `gains` or `order`/`ripple_db`/`wp`, not both".into(),
            ));
        }
        if gains.is_empty() || gains.iter().any(|k| !(k.is_finite() && *k > 0.0)) {
            return Err((
                "estimator.gains".into(),
                format!("must be 1 to 20 positive numbers, got {gains:?}"),
            ));
        }
        return Ok(EstimatorSettings {
            design: None,
            gains: gains.clone(),
        });
    }
    let (Some(order), Some(wp)) = (e.order, e.wp) else {
        return Err((
            "estimator".into(),
            "needs `order` and `wp` (and optionally `ripple_db`, default 3 dB), or `gains`".into(),
        ));
    };
    let design = ChebyshevDesign {
        order,
        ripple_db: e.ripple_db.unwrap_or(3.0),
        passband_rad_s: wp,
    };
    let gains = design
        .gains(dt_s)
        .map_err(|err| ("estimator".to_string(), err.to_string()))?;
    Ok(EstimatorSettings {
        design: Some(design),
        gains,
    })
}

fn initial(i: &spec::InitialSpec) -> Result<InitialCondition, (String, String)> {
    let finite = |name: &str, v: &[f64]| {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err((format!("initial.{name}"), format!("must be finite numbers, got {v:?}")))
        }
    };
    let v3 = |name: &str, v: Option<[f64; 3]>| -> Result<Option<Vec3>, (String, String)> {
        match v {
            Some(a) => finite(name, &a).map(|_| Some(Vec3::from(a))),
            None => Ok(None),
        }
    };
    let pos_w = v3("position", i.position)?;
    let vel_w = v3("velocity", i.velocity)?.unwrap_or_default();
    let omega_b = v3("rates", i.rates)?.unwrap_or_default().map(f64::to_radians);
    let q_wb = match (i.quaternion, v3("attitude", i.attitude)?) {
        (Some(q), _) => {
            finite("quaternion", &q)?;
            let quat = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
            if (quat.norm() - 1.0).abs() > 1e-6 {
                return Err((
                    "initial.quaternion".into(),
                    format!("must have unit norm, got {}", quat.norm()),
                ));
            }
            UnitQuat::new_unchecked(quat)
        }
        (None, Some(a)) => UnitQuat::from_euler_angles(a.x.to_radians(), a.y.to_radians(), a.z.to_radians()),
        (None, None) => UnitQuat::identity(),
    };
    Ok(InitialCondition {
        pos_w,
        vel_w,
        q_wb,
        omega_b,
        motors_at_hover: i.motors_at_hover.unwrap_or(pos_w.is_some()),
    })
}
