//! The benchmarks that run the autopilot itself: in this process (speed-up, scale, ACK latency)
//! or as a child process (start-up).

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use super::autopilot::{loopback_run, InProcess};
use super::client::BenchClient;
use super::{ms, percentile, resident_kib, BenchError, BenchOptions, Latency, Trial, REALTIME_FACTOR};
use crate::control::ControllerKind;
use crate::mav::{MavCmd, MavResult};
use crate::runtime::{Pace, RunConfig};

/// How long each send of a command is waited for; the client sends it up to
/// `client::COMMAND_ATTEMPTS` times before the benchmark gives up on it.
const COMMAND_TIMEOUT: Duration = Duration::from_secs(1);
const NAN: f32 = f32::NAN;

/// `count` vehicles at `pace` in this process, sending all telemetry to `gcs`.
fn start(options: &BenchOptions, count: usize, pace: Pace, gcs: SocketAddr) -> Result<InProcess, BenchError> {
    let any = SocketAddr::from(([127, 0, 0, 1], 0));
    InProcess::start(RunConfig {
        bind_gcs: any,
        bind_api: any,
        gcs,
        api: gcs,
        count,
        pace,
        ..RunConfig::single(options.airframe.clone(), ControllerKind::Geometric, 1)
    })
}

fn bind_client() -> Result<(BenchClient, SocketAddr), BenchError> {
    let io = |source| BenchError::Io {
        what: "bench ground station",
        source,
    };
    let client = BenchClient::bind().map_err(io)?;
    let addr = client.local_addr().map_err(io)?;
    Ok((client, addr))
}

/// NAV_TAKEOFF to 2 m and ARM for every vehicle.
fn take_off_all(client: &mut BenchClient, vehicles: &[(SocketAddr, u8)]) -> Result<(), BenchError> {
    for &(addr, sysid) in vehicles {
        client.heartbeat(addr);
        let takeoff = [NAN, NAN, NAN, NAN, NAN, NAN, NAN];
        client
            .command(addr, sysid, MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff, COMMAND_TIMEOUT)
            .ok_or(BenchError::Silent("NAV_TAKEOFF"))?;
        let arm = [1.0, NAN, NAN, NAN, NAN, NAN, NAN];
        client
            .command(addr, sysid, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, arm, COMMAND_TIMEOUT)
            .ok_or(BenchError::Silent("ARM"))?;
    }
    Ok(())
}

/// Simulated seconds per wall second of one flying vehicle at `--speedup max`.
pub(super) fn speedup_max_factor(options: &BenchOptions) -> Result<f64, BenchError> {
    let (mut client, addr) = bind_client()?;
    let autopilot = start(options, 1, Pace::Max, addr)?;
    take_off_all(&mut client, &autopilot.vehicles())?;
    let drain = client.drain().map_err(|source| BenchError::Io {
        what: "bench ground station",
        source,
    })?;
    std::thread::sleep(Duration::from_secs_f64(options.window_s));
    let report = autopilot.finish()?;
    drop(drain);
    Ok(report.vehicle_ticks as f64 * 1e-3 / report.wall_s.max(1e-9))
}

/// One trial: `count` flying vehicles at 1× for the window.
fn realtime_trial(options: &BenchOptions, count: usize) -> Result<Trial, BenchError> {
    let before_kib = resident_kib();
    let (mut client, addr) = bind_client()?;
    let autopilot = start(options, count, Pace::Speedup(1.0), addr)?;
    take_off_all(&mut client, &autopilot.vehicles())?;
    let drain = client.drain().map_err(|source| BenchError::Io {
        what: "bench ground station",
        source,
    })?;
    let window = Instant::now();
    std::thread::sleep(Duration::from_secs_f64(options.window_s));
    let during_kib = resident_kib();
    let received = drain.received();
    let window_s = window.elapsed().as_secs_f64();
    let report = autopilot.finish()?;
    drop(drain);
    let memory = match (before_kib, during_kib) {
        (Some(a), Some(b)) => (b - a).max(0.0) / count as f64,
        _ => 0.0,
    };
    Ok(Trial {
        count,
        realtime_factor: report.vehicle_ticks as f64 * 1e-3 / (count as f64 * report.wall_s.max(1e-9)),
        overruns: report.overruns,
        telemetry_per_s: received as f64 / window_s.max(1e-9),
        memory_per_vehicle_kib: memory,
    })
}

