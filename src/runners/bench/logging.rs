//! What the ULog flight log costs: `fly` and `sim` (homework Ex. 4's scenario, estimator on)
//! timed without a log and with every tick logged (the full profile), side by side. The runs
//! alternate (unlogged, logged, unlogged, …) so that a machine's drifting load falls on both; the
//! figure is the median of the per-pair speed ratios, and the bytes written per simulated second.
//! And what `run`'s default-profile flight log, written unasked, adds to a flying vehicle's tick
//! at real time: two vehicles as `run` flies them, one logging, stepped in alternating blocks.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{BenchError, BenchOptions};
use crate::commander::Request;
use crate::control::ControllerKind;
use crate::guidance::Home;
use crate::runners::fly::{fly, FlyOptions};
use crate::runners::scenario_run::simulate;
use crate::runtime::flight_log;
use crate::runtime::log_store::LogDir;
use crate::runtime::vehicle::Vehicle;
use crate::scenario::Scenario;
use crate::sitl::SensorModel;
use crate::ulog::Profile;

/// Wall time of one tick at real time [µs].
const REALTIME_TICK_US: f64 = 1000.0;

/// The Ex. 4 scenario `sim` is timed on.
const EX4: &str = include_str!("../../../scenarios/ex4_estimator.toml");

/// One program timed with and without its log.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LogCost {
    /// Median real-time factor without a log [-].
    pub unlogged_factor: f64,
    /// Median real-time factor with the full-profile ULog [-].
    pub logged_factor: f64,
    /// Median over the pairs of logged / unlogged speed [-].
    pub speed_ratio: f64,
    /// ULog bytes per simulated second.
    pub bytes_per_sim_s: f64,
}

/// What `run`'s default-profile flight log adds to a flying vehicle's tick.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct DefaultLogCost {
    /// Median tick without a log (realistic sensors and the navigation filter, `run`'s
    /// default) [µs].
    pub unlogged_tick_us: f64,
    /// Median tick with the default-profile flight log [µs].
    pub logged_tick_us: f64,
    /// Median over the block pairs of what the log adds, over the 1 ms a tick has at real
    /// time [-].
    pub share_of_realtime_tick: f64,
    /// Flight log bytes per simulated second of flight.
    pub bytes_per_sim_s: f64,
}

/// The cost for `fly` and `sim`, and of `run`'s default profile.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LoggingCost {
    /// `rotorpilot fly` (take-off and hover, no estimator).
    pub fly: LogCost,
    /// `rotorpilot sim` on homework Ex. 4's scenario (estimator on, every topic logged).
    pub sim: LogCost,
    /// `rotorpilot run`'s default-profile flight log.
    pub run_default: DefaultLogCost,
}

impl LoggingCost {
    /// The figures as lines of text.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        for (name, c) in [("fly", &self.fly), ("sim (Ex. 4)", &self.sim)] {
            out += &format!(
                "{name} with the full-profile ULog: {:.0}x real time vs {:.0}x without ({:.0} % of the speed), {:.0} KB per simulated second\n",
                c.logged_factor,
                c.unlogged_factor,
                100.0 * c.speed_ratio,
                c.bytes_per_sim_s / 1e3
            );
        }
        let d = &self.run_default;
        out += &format!(
            "run's default-profile flight log: a tick of {:.2} µs vs {:.2} µs without, {:.3} % of the 1 ms real-time tick, {:.1} KB per simulated second\n",
            d.logged_tick_us,
            d.unlogged_tick_us,
            100.0 * d.share_of_realtime_tick,
            d.bytes_per_sim_s / 1e3
        );
        out
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// Runs `run(log)` `pairs` times alternately without and with a log at `path`; each run returns
/// its real-time factor and simulated seconds.
fn compare(
    pairs: usize,
    path: &Path,
    mut run: impl FnMut(Option<&Path>) -> Result<(f64, f64), BenchError>,
) -> Result<LogCost, BenchError> {
    let (mut plain, mut logged, mut ratios, mut sizes) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..pairs.max(1) {
        let (a, _) = run(None)?;
        let (b, sim_s) = run(Some(path))?;
        let bytes = std::fs::metadata(path).map_err(|source| BenchError::Io {
            what: "reading the benchmark's log",
            source,
        })?;
        plain.push(a);
        logged.push(b);
        ratios.push(b / a.max(1e-9));
        sizes.push(bytes.len() as f64 / sim_s.max(1e-9));
    }
    Ok(LogCost {
        unlogged_factor: median(plain),
        logged_factor: median(logged),
        speed_ratio: median(ratios),
        bytes_per_sim_s: median(sizes),
    })
}

/// A scratch directory of this process for the logs.
fn scratch() -> Result<PathBuf, BenchError> {
    let dir = std::env::temp_dir().join(format!("rotorpilot-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| BenchError::Io {
        what: "creating the benchmark's log directory",
        source,
    })?;
    Ok(dir)
}

