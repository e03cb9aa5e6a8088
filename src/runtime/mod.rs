//! The autopilot process (`rotorpilot run`): one vehicle ticking at 1 kHz on its own thread and
//! two MAVLink UDP links (GCS and API, PX4 SITL ports) served by tokio. Runtime layer: clocks,
//! sockets, threads; every decision is made by the pure modules it calls.

pub mod flight_log;
pub mod link;
pub mod pacer;
pub mod scheduler;
mod signing_keeper;
pub mod signing_store;
pub mod vehicle;

use std::future::Future;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;
use thiserror::Error;
use tokio::net::UdpSocket;
use tokio::sync::{broadcast, mpsc, watch};

use crate::airframe::AirframeSource;
use crate::control::ControllerKind;
use crate::math::Vec3;
use crate::mav::signing::Signing;
use crate::mav::streams::LinkKind;
use crate::mav::translate::Identity;
use crate::navigation::Home;
use crate::telemetry::Snapshot;

use crate::commander::Event;
use crate::lockstep::ScheduledFailure;
use flight_log::LogSender;
use link::{run_link, LinkContext};
pub use pacer::Pace;
use scheduler::{SchedulerStats, VehicleIo, VehicleSlot};
use signing_keeper::{signing_keeper, SigningSetup};
use signing_store::SigningFileError;
use vehicle::{Vehicle, VehicleError};

/// Bound of the request queue into the tick thread: commands are never dropped silently; when
/// it is full the link answers TEMPORARILY_REJECTED at once.
const INBOX_CAPACITY: usize = 256;
/// Bound of the event queue out of the tick thread (announcements only; dropped when full).
const EVENT_CAPACITY: usize = 64;

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
    /// `--log DIR`: tlog and 1 kHz CSV (per vehicle in `DIR/vehicle-SYSID` when there are several).
    pub log_dir: Option<std::path::PathBuf>,
    /// Parameter values applied before start (`--params FILE`): (where, name, value).
    pub params: Vec<(String, String, f64)>,
    /// Number of vehicles (1 or more).
    pub count: usize,
    /// Distance between neighbouring vehicles on the start grid [m].
    pub spacing_m: f64,
    /// Simulated against wall time.
    pub pace: Pace,
    /// Rotors that stop at a simulated time, on every vehicle (`--fail-rotor`).
    pub rotor_failures: Vec<ScheduledFailure>,
    /// `--signing-key FILE`: the MAVLink 2 signing key of every vehicle (the file may not exist
    /// yet; SETUP_SIGNING then creates it), its timestamp kept in `FILE.timestamp`.
    pub signing_key: Option<std::path::PathBuf>,
}

