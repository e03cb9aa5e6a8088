//! One autopilot vehicle as the tick thread holds it: the flight controller and the plant in a
//! [`Lockstep`], and the `run.csv` log sender of `--log DIR`. A thin wrapper: every decision is
//! made by [`FlightController`], every tick by [`Lockstep::step`].

use crate::airframe::{Airframe, AirframeSource};
use crate::commander::{Event, Outcome, Request};
use crate::control::ControllerKind;
use crate::flight::FlightController;
use crate::lockstep::{Lockstep, Observer, ScheduledFailure, SetupError};
use crate::navigation::Home;
use crate::params::{ParamError, ParamTable};
use crate::sitl::SimPlant;
use crate::telemetry::Snapshot;

use super::flight_log::LogSender;

/// The autopilot's start-up estimator and tilt limit, where the fuzz targets name them.
pub use crate::flight::{AUTOPILOT_TILT_MAX_DEG, DEFAULT_ESTIMATOR};

/// The flight controller and plant of one vehicle, and where its ticks are logged.
#[derive(Debug)]
pub struct Vehicle {
    lockstep: Lockstep<FlightController>,
    log: Option<LogSender>,
}

/// What one tick produced for the links.
#[derive(Debug, Clone, PartialEq)]
pub struct TickOutput {
    /// Latest state.
    pub snapshot: Snapshot,
    /// What the commander did on its own.
    pub events: Vec<Event>,
}

impl Vehicle {
    /// Vehicle of airframe `src` flown by `kind`, home `home`, sensor seed `seed`, step `dt_s` [s].
    pub fn new(
        src: &AirframeSource,
        kind: ControllerKind,
        home: Home,
        seed: u64,
        dt_s: f64,
    ) -> Result<Self, SetupError> {
        let airframe = Airframe::from_source(src)?;
        let controller = FlightController::new(&airframe, kind, home, dt_s)?;
        let plant = SimPlant::from_source(src, seed)?;
        for w in plant.warnings() {
            tracing::warn!("{w}");
        }
        Ok(Self {
            lockstep: Lockstep::new(controller, plant, dt_s),
            log: None,
        })
    }

    /// Sends every tick to `log` (`run.csv` of `--log DIR`).
    pub fn set_log(&mut self, log: LogSender) {
        self.log = Some(log);
    }

    /// The parameter table.
    pub fn params(&self) -> &ParamTable {
        self.lockstep.pilot().params()
    }

    /// Sets parameter `name` to `value` at this tick boundary ([`FlightController::set_param`]).
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<usize, ParamError> {
        self.lockstep.set_param(name, value)
    }

    /// Rotor count.
    pub fn rotor_count(&self) -> usize {
        self.lockstep.pilot().rotor_count()
    }

    /// Simulated time [s].
    pub fn time_s(&self) -> f64 {
        self.lockstep.time_s()
    }

    /// Applies a ground-station request at the current tick boundary
    /// ([`Lockstep::request`]).
    pub fn apply(&mut self, request: Request) -> Outcome {
        self.lockstep.request(request)
    }

    /// Stops a rotor at a simulated time (`--fail-rotor`).
    pub fn schedule_rotor_failure(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        self.lockstep.schedule_rotor_failure(failure)
    }

    /// One tick ([`Lockstep::step`]), logged when a log is set.
    pub fn step(&mut self) -> TickOutput {
        let tick = self.lockstep.step();
        self.log.observe(&tick, self.lockstep.plant());
        TickOutput {
            snapshot: tick.report,
            events: tick.control.events,
        }
    }
}