/// Times `fly` and `sim` with and without the ULog.
pub(super) fn logging_cost(options: &BenchOptions) -> Result<LoggingCost, BenchError> {
    let dir = scratch()?;
    let flight = |log: Option<&Path>| {
        let opts = FlyOptions {
            duration_s: options.log_sim_s,
            controller: ControllerKind::Geometric,
            ulog: log.map(Path::to_path_buf),
            ..FlyOptions::default()
        };
        let s = fly(&options.airframe, &opts).map_err(|e| BenchError::Failed(format!("fly: {e}")))?;
        Ok((s.real_time_factor, s.sim_time_s))
    };
    let fly_cost = compare(options.log_pairs, &dir.join("fly.ulg"), flight);
    let text = EX4.replace("duration = 40.0", &format!("duration = {:.3}", options.log_sim_s));
    let scn = Scenario::from_toml_str(&text, "ex4_estimator.toml", "ex4_estimator", &dir)
        .map_err(|e| BenchError::Failed(format!("the Ex. 4 scenario: {e}")))?;
    let run = |log: Option<&Path>| {
        let out = log.and_then(Path::parent).map(|d| d.join("sim"));
        let s = simulate(&scn, out.as_deref()).map_err(|e| BenchError::Failed(format!("sim: {e}")))?;
        if let Some(out) = out {
            std::fs::rename(out.join("run.ulg"), dir.join("sim.ulg")).map_err(|source| BenchError::Io {
                what: "moving the benchmark's log",
                source,
            })?;
        }
        Ok((s.real_time_factor, s.sim_time_s))
    };
    let sim_cost = compare(options.log_pairs, &dir.join("sim.ulg"), run);
    let run_default = default_log_cost(options, &dir.join("run"));
    let _ = std::fs::remove_dir_all(&dir);
    Ok(LoggingCost {
        fly: fly_cost?,
        sim: sim_cost?,
        run_default: run_default?,
    })
}

/// A vehicle as `run` flies it (realistic sensors), taken off and climbing.
fn flying_vehicle(
    options: &BenchOptions,
    log: Option<(flight_log::LogSender, Profile)>,
) -> Result<Vehicle, BenchError> {
    let mut vehicle = Vehicle::new(
        &options.airframe,
        ControllerKind::Geometric,
        Home::default(),
        SensorModel::Suite,
        0,
        1e-3,
    )?;
    if let Some((sender, profile)) = log {
        vehicle.set_log(sender, profile);
    }
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
    Ok(vehicle)
}

/// Wall time per tick of `ticks` ticks of `vehicle` [µs].
fn tick_us(vehicle: &mut Vehicle, ticks: u64) -> f64 {
    let start = std::time::Instant::now();
    for _ in 0..ticks {
        std::hint::black_box(vehicle.step());
    }
    start.elapsed().as_secs_f64() * 1e6 / ticks.max(1) as f64
}

/// Two vehicles flown alike, one writing `run`'s default-profile flight logs into `dir`, stepped
/// in alternating blocks of `log_sim_s`.
fn default_log_cost(options: &BenchOptions, dir: &Path) -> Result<DefaultLogCost, BenchError> {
    let io = |source| BenchError::Io {
        what: "the default-profile flight log",
        source,
    };
    let (sender, writer) = flight_log::start(None, Some(LogDir::at(&dir.join("log"))), None).map_err(io)?;
    let mut plain = flying_vehicle(options, None)?;
    let mut logged = flying_vehicle(options, Some((sender, Profile::Default)))?;
    let ticks = (options.log_sim_s * 1e3).round().max(1.0) as u64;
    let (mut without, mut with, mut added) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..options.log_pairs.max(1) {
        let a = tick_us(&mut plain, ticks);
        let b = tick_us(&mut logged, ticks);
        without.push(a);
        with.push(b);
        added.push((b - a) / REALTIME_TICK_US);
    }
    // The logged vehicle armed at its 2 000th tick or earlier: at least this much flight.
    let flight_s = logged.time_s() - 2.0;
    drop(logged);
    writer
        .finish()
        .map_err(|e| BenchError::Failed(format!("the default-profile flight log: {e}")))?;
    let mut bytes = 0;
    for date in std::fs::read_dir(dir.join("log")).map_err(io)?.flatten() {
        for file in std::fs::read_dir(date.path()).map_err(io)?.flatten() {
            bytes += file.metadata().map_err(io)?.len();
        }
    }
    Ok(DefaultLogCost {
        unlogged_tick_us: median(without),
        logged_tick_us: median(with),
        share_of_realtime_tick: median(added),
        bytes_per_sim_s: bytes as f64 / flight_s.max(1e-9),
    })
}
