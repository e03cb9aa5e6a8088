//! What `rotorpilot run` is given ([`RunConfig`]), what it says when ready ([`Ready`]), what it
//! reports when it stops ([`RunReport`]) and why it could not run ([`RuntimeError`]).

use std::net::SocketAddr;

use serde::Serialize;
use thiserror::Error;

use crate::airframe::AirframeSource;
use crate::control::ControllerKind;
use crate::guidance::Home;
use crate::mav::identity::Personality;

use super::impairment::{LinkCounts, LinkImpairment};
use super::log_place::LogPlace;
use super::pacer::Pace;
use super::signing_store::SigningFileError;
use crate::lockstep::SetupError;
use crate::lockstep::{ScheduledFailure, ScheduledSensorFailure};
use crate::sitl::SensorModel;

/// Everything `rotorpilot run` needs.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// Airframe text.
    pub airframe: AirframeSource,
    /// Control law.
    pub controller: ControllerKind,
    /// System id of the first vehicle (1–255); vehicle i gets `system_id + i`.
    pub system_id: u8,
    /// GCS link bind address of the first vehicle; vehicle i binds port + i (port 0: any).
    pub bind_gcs: SocketAddr,
    /// Remote GCS address, shared by every vehicle (the GCS tells them apart by sysid).
    pub gcs: SocketAddr,
    /// API link bind address of the first vehicle; vehicle i binds port + i (port 0: any).
    pub bind_api: SocketAddr,
    /// Remote API address of the first vehicle; vehicle i sends to port + i.
    pub api: SocketAddr,
    /// Geodetic home of the first vehicle; the others stand on a grid north and east of it.
    pub home: Home,
    /// Sensor-noise seed of the first vehicle; vehicle i uses `seed + i`.
    pub seed: u64,
    /// Tick [s].
    pub dt_s: f64,
    /// Where the logs go: `--log DIR` (tlog and flight logs) or the per-user default (flight
    /// logs); `None`: no logs (`--no-log`). The flight logs are written as `SDLOG_MODE` says.
    pub log: Option<LogPlace>,
    /// Rates of the flight logs' topics.
    pub log_profile: crate::ulog::Profile,
    /// Parameter values applied before start (`--params FILE`): (where, name, value).
    pub params: Vec<(String, String, f64)>,
    /// Number of vehicles (1 or more).
    pub count: usize,
    /// The autopilot each vehicle presents itself as (`--autopilot`): one for every vehicle, or
    /// one per vehicle in order.
    pub personalities: Vec<Personality>,
    /// Distance between neighbouring vehicles on the start grid [m].
    pub spacing_m: f64,
    /// Simulated against wall time.
    pub pace: Pace,
    /// Rotors that stop at a simulated time, on every vehicle (`--fail-rotor`).
    pub rotor_failures: Vec<ScheduledFailure>,
    /// Which sensors the flight controllers read (`--sensors`).
    pub sensors: SensorModel,
    /// Sensors that fail at a simulated time, on every vehicle (`--fail`).
    pub sensor_failures: Vec<ScheduledSensorFailure>,
    /// `--signing-key FILE`: the MAVLink 2 signing key of every vehicle (the file may not exist
    /// yet; SETUP_SIGNING then creates it), its timestamp kept in `FILE.timestamp`.
    pub signing_key: Option<std::path::PathBuf>,
    /// `--link-loss`, `--link-delay`, `--link-duplicate`: the links made lossy on purpose.
    pub link_impairment: Option<LinkImpairment>,
}

impl RunConfig {
    /// One vehicle at `system_id` with PX4 SITL's defaults for everything else: real time, the
    /// given addresses, home at PX4's default, seed 0, 1 kHz; on the exact state (the command
    /// line's `run` chooses realistic sensors unless told `--sensors ideal`); no logs (the
    /// command line's `run` logs into the per-user directory unless told `--no-log`).
    pub fn single(airframe: AirframeSource, controller: ControllerKind, system_id: u8) -> Self {
        Self {
            airframe,
            controller,
            system_id,
            bind_gcs: SocketAddr::from(([127, 0, 0, 1], 18570)),
            gcs: SocketAddr::from(([127, 0, 0, 1], 14550)),
            bind_api: SocketAddr::from(([127, 0, 0, 1], 14580)),
            api: SocketAddr::from(([127, 0, 0, 1], 14540)),
            home: Home::default(),
            seed: 0,
            dt_s: 1e-3,
            log: None,
            log_profile: crate::ulog::Profile::Default,
            params: Vec::new(),
            count: 1,
            personalities: vec![Personality::Px4],
            spacing_m: DEFAULT_SPACING_M,
            pace: Pace::Speedup(1.0),
            sensors: SensorModel::State,
            sensor_failures: Vec::new(),
            rotor_failures: Vec::new(),
            signing_key: None,
            link_impairment: None,
        }
    }

