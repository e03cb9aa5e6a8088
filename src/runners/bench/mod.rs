//! `rotorpilot bench`: the speed and scale figures of issue 5, measured in one run (runtime
//! layer: clocks, threads, sockets).
//!
//! - headless ticks per second of one flying vehicle per control law, estimator on;
//! - the real-time factor of one flying vehicle at `--speedup max` with its MAVLink links up;
//! - the largest number of flying vehicles that holds real time (factor ≥ 0.99) with their
//!   default telemetry read by one ground-station socket, and the memory per vehicle;
//! - the time from spawning `rotorpilot run` to its first HEARTBEAT;
//! - the COMMAND_ACK round trip over loopback (p50/p99) of commands that pass the tick thread;
//! - what the ULog flight log costs `fly` and `sim` (speed with / without, bytes per second),
//!   and what `run`'s default-profile flight log adds to a tick at real time (alone:
//!   [`logging_only`], `rotorpilot bench --logging`);
//! - how a sweep's runs per second scale from one worker to one per core.

pub mod autopilot;
pub mod client;
mod logging;

pub use logging::LoggingCost;
mod runs;
mod sweep_scaling;

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::airframe::AirframeSource;
use crate::commander::Request;
use crate::control::ControllerKind;
use crate::guidance::Home;
use crate::lockstep::SetupError;
use crate::runtime::vehicle::Vehicle;
use crate::runtime::RuntimeError;
use crate::sitl::SensorModel;

/// The real-time factor a vehicle count must hold to count as real time.
pub const REALTIME_FACTOR: f64 = 0.99;

/// What to measure and for how long.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Airframe of every vehicle.
    pub airframe: AirframeSource,
    /// Headless ticks timed per control law.
    pub headless_ticks: u64,
    /// Wall time of each real-time trial and of the `max` run [s].
    pub window_s: f64,
    /// Largest vehicle count tried.
    pub max_count: usize,
    /// Smallest vehicle count tried first (doubled until real time fails).
    pub first_count: usize,
    /// Start-up measurements (median reported).
    pub startups: usize,
    /// COMMAND_ACK round trips.
    pub acks: usize,
    /// Unlogged/logged pairs of `fly` and `sim` runs timed for the logging cost.
    pub log_pairs: usize,
    /// Simulated time of each of those runs [s].
    pub log_sim_s: f64,
    /// One-worker/all-core pairs of sweep passes timed.
    pub sweep_pairs: usize,
    /// Simulated time of each run of the benchmark's sweep [s].
    pub sweep_sim_s: f64,
}

impl BenchOptions {
    /// The full measurement (about a minute and a half).
    pub fn full(airframe: AirframeSource) -> Self {
        Self {
            airframe,
            headless_ticks: 500_000,
            window_s: 5.0,
            max_count: 1600,
            first_count: 25,
            startups: 5,
            acks: 1000,
            log_pairs: 7,
            log_sim_s: 40.0,
            sweep_pairs: 5,
            sweep_sim_s: 10.0,
        }
    }

    /// A few seconds' smoke run (the figures are rough).
    pub fn quick(airframe: AirframeSource) -> Self {
        Self {
            airframe,
            headless_ticks: 20_000,
            window_s: 0.5,
            max_count: 4,
            first_count: 2,
            startups: 2,
            acks: 50,
            log_pairs: 1,
            log_sim_s: 2.0,
            sweep_pairs: 1,
            sweep_sim_s: 0.5,
        }
    }
}

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The airframe, flight core or plant was refused.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A socket, thread or child process failed.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// Cause.
        source: std::io::Error,
    },
    /// The autopilot process failed.
    #[error(transparent)]
    Runtime(#[from] RuntimeError),
    /// The autopilot did not answer.
    #[error("no answer: {0}")]
    Silent(&'static str),
    /// A headless run failed.
    #[error("{0}")]
    Failed(String),
}

/// One real-time trial.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Trial {
    /// Vehicles.
    pub count: usize,
    /// Achieved simulated seconds per wall second, per vehicle.
    pub realtime_factor: f64,
    /// Schedule rebases (missed more than 100 ms).
    pub overruns: u64,
    /// Telemetry datagrams the ground station received per second.
    pub telemetry_per_s: f64,
    /// Resident memory added by the vehicles, per vehicle [KiB].
    pub memory_per_vehicle_kib: f64,
}

