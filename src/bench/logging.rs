//! What the ULog flight log costs: `fly` and `sim` (homework Ex. 4's scenario, estimator on)
//! timed without a log and with every tick logged (the full profile), side by side. The runs
//! alternate (unlogged, logged, unlogged, …) so that a machine's drifting load falls on both; the
//! figure is the median of the per-pair speed ratios, and the bytes written per simulated second.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{BenchError, BenchOptions};
use crate::control::ControllerKind;
use crate::fly::{fly, FlyOptions};
use crate::scenario::Scenario;
use crate::sim::simulate;

/// The Ex. 4 scenario `sim` is timed on.
const EX4: &str = include_str!("../../scenarios/ex4_estimator.toml");

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

/// The cost for `fly` and `sim`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LoggingCost {
    /// `rotorpilot fly` (take-off and hover, no estimator).
    pub fly: LogCost,
    /// `rotorpilot sim` on homework Ex. 4's scenario (estimator on, every topic logged).
    pub sim: LogCost,
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
    let _ = std::fs::remove_dir_all(&dir);
    Ok(LoggingCost {
        fly: fly_cost?,
        sim: sim_cost?,
    })
}
