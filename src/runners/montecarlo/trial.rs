//! One Monte Carlo run: the flight core and the plant in lockstep from a drawn initial state,
//! holding hover at the origin against a constant external wrench, judged by a
//! controller-independent criterion on the true state. The setpoint heading ψ_sp is 0 (the
//! vehicle must also turn to north) or the initial heading ([`Heading`]).
//!
//! The flight core follows the hover setpoint ([`SetpointFollower`]) in [`Lockstep`] with the
//! plant; a [`Judge`] watches every tick (criterion and convergence in [`super::judging`]) and a
//! [`Guard`] ends runs that fault or leave the 1 km sphere.

use thiserror::Error;

use crate::airframe::{Airframe, AirframeSource};
use crate::control::{ControllerKind, FlatSetpoint};
use crate::flight::{FlightCore, SetpointFollower};
use crate::lockstep::{FailureSchedule, Guard, Lockstep, ScheduledFailure, SetupError};
use crate::math::Vec3;
use crate::sitl::{SensorModel, SimPlant};
use crate::wrench_estimator::{ChebyshevDesign, DesignError, ObserverError, WrenchObserver};

use super::envelope::Draw;
use super::judging::Judge;
pub use super::judging::{equilibrium_attitude, rotation_angle, Criterion, Heading, TrialOutcome};

/// Beyond this distance from the setpoint a run is stopped as a fly-away [m].
const FLY_AWAY_M: f64 = 1e3;

/// Height of the ground plane below the setpoint (NED z) [m]: far enough that no run touches it.
const GROUND_BELOW_M: f64 = 1e4;

