//! How a sweep scales over the cores (issue 18's target: at least 1.6 times the one-worker rate
//! on two cores): homework Ex. 4's estimator designs flown by `rotorpilot sweep`'s engine on one
//! worker and on one per core, alternately, so that a drifting load falls on both; the figure
//! is the median of the per-pair ratios.

use serde::Serialize;

use super::{BenchError, BenchOptions};
use crate::runners::sweep_run::LoadedSweep;

/// The Ex. 4 scenario the sweep varies.
const EX4: &str = include_str!("../../../scenarios/ex4_estimator.toml");

/// Runs per second on one worker and on every core.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SweepScaling {
    /// Runs in the benchmark's sweep.
    pub runs: usize,
    /// Worker threads of the parallel passes (one per core).
    pub jobs: usize,
    /// Median runs per second on one worker [1/s].
    pub runs_per_s_one: f64,
    /// Median runs per second on `jobs` workers [1/s].
    pub runs_per_s_all: f64,
    /// Median over the pairs of the `jobs`-worker rate over the one-worker rate [-].
    pub scaling: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// Flies the sweep (orders 1–13 × passband edges 2 and 5 rad/s, `options.sweep_sim_s` each)
/// `options.sweep_pairs` times on one worker and on every core.
pub fn sweep_scaling(options: &BenchOptions) -> Result<SweepScaling, BenchError> {
    let io = |what: &'static str| move |source| BenchError::Io { what, source };
    let dir = std::env::temp_dir().join(format!("rotorpilot-bench-sweep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(io("creating the sweep's directory"))?;
    let scenario = EX4.replace("duration = 40.0", &format!("duration = {}", options.sweep_sim_s));
    std::fs::write(dir.join("ex4.toml"), scenario).map_err(io("writing the sweep's scenario"))?;
    let sweep = "scenario = \"ex4.toml\"\nmetrics = [\"exit\"]\n\
                 [[axis]]\nfield = \"estimator.order\"\nrange = [1, 13]\nsteps = 13\ninteger = true\n\
                 [[axis]]\nfield = \"estimator.wp\"\nvalues = [2.0, 5.0]\n";
    std::fs::write(dir.join("sweep.toml"), sweep).map_err(io("writing the sweep"))?;
    let loaded = LoadedSweep::load(&dir.join("sweep.toml")).map_err(|e| BenchError::Failed(e.to_string()))?;
    let jobs = std::thread::available_parallelism().map_or(1, usize::from);
    let runs = loaded.runs.len();
    let rate = |jobs: usize| -> Result<f64, BenchError> {
        let manifest = loaded
            .fly_range(0..runs, jobs, &dir.join("out"))
            .map_err(|e| BenchError::Failed(e.to_string()))?;
        Ok(manifest.results.map_or(0.0, |r| r.runs_per_s))
    };
    let (mut one, mut all, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..options.sweep_pairs.max(1) {
        let a = rate(1)?;
        let b = rate(jobs)?;
        one.push(a);
        all.push(b);
        ratios.push(b / a.max(1e-9));
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(SweepScaling {
        runs,
        jobs,
        runs_per_s_one: median(one),
        runs_per_s_all: median(all),
        scaling: median(ratios),
    })
}