/// Vehicles one process can fly (system ids 1–255).
const MAX_VEHICLES: usize = 255;

/// Doubles the vehicle count from `first_count` until real time fails (or `max_count`, at most
/// 255), then
/// halves the gap twice between the last count that held and the first that did not.
pub(super) fn realtime_trials(options: &BenchOptions) -> Result<Vec<Trial>, BenchError> {
    let mut trials = Vec::new();
    let mut good = 0;
    let mut bad = None;
    // System ids end at 255: one process (one MAVLink network) flies at most 255 vehicles.
    let cap = options.max_count.min(MAX_VEHICLES);
    let mut count = options.first_count.clamp(1, cap.max(1));
    loop {
        let trial = realtime_trial(options, count)?;
        trials.push(trial);
        if trial.realtime_factor < REALTIME_FACTOR {
            bad = Some(count);
            break;
        }
        good = count;
        if count >= cap {
            break;
        }
        count = (count * 2).min(cap);
    }
    if let Some(mut bad) = bad {
        for _ in 0..2 {
            let mid = (good + bad) / 2;
            if mid <= good || mid >= bad {
                break;
            }
            let trial = realtime_trial(options, mid)?;
            trials.push(trial);
            if trial.realtime_factor >= REALTIME_FACTOR {
                good = mid;
            } else {
                bad = mid;
            }
        }
    }
    Ok(trials)
}

/// Median time from spawning this executable's `run` to its first HEARTBEAT [ms].
pub(super) fn first_heartbeat_ms(options: &BenchOptions) -> Result<f64, BenchError> {
    let exe = std::env::current_exe().map_err(|source| BenchError::Io {
        what: "finding rotorpilot",
        source,
    })?;
    let mut samples = Vec::with_capacity(options.startups);
    for _ in 0..options.startups.max(1) {
        let (client, addr) = bind_client()?;
        let spawned = Instant::now();
        let mut child = loopback_run(&exe, addr, 5)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .map_err(|source| BenchError::Io {
                what: "spawning rotorpilot run",
                source,
            })?;
        let heard = client.first_heartbeat(Duration::from_secs(5));
        let _ = child.kill();
        let _ = child.wait();
        let heard_at = heard.ok_or(BenchError::Silent("no HEARTBEAT from rotorpilot run"))?;
        samples.push(ms(heard_at.duration_since(spawned)));
    }
    samples.sort_by(f64::total_cmp);
    Ok(percentile(&samples, 50.0))
}

/// Round trips of DO_CHANGE_SPEED to one vehicle at 1×: each goes through the tick thread (the
/// commander applies it at the next tick boundary), and each speed differs, so no repeat is
/// answered from the duplicate cache.
pub(super) fn command_ack_latency(options: &BenchOptions) -> Result<Latency, BenchError> {
    let (mut client, addr) = bind_client()?;
    let autopilot = start(options, 1, Pace::Speedup(1.0), addr)?;
    let (vehicle, sysid) = autopilot
        .vehicles()
        .first()
        .copied()
        .ok_or(BenchError::Silent("no vehicle"))?;
    client.heartbeat(vehicle);
    let mut samples = Vec::with_capacity(options.acks);
    for k in 0..options.acks {
        let speed = 5.0 + 0.001 * k as f32;
        let params = [NAN, speed, NAN, NAN, NAN, NAN, NAN];
        let (result, rtt) = client
            .command(vehicle, sysid, MavCmd::MAV_CMD_DO_CHANGE_SPEED, params, COMMAND_TIMEOUT)
            .ok_or(BenchError::Silent("DO_CHANGE_SPEED"))?;
        if result != MavResult::MAV_RESULT_ACCEPTED {
            return Err(BenchError::Silent("DO_CHANGE_SPEED was not accepted"));
        }
        samples.push(ms(rtt));
        std::thread::sleep(Duration::from_millis(2));
    }
    autopilot.finish()?;
    samples.sort_by(f64::total_cmp);
    Ok(Latency {
        p50_ms: percentile(&samples, 50.0),
        p99_ms: percentile(&samples, 99.0),
        max_ms: samples.last().copied().unwrap_or(0.0),
        samples: samples.len(),
    })
}