/// A campaign that cannot be set up (the same for every draw).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TrialError {
    /// The airframe, flight core or plant was refused.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The estimator design is not usable.
    #[error("estimator design: {0}")]
    Design(#[from] DesignError),
    /// The estimator refused its settings.
    #[error("estimator: {0}")]
    Observer(#[from] ObserverError),
    /// The airframe text could not be rewritten with the run's disturbance.
    #[error("{origin}: {reason}")]
    Text {
        /// Airframe name.
        origin: String,
        /// What failed.
        reason: String,
    },
    /// A step or duration that is not a positive number.
    #[error("{0}")]
    Timing(String),
    /// A rotor failure names no rotor of the airframe or a negative time.
    #[error("--fail-rotor: {0}")]
    RotorFailure(String),
}

/// What every run of a campaign shares.
#[derive(Debug, Clone)]
pub struct TrialSetup {
    /// The FC's view of the airframe.
    pub airframe: Airframe,
    origin: String,
    plant_table: toml::Table,
    estimator: Option<ChebyshevDesign>,
    estimator_gains: Vec<f64>,
    compensation: bool,
    dt_s: f64,
    duration_s: f64,
    /// Convergence criterion.
    pub criterion: Criterion,
    /// Heading of the setpoint.
    pub heading: Heading,
    /// Rotors that stop in every run.
    rotor_failures: FailureSchedule,
}

impl TrialSetup {
    /// Setup for `src` with the estimator `estimator` (`None`: off), compensation on or off, step
    /// `dt_s` [s] and run length `duration_s` [s]. Builds one core and one plant to refuse a bad
    /// configuration here rather than in every run.
    pub fn new(
        src: &AirframeSource,
        estimator: Option<ChebyshevDesign>,
        compensation: bool,
        dt_s: f64,
        duration_s: f64,
        criterion: Criterion,
    ) -> Result<Self, TrialError> {
        if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= 0.01) {
            return Err(TrialError::Timing(format!("step {dt_s} s must be in (0, 0.01]")));
        }
        if !(duration_s.is_finite() && duration_s > 0.0 && duration_s <= 3600.0) {
            return Err(TrialError::Timing(format!(
                "--duration {duration_s}: must be a positive number of seconds up to 3600"
            )));
        }
        if !(criterion.window_s.is_finite() && criterion.window_s > 0.0 && criterion.window_s < duration_s) {
            return Err(TrialError::Timing(format!(
                "--window {}: must be positive and shorter than the duration {duration_s} s",
                criterion.window_s
            )));
        }
        let text_err = |reason: String| TrialError::Text {
            origin: src.origin.clone(),
            reason,
        };
        let airframe = Airframe::from_source(src).map_err(SetupError::from)?;
        let mut plant_table: toml::Table = toml::from_str(&src.text).map_err(|e| text_err(e.to_string()))?;
        let plant = plant_table
            .entry("plant")
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let toml::Value::Table(plant) = plant else {
            return Err(text_err("plant: must be a table".into()));
        };
        // The run flies in free air: no ceiling, no scripted wrench but its own, no start pose.
        for key in ["ceiling", "disturbance", "initial"] {
            plant.remove(key);
        }
        let ground = plant
            .entry("ground")
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let toml::Value::Table(ground) = ground {
            ground.insert("height".into(), toml::Value::Float(GROUND_BELOW_M));
        }
        let estimator_gains = match &estimator {
            Some(d) => d.gains(dt_s)?,
            None => Vec::new(),
        };
        let rotor_failures = FailureSchedule::new(airframe.rotors.len());
        let setup = Self {
            airframe,
            origin: src.origin.clone(),
            plant_table,
            estimator,
            estimator_gains,
            compensation,
            dt_s,
            duration_s,
            criterion,
            heading: Heading::Zero,
            rotor_failures,
        };
        setup.core(ControllerKind::Geometric)?;
        setup.plant(&Vec3::zeros(), &Vec3::zeros(), 0)?;
        Ok(setup)
    }

    /// Stops rotor `failure.rotor` at `failure.at_s` in every run; refused naming what is wrong.
    pub fn schedule_rotor_failure(&mut self, failure: ScheduledFailure) -> Result<(), TrialError> {
        self.rotor_failures.schedule(failure).map_err(TrialError::RotorFailure)
    }

    /// Estimator design (`None`: no estimator).
    pub fn estimator(&self) -> Option<&ChebyshevDesign> {
        self.estimator.as_ref()
    }

    /// Subtract the estimated wrench.
    pub fn compensation(&self) -> bool {
        self.compensation
    }

    /// Control and integration step [s].
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Simulated duration of each run [s].
    pub fn duration_s(&self) -> f64 {
        self.duration_s
    }

    /// Number of ticks of one run.
    pub fn ticks(&self) -> u64 {
        (self.duration_s / self.dt_s).round() as u64
    }

    /// The flight core of one run: default gains, compensation as set, a fresh estimator.
    fn core(&self, kind: ControllerKind) -> Result<FlightCore, TrialError> {
        let mut core = FlightCore::for_airframe(&self.airframe, kind, self.dt_s).map_err(SetupError::from)?;
        core.controller.set_compensation(self.compensation);
        if self.estimator.is_some() {
            let observer = WrenchObserver::new(
                self.airframe.mass_kg,
                self.airframe.inertia_kg_m2,
                self.estimator_gains.clone(),
                self.dt_s,
            )?;
            core.set_observer(Some(observer));
        }
        Ok(core)
    }

    /// The plant of one run with a constant wrench (`force_w` world NED [N], `torque_b` body
    /// FRD [N·m]) and sensor-noise seed `seed`.
    fn plant(&self, force_w: &Vec3, torque_b: &Vec3, seed: u64) -> Result<SimPlant, TrialError> {
        let mut table = self.plant_table.clone();
        let mut component = toml::Table::new();
        let arr = |v: &Vec3| toml::Value::Array(v.iter().map(|x| toml::Value::Float(*x)).collect());
        component.insert("kind".into(), toml::Value::String("constant".into()));
        component.insert("force".into(), arr(force_w));
        component.insert("torque".into(), arr(torque_b));
        if let Some(toml::Value::Table(plant)) = table.get_mut("plant") {
            plant.insert(
                "disturbance".into(),
                toml::Value::Array(vec![toml::Value::Table(component)]),
            );
        }
        let text = toml::to_string(&table).map_err(|e| TrialError::Text {
            origin: self.origin.clone(),
            reason: e.to_string(),
        })?;
        let src = AirframeSource {
            origin: format!("{} (monte carlo run)", self.origin),
            text,
        };
        Ok(SimPlant::from_source(&src, seed).map_err(SetupError::from)?)
    }
}

