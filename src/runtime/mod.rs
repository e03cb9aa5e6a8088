//! The autopilot process (`rotorpilot run`): one vehicle ticking at 1 kHz on its own thread and
//! two MAVLink UDP links (GCS and API, PX4 SITL ports) served by tokio. Runtime layer: clocks,
//! sockets, threads; every decision is made by the pure modules it calls.

pub mod flight_log;
pub mod link;
pub mod scheduler;
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
use crate::commander::{FlightMode, LandedState, MissionState};
use crate::control::ControllerKind;
use crate::math::Vec3;
use crate::mav::streams::LinkKind;
use crate::mav::translate::Identity;
use crate::navigation::Home;
use crate::telemetry::Snapshot;

use link::{run_link, LinkContext};
use scheduler::{SchedulerIo, SchedulerStats};
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
    /// System id (1–255).
    pub system_id: u8,
    /// GCS link: local bind address and the remote that always gets telemetry.
    pub bind_gcs: SocketAddr,
    /// Remote GCS address.
    pub gcs: SocketAddr,
    /// API link bind address.
    pub bind_api: SocketAddr,
    /// Remote API address.
    pub api: SocketAddr,
    /// Geodetic home.
    pub home: Home,
    /// Sensor-noise seed.
    pub seed: u64,
    /// Tick [s].
    pub dt_s: f64,
    /// `--log DIR`: tlog and 1 kHz CSV.
    pub log_dir: Option<std::path::PathBuf>,
    /// Parameter values applied before start (`--params FILE`): (where, name, value).
    pub params: Vec<(String, String, f64)>,
}

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
    /// The log directory could not be written.
    #[error("--log {dir}: {source}")]
    Log {
        /// Directory.
        dir: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The tokio runtime could not start.
    #[error("runtime: {0}")]
    Runtime(std::io::Error),
}

/// The machine-readable start-up line (printed as JSON on stdout).
#[derive(Debug, Clone, Serialize)]
pub struct Ready {
    /// Always "ready".
    pub event: &'static str,
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

/// Runs the autopilot until `shutdown` completes; `on_ready` receives the bound addresses once
/// the sockets are open and the tick thread runs.
pub fn run(
    config: RunConfig,
    shutdown: impl Future<Output = ()> + Send + 'static,
    on_ready: impl FnOnce(&Ready),
) -> Result<(), RuntimeError> {
    let mut vehicle = Vehicle::new(
        &config.airframe,
        config.controller,
        config.home,
        config.seed,
        config.dt_s,
    )?;
    for (origin, name, value) in &config.params {
        vehicle
            .set_param(name, *value)
            .map_err(|e| RuntimeError::Params(format!("{origin}: {e}")))?;
    }
    let log = match &config.log_dir {
        Some(dir) => {
            let (sender, writer) =
                flight_log::start(dir, vehicle.rotor_count()).map_err(|source| RuntimeError::Log {
                    dir: dir.display().to_string(),
                    source,
                })?;
            vehicle.set_log(sender.clone());
            Some((sender, writer))
        }
        None => None,
    };
    let identity = Identity::autopilot(config.system_id, vehicle.rotor_count());
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(RuntimeError::Runtime)?;
    let bind = |addr: SocketAddr| {
        let _guard = rt.enter();
        bind_udp(addr).map_err(|source| RuntimeError::Bind { addr, source })
    };
    let gcs_socket = bind(config.bind_gcs)?;
    let api_socket = bind(config.bind_api)?;
    let local = |s: &UdpSocket| s.local_addr().map(|a| a.to_string()).unwrap_or_default();
    let ready = Ready {
        event: "ready",
        sysid: config.system_id,
        gcs_bind: local(&gcs_socket),
        api_bind: local(&api_socket),
        gcs: config.gcs.to_string(),
        api: config.api.to_string(),
    };

    let (inbox_tx, inbox_rx) = mpsc::channel(INBOX_CAPACITY);
    let (snapshot_tx, snapshot_rx) = watch::channel(initial_snapshot(config.home));
    let (params_tx, params_rx) = watch::channel(Arc::new(vehicle.params().clone()));
    let (event_tx, mut event_rx) = mpsc::channel(EVENT_CAPACITY);
    let (announce_tx, _) = broadcast::channel(EVENT_CAPACITY);
    let (shutdown_tx, shutdown_rx) = watch::channel(false);
    let mission_store = Arc::new(std::sync::Mutex::new(Vec::new()));
    let stop = Arc::new(AtomicBool::new(false));
    let stats = Arc::new(SchedulerStats::default());
    let dt = Duration::from_secs_f64(config.dt_s);
    let io = SchedulerIo {
        inbox: inbox_rx,
        snapshot: snapshot_tx,
        params: params_tx,
        events: event_tx,
        stop: stop.clone(),
        stats: stats.clone(),
    };
    let tick_thread = std::thread::Builder::new()
        .name("rotorpilot-tick".into())
        .spawn(move || scheduler::run(vehicle, dt, io))
        .map_err(RuntimeError::Runtime)?;

    let link = |socket, remote, kind| {
        let ctx = LinkContext {
            identity,
            inbox: inbox_tx.clone(),
            snapshot: snapshot_rx.clone(),
            params: params_rx.clone(),
            announcements: announce_tx.subscribe(),
            shutdown: shutdown_rx.clone(),
            mission_store: mission_store.clone(),
            log: log.as_ref().map(|(s, _)| s.clone()),
            kind,
        };
        rt.spawn(run_link(socket, remote, ctx))
    };
    let gcs_task = link(gcs_socket, config.gcs, LinkKind::Gcs);
    let api_task = link(api_socket, config.api, LinkKind::Api);
    let fan_out = rt.spawn(async move {
        while let Some(e) = event_rx.recv().await {
            let _ = announce_tx.send(e);
        }
    });
    on_ready(&ready);

    rt.block_on(async move {
        shutdown.await;
        let _ = shutdown_tx.send(true);
        let _ = gcs_task.await;
        let _ = api_task.await;
    });
    stop.store(true, Ordering::Relaxed);
    let _ = tick_thread.join();
    fan_out.abort();
    drop(rt);
    if let Some((sender, writer)) = log {
        let dropped = sender.dropped();
        drop(sender);
        let _ = writer.join();
        if dropped > 0 {
            tracing::warn!("log: {dropped} records dropped (writer too slow)");
        }
    }
    tracing::info!(
        "stopped after {} ticks, {} overruns",
        stats.ticks.load(Ordering::Relaxed),
        stats.overruns.load(Ordering::Relaxed)
    );
    Ok(())
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

fn initial_snapshot(home: Home) -> Snapshot {
    Snapshot {
        t_s: 0.0,
        pos_w: Vec3::zeros(),
        vel_w: Vec3::zeros(),
        eta: Vec3::zeros(),
        omega_b: Vec3::zeros(),
        accel_b: Vec3::zeros(),
        armed: false,
        mode: FlightMode::Loiter,
        landed: LandedState::OnGround,
        home,
        home_w: Vec3::zeros(),
        mission_seq: 0,
        mission_total: 0,
        mission_state: MissionState::NoMission,
        estimate: None,
        setpoint: None,
        eta_desired: None,
        thrust_fraction: 0.0,
        rotor_speeds: [0.0; crate::airframe::MAX_ROTORS],
        rotor_count: 0,
        rotor_max_rad_s: 1.0,
    }
}
