//! The autopilot process (`rotorpilot run`): vehicles ticking at 1 kHz on dedicated threads and,
//! per vehicle, one tokio task serving its two MAVLink UDP links (GCS and API, PX4 SITL ports).
//! Runtime layer: clocks, sockets, threads, files; every decision is made by the pure modules
//! it calls (`mav::link` for the protocol, the vehicle's flight software for the rest).
//!
//! # Layout
//! - `mod.rs`: setting up the vehicles, their channels and sockets; running until shutdown.
//! - `config.rs`: what `run` is given, prints when ready, reports at the end, its errors.
//! - [`scheduler`]: the tick threads; [`pacer`]: their pace; [`vehicle`]: one vehicle's lockstep.
//! - [`link`]: the link task: sockets ↔ `mav::link::LinkMachine` ↔ the tick thread;
//!   `sockets.rs`: its two UDP sockets; [`impairment`]: `--link-loss` and its kin, the links
//!   made lossy on purpose.
//! - [`signing_store`], `signing_keeper.rs`: the `--signing-key` file and its timestamp.
//! - [`flight_log`]: the log writer thread (tlog and ULog files of `--log`, `sim`, `fly`).
//! - [`ulog_file`]: one ULog file for a whole headless run (`sim`, `fly`).
//! - [`ulog_stream`]: the tick thread's side of a ULog file.
//! - [`log_store`]: the flight logs in `DIR/log/`, written as `SDLOG_MODE` says, served over
//!   the log protocol and FTP; [`log_place`]: where `DIR` is (`--log` or the per-user default)
//!   and one vehicle's log set-up.

mod config;
pub mod flight_log;
pub mod impairment;
pub mod link;
pub mod log_place;
pub mod log_store;
pub mod pacer;
pub mod scheduler;
mod signing_keeper;
pub mod signing_store;
mod sockets;
pub mod ulog_file;
pub mod ulog_stream;
pub mod vehicle;

use std::future::Future;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::{mpsc, watch};

use crate::guidance::Home;
use crate::math::Vec3;
use crate::mav::ardupilot::copter_param_face::copter_file_param;
use crate::mav::ardupilot::copter_params::copter_defaults;
use crate::mav::identity::Personality;
use crate::mav::link::{LinkConfig, LinkMachine};
use crate::mav::logs::{LogStore, MemLogStore};
use crate::mav::signing::Signing;
use crate::mav::streams::LinkKind;
use crate::mav::translate::Identity;
use crate::telemetry::Snapshot;

pub use config::{Ready, RunConfig, RunReport, RuntimeError, VehicleLinkCounts, VehicleReady, DEFAULT_SPACING_M};
use flight_log::LogSender;
use impairment::Impairments;
use link::{LinkIo, SigningStatus};
pub use pacer::Pace;
use scheduler::{SchedulerStats, VehicleIo, VehicleSlot};
use signing_keeper::{signing_keeper, SigningSetup};
use signing_store::signing_now;
use sockets::LinkSockets;
use vehicle::Vehicle;

/// Bound of the request queue into the tick thread: commands are never dropped silently; when
/// it is full the link answers TEMPORARILY_REJECTED at once.
const INBOX_CAPACITY: usize = 256;
/// Bound of the event queue out of the tick thread (announcements only; dropped when full).
const EVENT_CAPACITY: usize = 64;
/// Bound of the log writer's announcements to the links (dropped when full).
const NOTICE_CAPACITY: usize = 8;