impl RunConfig {
    /// One vehicle at `system_id` with PX4 SITL's defaults for everything else: real time, the
    /// given addresses, home at PX4's default, seed 0, 1 kHz.
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
            log_dir: None,
            params: Vec::new(),
            count: 1,
            spacing_m: DEFAULT_SPACING_M,
            pace: Pace::Speedup(1.0),
            rotor_failures: Vec::new(),
            signing_key: None,
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
    Vehicle(#[from] VehicleError),
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
    /// A `--fail-rotor` schedule does not fit the airframe.
    #[error("--fail-rotor {0}")]
    RotorFailure(String),
    /// The log directory could not be written.
    #[error("--log {dir}: {source}")]
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
    /// Bound GCS address.
    pub gcs_bind: String,
    /// Bound API address.
    pub api_bind: String,
    /// Remote GCS address.
    pub gcs: String,
    /// Remote API address.
    pub api: String,
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

/// What the process did, returned when it stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunReport {
    /// Vehicle ticks run (all vehicles together).
    pub vehicle_ticks: u64,
    /// Schedule rebases after a backlog.
    pub overruns: u64,
    /// Wall time between start and stop [s].
    pub wall_s: f64,
}

/// One vehicle's share of the process: its sockets, channels and log.
struct VehicleSetup {
    slot: VehicleSlot,
    ready: VehicleReady,
    links: [(UdpSocket, SocketAddr, LinkKind); 2],
    context: LinkContext,
    events: mpsc::Receiver<Event>,
    announce: broadcast::Sender<Event>,
    log: Option<(LogSender, std::thread::JoinHandle<()>)>,
}

/// Port `port + i` of an address; port 0 stays 0 (any free port).
fn nth_port(addr: SocketAddr, i: usize) -> Option<SocketAddr> {
    if addr.port() == 0 {
        return Some(addr);
    }
    let port = u16::try_from(usize::from(addr.port()) + i).ok()?;
    Some(SocketAddr::new(addr.ip(), port))
}

/// Where vehicle `i` of `count` stands: a square grid, rows north, columns east [m].
fn grid_offset(i: usize, count: usize, spacing_m: f64) -> Vec3 {
    let columns = (count as f64).sqrt().ceil().max(1.0) as usize;
    Vec3::new((i / columns) as f64 * spacing_m, (i % columns) as f64 * spacing_m, 0.0)
}

fn setup_vehicle(
    config: &RunConfig,
    i: usize,
    rt: &tokio::runtime::Runtime,
    shutdown: &watch::Receiver<bool>,
    signing: &SigningSetup,
) -> Result<VehicleSetup, RuntimeError> {
    let too_many = |why| RuntimeError::Count {
        count: config.count,
        first: config.system_id,
        why,
    };
    let sysid = u8::try_from(usize::from(config.system_id) + i).map_err(|_| too_many("system ids end at 255"))?;
    let (lat_deg, lon_deg, alt_amsl_m) = config.home.to_global(&grid_offset(i, config.count, config.spacing_m));
    let home = Home {
        lat_deg,
        lon_deg,
        alt_amsl_m,
    };
    let mut vehicle = Vehicle::new(
        &config.airframe,
        config.controller,
        home,
        config.seed.wrapping_add(i as u64),
        config.dt_s,
    )?;
    for (origin, name, value) in &config.params {
        vehicle
            .set_param(name, *value)
            .map_err(|e| RuntimeError::Params(format!("{origin}: {e}")))?;
    }
    for failure in &config.rotor_failures {
        vehicle
            .schedule_rotor_failure(*failure)
            .map_err(RuntimeError::RotorFailure)?;
    }
    let log = match &config.log_dir {
        Some(dir) => {
            let dir = if config.count > 1 {
                dir.join(format!("vehicle-{sysid}"))
            } else {
                dir.clone()
            };
            let (sender, writer) =
                flight_log::start(&dir, vehicle.rotor_count()).map_err(|source| RuntimeError::Log {
                    dir: dir.display().to_string(),
                    source,
                })?;
            vehicle.set_log(sender.clone());
            Some((sender, writer))
        }
        None => None,
    };
    let port = |addr| nth_port(addr, i).ok_or_else(|| too_many("ports end at 65535"));
    let (bind_gcs, bind_api, api) = (port(config.bind_gcs)?, port(config.bind_api)?, port(config.api)?);
    let bind = |addr: SocketAddr| {
        let _guard = rt.enter();
        bind_udp(addr).map_err(|source| RuntimeError::Bind { addr, source })
    };
    let gcs_socket = bind(bind_gcs)?;
    let api_socket = bind(bind_api)?;
    let local = |s: &UdpSocket| s.local_addr().map(|a| a.to_string()).unwrap_or_default();
    let ready = VehicleReady {
        sysid,
        gcs_bind: local(&gcs_socket),
        api_bind: local(&api_socket),
        gcs: config.gcs.to_string(),
        api: api.to_string(),
    };
    let (inbox_tx, inbox_rx) = mpsc::channel(INBOX_CAPACITY);
    let (snapshot_tx, snapshot_rx) = watch::channel(Snapshot::initial(home));
    let (params_tx, params_rx) = watch::channel(Arc::new(vehicle.params().clone()));
    let (event_tx, event_rx) = mpsc::channel(EVENT_CAPACITY);
    let (announce_tx, _) = broadcast::channel(EVENT_CAPACITY);
    let context = LinkContext {
        identity: Identity::autopilot(sysid, vehicle.rotor_count()),
        inbox: inbox_tx,
        snapshot: snapshot_rx,
        params: params_rx,
        announcements: announce_tx.subscribe(),
        shutdown: shutdown.clone(),
        mission_store: Arc::new(std::sync::Mutex::new(Vec::new())),
        log: log.as_ref().map(|(s, _)| s.clone()),
        kind: LinkKind::Gcs,
        signing: Arc::new(std::sync::Mutex::new(Signing::new(
            signing.key.clone(),
            signing.timestamp,
        ))),
        signing_store: signing.store.clone(),
    };
    let io = VehicleIo {
        inbox: inbox_rx,
        snapshot: snapshot_tx,
        params: params_tx,
        events: event_tx,
    };
    Ok(VehicleSetup {
        slot: VehicleSlot::new(vehicle, io),
        ready,
        links: [
            (gcs_socket, config.gcs, LinkKind::Gcs),
            (api_socket, api, LinkKind::Api),
        ],
        context,
        events: event_rx,
        announce: announce_tx,
        log,
    })
}

/// Tick threads for `count` vehicles: one per core, at most one per vehicle.
fn tick_thread_count(count: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    count.clamp(1, cores.max(1))
}

/// Runs the autopilot(s) until `shutdown` completes; `on_ready` receives the bound addresses
/// once every socket is open and the tick threads run.
pub fn run(
    config: RunConfig,
    shutdown: impl Future<Output = ()> + Send + 'static,
    on_ready: impl FnOnce(&Ready),
) -> Result<RunReport, RuntimeError> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(RuntimeError::Runtime)?;
    let (shutdown_tx, shutdown_rx) = watch::channel(false);
    let signing = SigningSetup::load(config.signing_key.clone())?;
    let mut setups = Vec::with_capacity(config.count.max(1));
    for i in 0..config.count.max(1) {
        setups.push(setup_vehicle(&config, i, &rt, &shutdown_rx, &signing)?);
    }
    let keeper = rt.spawn(signing_keeper(
        setups.iter().map(|s| s.context.signing.clone()).collect(),
        signing.store.clone(),
        shutdown_rx.clone(),
    ));
    let stop = Arc::new(AtomicBool::new(false));
    let stats = Arc::new(SchedulerStats::default());
    let dt = Duration::from_secs_f64(config.dt_s);
    let threads = tick_thread_count(setups.len());
    let mut groups: Vec<Vec<VehicleSlot>> = (0..threads).map(|_| Vec::new()).collect();
    let mut vehicles = Vec::with_capacity(setups.len());
    let mut tasks = Vec::new();
    let mut logs = Vec::new();
    for (i, setup) in setups.into_iter().enumerate() {
        groups[i % threads].push(setup.slot);
        vehicles.push(setup.ready);
        for (socket, remote, kind) in setup.links {
            tasks.push(rt.spawn(run_link(socket, remote, setup.context.with_kind(kind))));
        }
        let (mut events, announce) = (setup.events, setup.announce);
        rt.spawn(async move {
            while let Some(e) = events.recv().await {
                let _ = announce.send(e);
            }
        });
        logs.extend(setup.log);
    }
    let started = std::time::Instant::now();
    let mut tick_threads = Vec::with_capacity(threads);
    for (k, group) in groups.into_iter().enumerate() {
        let (stop, stats) = (stop.clone(), stats.clone());
        let pace = config.pace;
        let handle = std::thread::Builder::new()
            .name(format!("rotorpilot-tick-{k}"))
            .spawn(move || scheduler::run_group(group, dt, pace, &stop, &stats))
            .map_err(RuntimeError::Runtime)?;
        tick_threads.push(handle);
    }
    let first = vehicles[0].clone();
    on_ready(&Ready {
        event: "ready",
        first,
        vehicles,
    });

