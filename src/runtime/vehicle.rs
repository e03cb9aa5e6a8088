//! One autopilot vehicle as the tick thread holds it: the flight controller and the plant in a
//! [`Lockstep`], and its ULog flight logs, opened and closed as `SDLOG_MODE` (read at the first
//! tick, as PX4 reads it at boot) says: by default one file per arming, from arming to
//! disarming. A thin wrapper: every decision is made by [`FlightController`], every tick by
//! [`Lockstep::step`], when to log by [`LogSchedule`].

use std::sync::Arc;

use crate::airframe::{Airframe, AirframeSource};
use crate::commander::{Event, Outcome, Request};
use crate::control::ControllerKind;
use crate::flight::FlightController;
use crate::guidance::Home;
use crate::lockstep::{Exit, Lockstep, Observer, ScheduledFailure, ScheduledSensorFailure, SetupError, Tick, TickView};
use crate::params::{ParamError, ParamTable};
use crate::sitl::{PlantTruth, SensorModel, SimPlant};
use crate::telemetry::Snapshot;

use super::flight_log::{LogSender, UlogTarget};
use super::ulog_stream::{log_params, param_value, UlogStream};
use crate::ulog::{LogInfo, LogSchedule, Profile, Recorder, RecorderSetup};

/// The autopilot's start-up estimator and tilt limit, where the fuzz targets name them.
pub use crate::flight::{AUTOPILOT_TILT_MAX_DEG, DEFAULT_ESTIMATOR};

/// The flight controller and plant of one vehicle, and where its ticks are logged.
#[derive(Debug)]
pub struct Vehicle {
    lockstep: Lockstep<FlightController>,
    log: Option<FlightLogs>,
    /// What the ULog recorder needs of the airframe.
    log_setup: RecorderSetup,
    /// The log's info.
    log_info: LogInfo,
}

/// The ULog flight logs (the writer names them in its log directory's `log/`).
#[derive(Debug)]
struct FlightLogs {
    stream: UlogStream,
    /// When a log is open; made at the first tick from `SDLOG_MODE`.
    schedule: Option<LogSchedule>,
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
    /// Vehicle of airframe `src` flown by `kind`, home `home`, reading `sensors` seeded by
    /// `seed`, step `dt_s` [s].
    pub fn new(
        src: &AirframeSource,
        kind: ControllerKind,
        home: Home,
        sensors: SensorModel,
        seed: u64,
        dt_s: f64,
    ) -> Result<Self, SetupError> {
        let airframe = Airframe::from_source(src)?;
        let mut controller = FlightController::new(&airframe, kind, home, dt_s)?;
        if sensors == SensorModel::Suite {
            controller.expect_sensor_suite();
        }
        let plant = SimPlant::at_home(src, &home, seed)?.with_sensor_model(sensors);
        for w in plant.warnings() {
            tracing::warn!("{w}");
        }
        let log_setup = RecorderSetup::new(&airframe, plant.true_mass_kg(), Profile::Default, dt_s);
        let log_info = LogInfo::new(&airframe.name, kind, None);
        Ok(Self {
            lockstep: Lockstep::new(controller, plant, dt_s),
            log: None,
            log_setup,
            log_info,
        })
    }

    /// Writes ULog flight logs through `sender` (into its log directory), with `profile`, as
    /// `SDLOG_MODE` says at the first tick.
    pub fn set_log(&mut self, sender: LogSender, profile: Profile) {
        let setup = RecorderSetup {
            profile,
            ..self.log_setup.clone()
        };
        self.log = Some(FlightLogs {
            stream: UlogStream::new(Recorder::new(setup), sender, false),
            schedule: None,
        });
    }

    /// The parameter table.
    pub fn params(&self) -> &ParamTable {
        self.lockstep.pilot().params()
    }

    /// The parameter table as its owner publishes it after each set, shared (no copy; see
    /// [`FlightController::shared_params`]): what the link holds.
    pub fn shared_params(&self) -> Arc<ParamTable> {
        self.lockstep.pilot().shared_params()
    }

    /// Sets parameter `name` to `value` at this tick boundary ([`FlightController::set_param`]).
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<usize, ParamError> {
        let index = self.lockstep.set_param(name, value)?;
        if let (Some(log), Some((def, value))) = (&mut self.log, self.lockstep.pilot().params().get(index)) {
            log.stream.param_changed(def.name, param_value(def, value));
        }
        Ok(index)
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

    /// The plant's exact state (for tests and benchmarks; never the flight controller's input).
    pub fn truth(&self) -> PlantTruth {
        self.lockstep.plant().truth()
    }

    /// Stops a rotor at a simulated time (`--fail-rotor`).
    pub fn schedule_rotor_failure(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        self.lockstep.schedule_rotor_failure(failure)
    }

    /// Fails a sensor at a simulated time (`--fail`).
    pub fn schedule_sensor_failure(&mut self, failure: ScheduledSensorFailure) {
        self.lockstep.schedule_sensor_failure(failure)
    }

    /// One tick ([`Lockstep::step_observed`]), watched by the flight logs when a log is set
    /// ([`LogWatch`]).
    pub fn step(&mut self) -> TickOutput {
        let params = self.log.as_ref().map(|_| self.lockstep.pilot().shared_params());
        let mut watch = match (&mut self.log, &params) {
            (Some(logs), Some(params)) => Some(LogWatch {
                logs,
                params,
                info: &self.log_info,
            }),
            _ => None,
        };
        let (tick, _) = self.lockstep.step_observed(&mut watch);
        TickOutput {
            snapshot: tick.report,
            events: tick.control.events,
        }
    }
}

/// The flight logs watching one tick: a file opens when the [`LogSchedule`] asks for one (by
/// default at arming), the tick is recorded, and the file closes after the tick at which the
/// schedule no longer asks (by default the disarming tick).
struct LogWatch<'a> {
    logs: &'a mut FlightLogs,
    /// The parameters as they are at this tick (`SDLOG_MODE`, and the values a new file lists).
    params: &'a ParamTable,
    info: &'a LogInfo,
}

impl Observer<Snapshot> for LogWatch<'_> {
    fn observe(&mut self, tick: &Tick<Snapshot>, plant: &SimPlant) -> Option<Exit> {
        let params = self.params;
        let logs = &mut *self.logs;
        let schedule = logs
            .schedule
            .get_or_insert_with(|| LogSchedule::new(params.current().log_mode));
        let wanted = schedule.wants_log(tick.report.armed);
        if wanted && !logs.stream.is_open() {
            let now = std::time::SystemTime::now();
            let mut info = self.info.clone();
            info.utc_s = now.duration_since(std::time::UNIX_EPOCH).ok().map(|d| d.as_secs());
            logs.stream
                .open(UlogTarget::Flight(now), tick.t_s, &info, &log_params(params));
        }
        logs.stream.record(&TickView::of(tick, plant));
        if !wanted && logs.stream.is_open() {
            logs.stream.close();
        }
        None
    }
}