/// One vehicle's share of the process: its tick slot, its link machine and sockets, its log.
struct VehicleSetup {
    slot: VehicleSlot,
    ready: VehicleReady,
    machine: LinkMachine<SocketAddr>,
    io: LinkIo,
    log: Option<(LogSender, flight_log::LogWriter)>,
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
        config.sensors,
        config.seed.wrapping_add(i as u64),
        config.dt_s,
    )?;
    let personality = config.personality(i);
    if personality == Personality::ArduPilot {
        for (origin, name, value) in copter_defaults() {
            vehicle
                .set_param(name, value)
                .map_err(|e| RuntimeError::Personality(format!("ardupilot: {origin}: {e}")))?;
        }
    }
    for (origin, name, value) in &config.params {
        let refused = |e: String| RuntimeError::Params(format!("{origin}: {e}"));
        // ArduCopter's names too, for a vehicle presented as ArduCopter (docs/ardupilot.md §5.3).
        let (name, value) = match personality {
            Personality::ArduPilot => copter_file_param(vehicle.params(), name, *value)
                .map_err(refused)?
                .unwrap_or((name.as_str(), *value)),
            Personality::Px4 => (name.as_str(), *value),
        };
        vehicle.set_param(name, value).map_err(|e| refused(e.to_string()))?;
    }
    for failure in &config.rotor_failures {
        vehicle
            .schedule_rotor_failure(*failure)
            .map_err(RuntimeError::RotorFailure)?;
    }
    for failure in &config.sensor_failures {
        vehicle.schedule_sensor_failure(*failure);
    }
    let (notice_tx, notices) = mpsc::channel(NOTICE_CAPACITY);
    let announce: flight_log::Announce = Box::new(move |text| {
        let _ = notice_tx.try_send(text);
    });
    let place = config.log.as_ref();
    let vehicle_log = place
        .map(|p| log_place::open(p, (i, sysid, config.count), &mut vehicle, config.log_profile, announce))
        .transpose()?;
    let (log_dir, logs, log, tlog): (_, Box<dyn LogStore>, _, _) = match vehicle_log {
        Some(v) => (Some(v.dir), Box::new(v.store), v.writer, v.tlog),
        None => (None, Box::new(MemLogStore::default()), None, false),
    };
    let port = |addr| nth_port(addr, i).ok_or_else(|| too_many("ports end at 65535"));
    let (bind_gcs, bind_api, api) = (port(config.bind_gcs)?, port(config.bind_api)?, port(config.api)?);
    let sockets =
        LinkSockets::bind(rt, bind_gcs, bind_api).map_err(|(addr, source)| RuntimeError::Bind { addr, source })?;
    let (gcs_bind, api_bind) = sockets.local_addrs();
    let ready = VehicleReady {
        sysid,
        autopilot: personality,
        gcs_bind,
        api_bind,
        gcs: config.gcs.to_string(),
        api: api.to_string(),
        log_dir: log_dir.map(|d| d.display().to_string()),
    };
    let (inbox_tx, inbox_rx) = mpsc::channel(INBOX_CAPACITY);
    let initial = Arc::new(Snapshot::initial(home));
    let (snapshot_tx, snapshot_rx) = watch::channel(Arc::clone(&initial));
    let (event_tx, event_rx) = mpsc::channel(EVENT_CAPACITY);
    let (replies_to, replies) = mpsc::unbounded_channel();
    let start = std::time::Instant::now();
    let machine = LinkMachine::new(LinkConfig {
        identity: Identity::autopilot(sysid, vehicle.rotor_count()).with_personality(personality),
        links: vec![(LinkKind::Gcs, config.gcs), (LinkKind::Api, api)],
        params: vehicle.shared_params(),
        snapshot: initial,
        signing: Signing::new(signing.key.clone(), signing.timestamp),
        signing_epoch: signing_now(),
        key_store: signing.store.is_some(),
        record_received: tlog,
        logs,
    });
    let io = LinkIo {
        sockets,
        start,
        vehicle: inbox_tx,
        replies_to,
        replies,
        snapshot: snapshot_rx,
        events: event_rx,
        notices,
        shutdown: shutdown.clone(),
        log: log.as_ref().filter(|_| tlog).map(|(s, _)| s.clone()),
        store: signing.store.clone(),
        signing: Arc::new(SigningStatus::default()),
        impair: config.link_impairment.as_ref().map(|c| Impairments::new(c, i)),
    };
    let vehicle_io = VehicleIo {
        inbox: inbox_rx,
        snapshot: snapshot_tx,
        events: event_tx,
    };
    Ok(VehicleSetup {
        slot: VehicleSlot::new(vehicle, vehicle_io),
        ready,
        machine,
        io,
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
    // Polled once before anything is announced, so its signal handlers are installed: a SIGTERM
    // right after the ready line then shuts down cleanly (the signing timestamp saved) instead
    // of killing the process with the signal's default action.
    let mut shutdown = Box::pin(shutdown);
    let stopped_already = rt.block_on(std::future::poll_fn(|cx| {
        std::task::Poll::Ready(shutdown.as_mut().poll(cx).is_ready())
    }));
    let given = config.personalities.len();
    if given != 1 && given != config.count.max(1) {
        return Err(RuntimeError::Personality(format!(
            "names {given} autopilots for {} vehicles: give one for all or one per vehicle",
            config.count.max(1)
        )));
    }
    let signing = SigningSetup::load(config.signing_key.clone())?;
    let mut setups = Vec::with_capacity(config.count.max(1));
    for i in 0..config.count.max(1) {
        setups.push(setup_vehicle(&config, i, &rt, &shutdown_rx, &signing)?);
    }
    // The keeper's last save waits for the links to stop, so no frame is sent after it.
    let (links_stopped_tx, links_stopped_rx) = watch::channel(false);
    let keeper = rt.spawn(signing_keeper(
        setups.iter().map(|s| s.io.signing.clone()).collect(),
        signing.store.clone(),
        signing.timestamp,
        links_stopped_rx,
    ));
    let stop = Arc::new(AtomicBool::new(false));
    let stats = Arc::new(SchedulerStats::default());
    let dt = Duration::from_secs_f64(config.dt_s);
    let threads = tick_thread_count(setups.len());
    let mut groups: Vec<Vec<VehicleSlot>> = (0..threads).map(|_| Vec::new()).collect();
    let mut vehicles = Vec::with_capacity(setups.len());
    let mut tasks: Vec<(u8, _)> = Vec::new();
    let mut logs = Vec::new();
    for (i, setup) in setups.into_iter().enumerate() {
        groups[i % threads].push(setup.slot);
        tasks.push((setup.ready.sysid, rt.spawn(link::serve(setup.machine, setup.io))));
        vehicles.push(setup.ready);
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

    let link_impairment = rt.block_on(async move {
        // A future that completed must not be polled again.
        if !stopped_already {
            shutdown.await;
        }
        let _ = shutdown_tx.send(true);
        let mut counts = Vec::new();
        for (sysid, task) in tasks {
            let links = task.await.unwrap_or_default();
            if !links.is_empty() {
                counts.push(VehicleLinkCounts { sysid, links });
            }
        }
        let _ = links_stopped_tx.send(true);
        let _ = keeper.await;
        counts
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
        if let Err(e) = writer.finish() {
            tracing::error!("log: {e}");
        }
        if dropped > 0 {
            tracing::warn!("log: {dropped} records dropped (writer too slow)");
        }
    }
    for v in &link_impairment {
        for l in &v.links {
            tracing::info!(
                "link impairment, sysid {} {}: to the vehicle {} datagrams, {} dropped, {} duplicated, {} delayed; \
                 from it {} datagrams, {} dropped, {} duplicated, {} delayed",
                v.sysid,
                l.link,
                l.up.datagrams,
                l.up.dropped,
                l.up.duplicated,
                l.up.delayed,
                l.down.datagrams,
                l.down.dropped,
                l.down.duplicated,
                l.down.delayed
            );
        }
    }
    let report = RunReport {
        event: "stopped",
        vehicle_ticks: stats.ticks.load(Ordering::Relaxed),
        overruns: stats.overruns.load(Ordering::Relaxed),
        wall_s,
        link_impairment,
    };
    tracing::info!(
        "stopped after {} vehicle ticks, {} overruns",
        report.vehicle_ticks,
        report.overruns
    );
    Ok(report)
}