    rt.block_on(async move {
        shutdown.await;
        let _ = shutdown_tx.send(true);
        for task in tasks {
            let _ = task.await;
        }
        let _ = keeper.await;
    });
    stop.store(true, Ordering::Relaxed);
    for handle in tick_threads {
        let _ = handle.join();
    }
    let wall_s = started.elapsed().as_secs_f64();
    drop(rt);
    for (sender, writer) in logs {
        let dropped = sender.dropped();
        drop(sender);
        let _ = writer.join();
        if dropped > 0 {
            tracing::warn!("log: {dropped} records dropped (writer too slow)");
        }
    }
    let report = RunReport {
        vehicle_ticks: stats.ticks.load(Ordering::Relaxed),
        overruns: stats.overruns.load(Ordering::Relaxed),
        wall_s,
    };
    tracing::info!(
        "stopped after {} vehicle ticks, {} overruns",
        report.vehicle_ticks,
        report.overruns
    );
    Ok(report)
}

/// Kernel receive buffer of each link socket [bytes]: large enough that a burst of garbage
/// datagrams does not make the kernel drop the legitimate command behind it.
const RECV_BUFFER_BYTES: usize = 4 << 20;

/// A non-blocking UDP socket bound to `addr` with a large receive buffer, for tokio.
fn bind_udp(addr: SocketAddr) -> std::io::Result<UdpSocket> {
    let socket = socket2::Socket::new(socket2::Domain::for_address(addr), socket2::Type::DGRAM, None)?;
    // Best effort: the kernel caps it at net.core.rmem_max.
    let _ = socket.set_recv_buffer_size(RECV_BUFFER_BYTES);
    socket.set_nonblocking(true)?;
    socket.bind(&addr.into())?;
    UdpSocket::from_std(socket.into())
}