/// Percentiles of the COMMAND_ACK round trip [ms].
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Latency {
    /// Median [ms].
    pub p50_ms: f64,
    /// 99th percentile [ms].
    pub p99_ms: f64,
    /// Largest [ms].
    pub max_ms: f64,
    /// Round trips measured.
    pub samples: usize,
}

/// Every figure of one bench run.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    /// Logical cores of this machine.
    pub cores: usize,
    /// CPU model (from /proc/cpuinfo, when readable).
    pub cpu: Option<String>,
    /// Headless ticks per second of one flying vehicle, per control law (estimator on), on the
    /// exact state.
    pub headless_ticks_per_s: BTreeMap<&'static str, f64>,
    /// The same for the geometric law on realistic sensors: the sensor suite and the
    /// navigation filter run every tick.
    pub headless_ticks_per_s_realistic: f64,
    /// Real-time factor of one flying vehicle at `--speedup max`, links up.
    pub speedup_max_factor: f64,
    /// Largest vehicle count that held real time (0 if none did).
    pub largest_realtime_count: usize,
    /// Every real-time trial, in the order run.
    pub trials: Vec<Trial>,
    /// Median time from spawning `rotorpilot run` to its first HEARTBEAT [ms].
    pub first_heartbeat_ms: f64,
    /// COMMAND_ACK round trip over loopback (DO_CHANGE_SPEED through the tick thread, 1×).
    pub command_ack: Latency,
    /// What the full-profile ULog costs `fly` and `sim`, and the default profile `run`.
    pub logging: LoggingCost,
    /// A sweep's runs per second on one worker and on every core.
    pub sweep: sweep_scaling::SweepScaling,
}

/// Runs every benchmark.
pub fn run(options: &BenchOptions) -> Result<BenchReport, BenchError> {
    let mut headless = BTreeMap::new();
    for kind in [
        ControllerKind::Geometric,
        ControllerKind::Hierarchical,
        ControllerKind::Passivity,
    ] {
        headless.insert(kind.name(), headless_ticks_per_s(options, kind, SensorModel::State)?);
    }
    let headless_ticks_per_s_realistic = headless_ticks_per_s(options, ControllerKind::Geometric, SensorModel::Suite)?;
    let speedup_max_factor = runs::speedup_max_factor(options)?;
    let trials = runs::realtime_trials(options)?;
    let largest_realtime_count = trials
        .iter()
        .filter(|t| t.realtime_factor >= REALTIME_FACTOR)
        .map(|t| t.count)
        .max()
        .unwrap_or(0);
    Ok(BenchReport {
        cores: std::thread::available_parallelism().map_or(1, usize::from),
        cpu: cpu_model(),
        headless_ticks_per_s: headless,
        headless_ticks_per_s_realistic,
        speedup_max_factor,
        largest_realtime_count,
        trials,
        first_heartbeat_ms: runs::first_heartbeat_ms(options)?,
        command_ack: runs::command_ack_latency(options)?,
        logging: logging::logging_cost(options)?,
        sweep: sweep_scaling::sweep_scaling(options)?,
    })
}

/// Only the logging figures ([`BenchReport::logging`]).
pub fn logging_only(options: &BenchOptions) -> Result<LoggingCost, BenchError> {
    logging::logging_cost(options)
}