    /// The autopilot vehicle `i` presents itself as: the one given for all, or its own.
    pub fn personality(&self, i: usize) -> Personality {
        match self.personalities.as_slice() {
            [one] => *one,
            each => each.get(i).copied().unwrap_or_default(),
        }
    }
}

/// Default distance between neighbouring vehicles on the start grid [m].
pub const DEFAULT_SPACING_M: f64 = 3.0;

/// Why the process could not run.
#[derive(Debug, Error)]
pub enum RuntimeError {
    /// The vehicle could not be built.
    #[error(transparent)]
    Vehicle(#[from] SetupError),
    /// A socket could not be bound.
    #[error("cannot bind {addr}: {source}")]
    Bind {
        /// Address.
        addr: SocketAddr,
        /// Cause.
        source: std::io::Error,
    },
    /// A `--params` value was refused.
    #[error("--params {0}")]
    Params(String),
    /// `--autopilot` names neither one personality for every vehicle nor one per vehicle, or
    /// ArduCopter's defaults do not fit the airframe.
    #[error("--autopilot {0}")]
    Personality(String),
    /// A `--fail-rotor` schedule does not fit the airframe.
    #[error("--fail-rotor {0}")]
    RotorFailure(String),
    /// The log directory could not be written.
    #[error("log directory {dir}: {source}")]
    Log {
        /// Directory.
        dir: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The vehicle count does not fit the system ids or ports.
    #[error("--count {count} from sysid {first}: {why}")]
    Count {
        /// Vehicles asked for.
        count: usize,
        /// First system id.
        first: u8,
        /// What does not fit.
        why: &'static str,
    },
    /// The signing key or timestamp file could not be read.
    #[error(transparent)]
    Signing(#[from] SigningFileError),
    /// The tokio runtime or a thread could not start.
    #[error("runtime: {0}")]
    Runtime(std::io::Error),
}

/// The addresses of one vehicle, as the ready line reports them.
#[derive(Debug, Clone, Serialize)]
pub struct VehicleReady {
    /// System id.
    pub sysid: u8,
    /// The autopilot it presents itself as ("px4" or "ardupilot").
    pub autopilot: Personality,
    /// Bound GCS address.
    pub gcs_bind: String,
    /// Bound API address.
    pub api_bind: String,
    /// Remote GCS address.
    pub gcs: String,
    /// Remote API address.
    pub api: String,
    /// The vehicle's log directory (flight logs in `log/YYYY-MM-DD/HH_MM_SS.ulg` below it,
    /// `flight.tlog` with `--log`); null without logs.
    pub log_dir: Option<String>,
}

/// The machine-readable start-up line (printed as JSON on stdout): the first vehicle's
/// addresses at the top level, every vehicle's in `vehicles`.
#[derive(Debug, Clone, Serialize)]
pub struct Ready {
    /// Always "ready".
    pub event: &'static str,
    /// The first vehicle.
    #[serde(flatten)]
    pub first: VehicleReady,
    /// Every vehicle, in sysid order.
    pub vehicles: Vec<VehicleReady>,
}

/// What one vehicle's link impairment did.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct VehicleLinkCounts {
    /// System id.
    pub sysid: u8,
    /// Each impaired link, both ways.
    pub links: Vec<LinkCounts>,
}

/// What the process did, returned when it stops (printed as a JSON line by `run`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunReport {
    /// Always "stopped".
    pub event: &'static str,
    /// Vehicle ticks run (all vehicles together).
    pub vehicle_ticks: u64,
    /// Schedule rebases after a backlog.
    pub overruns: u64,
    /// Wall time between start and stop [s].
    pub wall_s: f64,
    /// What the link impairment did, per vehicle (empty without one).
    pub link_impairment: Vec<VehicleLinkCounts>,
}