/// Flies one run of `kind` from `draw` (module docs). Never panics by design; the runner still
/// guards it.
pub fn fly(setup: &TrialSetup, kind: ControllerKind, draw: &Draw) -> Result<TrialOutcome, TrialError> {
    let core = setup.core(kind)?;
    let mut plant = setup.plant(&draw.force_w, &draw.torque_b, draw.noise_seed)?;
    plant.set_initial_state(Some(draw.pos_w), draw.vel_w, draw.q_wb, draw.omega_b, true);
    let yaw_sp = setup.heading.setpoint_yaw_rad(draw);
    let r_eq = equilibrium_attitude(plant.true_mass_kg(), &draw.force_w, yaw_sp);
    let judge = Judge::new(setup.criterion, r_eq, &plant.truth());
    let setpoint = FlatSetpoint::hold(Vec3::zeros(), yaw_sp);
    let mut follower = SetpointFollower::new(core, setpoint);
    if plant.sensor_model() == SensorModel::Suite {
        follower = follower.starting_at(&plant.true_state());
    }
    let mut lockstep = Lockstep::new(follower, plant, setup.dt_s);
    lockstep.set_rotor_failures(setup.rotor_failures.clone());
    let mut observer = (judge, Guard { fly_away_m: FLY_AWAY_M });
    let end = lockstep.run(setup.ticks(), &mut observer);
    let window_ticks = (setup.criterion.window_s / setup.dt_s).round() as u64;
    Ok(observer.0.outcome(end, window_ticks, setup.dt_s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lockstep::Exit;
    use crate::math::{e3, Mat3, UnitQuat, GRAVITY_M_S2};

    fn setup(duration_s: f64) -> TrialSetup {
        setup_with(duration_s, Criterion::default())
    }

    fn setup_with(duration_s: f64, criterion: Criterion) -> TrialSetup {
        let design = ChebyshevDesign {
            order: 1,
            ripple_db: 3.0,
            passband_rad_s: 2.0,
        };
        TrialSetup::new(
            &AirframeSource::resolve("quad_x").unwrap(),
            Some(design),
            true,
            1e-3,
            duration_s,
            criterion,
        )
        .unwrap()
    }

    fn hover_draw() -> Draw {
        Draw {
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            q_wb: UnitQuat::identity(),
            omega_b: Vec3::zeros(),
            force_w: Vec3::zeros(),
            torque_b: Vec3::zeros(),
            noise_seed: 0,
        }
    }

    #[test]
    fn the_equilibrium_attitude_balances_weight_and_force() {
        let f = Vec3::new(2.0, -1.0, 0.5);
        let r = equilibrium_attitude(1.5, &f, 0.0);
        assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-12);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        // Thrust −u R e3 cancels m g e3 + f for u = ‖m g e3 + f‖.
        let total = 1.5 * GRAVITY_M_S2 * e3() + f;
        assert!((total - total.norm() * r * e3()).norm() < 1e-12);
        assert_eq!(equilibrium_attitude(1.5, &Vec3::zeros(), 0.0), Mat3::identity());
        // Level at heading ψ is Rz(ψ).
        let yawed = equilibrium_attitude(1.5, &Vec3::zeros(), 2.0);
        let rz = crate::math::UnitQuat::from_euler_angles(0.0, 0.0, 2.0)
            .to_rotation_matrix()
            .into_inner();
        assert!((yawed - rz).norm() < 1e-12);
        assert!((rotation_angle(&Mat3::identity(), &r) - total.normalize().dot(&e3()).acos()).abs() < 0.05);
    }

    #[test]
    fn a_vehicle_at_rest_in_hover_converges_at_once() {
        let s = setup(2.0);
        for kind in ControllerKind::ALL {
            let o = fly(&s, kind, &hover_draw()).unwrap();
            assert!(o.converged, "{kind:?}: {o:?}");
            assert_eq!(o.convergence_time_s, Some(0.0), "{kind:?}");
            assert!(o.final_position_error_m < 1e-6, "{kind:?}: {o:?}");
            assert_eq!(o.ticks, 2000);
        }
    }

    #[test]
    fn a_disturbed_start_settles_later_and_is_reproducible() {
        let s = setup(6.0);
        let draw = Draw {
            pos_w: Vec3::new(0.5, -0.3, 0.2),
            vel_w: Vec3::new(1.0, 0.0, -1.0),
            q_wb: UnitQuat::from_euler_angles(0.5, -0.3, 0.4),
            omega_b: Vec3::new(1.0, -1.0, 0.5),
            force_w: Vec3::new(1.0, 1.0, 0.5),
            torque_b: Vec3::new(0.1, -0.1, 0.05),
            noise_seed: 9,
        };
        for kind in ControllerKind::ALL {
            let a = fly(&s, kind, &draw).unwrap();
            assert!(a.converged, "{kind:?}: {a:?}");
            let t = a.convergence_time_s.unwrap();
            assert!(t > 0.2 && t < 5.0, "{kind:?}: {t}");
            assert_eq!(a, fly(&s, kind, &draw).unwrap(), "{kind:?}");
        }
    }

    #[test]
    fn a_run_still_outside_the_tolerance_at_the_end_has_not_converged() {
        // 0.5 s is too short to recover from 2 m away.
        let s = setup_with(
            0.5,
            Criterion {
                window_s: 0.1,
                ..Criterion::default()
            },
        );
        let draw = Draw {
            pos_w: Vec3::new(2.0, 0.0, 0.0),
            ..hover_draw()
        };
        let o = fly(&s, ControllerKind::Geometric, &draw).unwrap();
        assert!(!o.converged && o.convergence_time_s.is_none(), "{o:?}");
        assert!(o.final_position_error_m > 0.1);
        assert_eq!(o.end, Exit::Complete);
    }

    #[test]
    fn bad_timing_is_refused() {
        let src = AirframeSource::resolve("quad_x").unwrap();
        let c = Criterion::default();
        assert!(TrialSetup::new(&src, None, false, 0.0, 6.0, c).is_err());
        assert!(TrialSetup::new(&src, None, false, 1e-3, f64::NAN, c).is_err());
        assert!(
            TrialSetup::new(&src, None, false, 1e-3, 0.5, c).is_err(),
            "window ≥ duration"
        );
    }
}