/// Ticks per second of one vehicle climbing and hovering on `sensors`, with no sockets and no
/// pacing (with the sensor suite, once the filter is aligned and the vehicle may arm).
fn headless_ticks_per_s(options: &BenchOptions, kind: ControllerKind, sensors: SensorModel) -> Result<f64, BenchError> {
    let mut vehicle = Vehicle::new(&options.airframe, kind, Home::default(), sensors, 0, 1e-3)?;
    for _ in 0..10_000 {
        if vehicle.step().snapshot.nav.armable {
            break;
        }
    }
    vehicle.apply(Request::Takeoff { height_m: Some(2.0) });
    vehicle.apply(Request::Arm { force: false });
    for _ in 0..2_000 {
        vehicle.step();
    }
    let start = Instant::now();
    for _ in 0..options.headless_ticks {
        std::hint::black_box(vehicle.step());
    }
    Ok(options.headless_ticks as f64 / start.elapsed().as_secs_f64().max(1e-9))
}

/// The CPU model line of /proc/cpuinfo.
fn cpu_model() -> Option<String> {
    let text = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    text.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_owned())
}

/// Resident memory of this process [KiB] (Linux; `None` elsewhere).
fn resident_kib() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// `p`-th percentile (0–100) of sorted `values`.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * (sorted.len() - 1) as f64).round() as usize;
    sorted[rank.min(sorted.len() - 1)]
}

/// A wall-clock span as [ms].
fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl BenchReport {
    /// The report as the text table `rotorpilot bench` prints.
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "machine: {} cores, {}\n",
            self.cores,
            self.cpu.as_deref().unwrap_or("unknown CPU")
        );
        for (law, rate) in &self.headless_ticks_per_s {
            out += &format!(
                "headless ticks/s ({law}, estimator on): {rate:.0} ({:.0}x real time)\n",
                rate / 1000.0
            );
        }
        let rate = self.headless_ticks_per_s_realistic;
        out += &format!(
            "headless ticks/s (geometric, realistic sensors and navigation filter): {rate:.0} ({:.0}x real time)\n",
            rate / 1000.0
        );
        out += &format!(
            "real-time factor at --speedup max (1 vehicle, links up): {:.0}\n",
            self.speedup_max_factor
        );
        for t in &self.trials {
            out += &format!(
                "  {:>5} vehicles at 1x: factor {:.4}, {} overruns, {:.0} telemetry msgs/s to the GCS, {:.0} KiB/vehicle\n",
                t.count, t.realtime_factor, t.overruns, t.telemetry_per_s, t.memory_per_vehicle_kib
            );
        }
        out += &format!(
            "largest vehicle count at real time (factor >= {REALTIME_FACTOR}): {}\n",
            self.largest_realtime_count
        );
        out += &format!("first HEARTBEAT after spawn: {:.1} ms\n", self.first_heartbeat_ms);
        out += &format!(
            "COMMAND_ACK round trip: p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms ({} samples)\n",
            self.command_ack.p50_ms, self.command_ack.p99_ms, self.command_ack.max_ms, self.command_ack.samples
        );
        out += &self.logging.to_text();
        let s = &self.sweep;
        out += &format!(
            "sweep ({} runs of Ex. 4's designs): {:.1} runs/s on 1 worker, {:.1} runs/s on {} workers ({:.2}x)\n",
            s.runs, s.runs_per_s_one, s.runs_per_s_all, s.jobs, s.scaling
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_pick_ranks() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 50.0), 51.0);
        assert_eq!(percentile(&v, 99.0), 99.0);
        assert_eq!(percentile(&v, 100.0), 100.0);
        assert_eq!(percentile(&[], 50.0), 0.0);
    }

    #[test]
    fn headless_rate_is_measured_on_a_flying_vehicle() {
        let options = BenchOptions::quick(AirframeSource::resolve("quad_x").unwrap());
        let rate = headless_ticks_per_s(&options, ControllerKind::Geometric, SensorModel::State).unwrap();
        assert!(rate.is_finite() && rate > 0.0);
    }
}
