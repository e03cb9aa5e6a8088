//! `rotorpilot sweep SWEEP.toml --out DIR`: every run of a sweep (docs/sweep.md) flown by the
//! `sim` engine on worker threads, its metrics kept as a row of `DIR/results.parquet`, with
//! `DIR/sweep.json` beside it (docs/sweep.md §4). Runtime layer: it reads the sweep's files,
//! spreads runs over threads and writes the results; the sweep's maths is in [`crate::sweep`].
//!
//! # Layout
//! - `mod.rs`: loading a sweep, flying one run into its row, flying a range of runs.
//! - [`engine`]: the worker threads, shared with `rotorpilot montecarlo`.
//! - [`parquet`]: the results table as a Parquet file.
//! - [`manifest`]: `sweep.json` and `--plan`.

pub mod engine;
pub mod manifest;
pub mod parquet;

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::runners::scenario_run::simulate;
use crate::scenario::Scenario;
use crate::sweep::metrics::{flatten, keep, select, Scalar};
use crate::sweep::results::{columns, RunRow, Status};
use crate::sweep::{Run, Sweep, SweepError};
use manifest::{Machine, Manifest, ResultsInfo};

/// Summary fields that measure the machine, not the run: never metrics, so a run's row depends
/// on its scenario and seed only.
const WALL_CLOCK_FIELDS: [&str; 2] = ["wall_time_s", "real_time_factor"];

/// A sweep ready to fly: the checked file, its base scenario's table and its runs.
pub struct LoadedSweep {
    /// The sweep.
    pub sweep: Sweep,
    /// Every run, in order.
    pub runs: Vec<Run>,
    /// The sweep file as given.
    pub path: PathBuf,
    base: toml::Table,
    base_name: String,
    base_dir: PathBuf,
    inputs: Vec<String>,
}

/// The absolute form of `p` (as given when it cannot be resolved).
fn absolute(p: &Path) -> String {
    std::fs::canonicalize(p)
        .unwrap_or_else(|_| p.to_path_buf())
        .display()
        .to_string()
}

impl LoadedSweep {
    /// Reads and checks the sweep at `path` and its base scenario, and lists the runs.
    pub fn load(path: &Path) -> Result<Self, SweepError> {
        let sweep = Sweep::load(path)?;
        let scenario = &sweep.scenario;
        let origin = scenario.display().to_string();
        let text = std::fs::read_to_string(scenario).map_err(|e| SweepError::Read {
            path: format!("{} (scenario of {})", origin, path.display()),
            message: e.to_string(),
        })?;
        let base: toml::Table = toml::from_str(&text).map_err(|e| SweepError::Syntax {
            origin: origin.clone(),
            message: e.to_string(),
        })?;
        Scenario::check_fields(&text, &origin).map_err(|e| SweepError::Invalid(e.to_string()))?;
        let base_dir = scenario.parent().unwrap_or(Path::new(".")).to_path_buf();
        let mut inputs = vec![absolute(path), absolute(scenario)];
        if let Some(airframe) = base
            .get("airframe")
            .and_then(|a| a.get("path"))
            .and_then(toml::Value::as_str)
        {
            inputs.push(absolute(&base_dir.join(airframe)));
        }
        sweep.check_axis_fields(&base, &path.display().to_string())?;
        let runs = sweep.runs()?;
        Ok(Self {
            base_name: scenario
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            sweep,
            runs,
            path: path.to_path_buf(),
            base,
            base_dir,
            inputs,
        })
    }

    /// The manifest without results (`--plan`).
    pub fn plan(&self) -> Manifest {
        let points = self.runs.last().map_or(0, |r| r.point + 1);
        let files = [absolute(&self.path), absolute(&self.sweep.scenario)];
        Manifest::plan(&self.sweep, files, self.runs.len(), points, self.inputs.clone())
    }

    /// Flies run `index` into its row, the metrics of its summary kept by `choose` (which may
    /// refuse the sweep's metrics list).
    fn fly<C>(&self, index: usize, choose: C) -> Result<RunRow, SweepError>
    where
        C: Fn(Vec<(String, Option<Scalar>)>, Option<&[String]>) -> Result<Vec<(String, Scalar)>, SweepError>,
    {
        let run = &self.runs[index];
        let scenario = self
            .sweep
            .scenario_table(&self.base, run)
            .map_err(|e| e.to_string())
            .and_then(|t| toml::to_string(&t).map_err(|e| e.to_string()))
            .and_then(|text| {
                let origin = self.sweep.scenario.display().to_string();
                Scenario::from_toml_str(&text, &origin, &self.base_name, &self.base_dir).map_err(|e| {
                    if e.field.is_empty() {
                        e.reason
                    } else {
                        format!("{}: {}", e.field, e.reason)
                    }
                })
            });
        let scenario = match scenario {
            Ok(s) => s,
            Err(why) => return Ok(RunRow::of(index, run, Status::Refused, Some(why))),
        };
        let summary = simulate(&scenario, None)
            .map_err(|e| e.to_string())
            .and_then(|s| serde_json::to_value(&s).map_err(|e| e.to_string()));
        let summary = match summary {
            Ok(summary) => summary,
            Err(why) => return Ok(RunRow::of(index, run, Status::Failed, Some(why))),
        };
        let mut all = flatten(&summary);
        all.retain(|(name, _)| !WALL_CLOCK_FIELDS.contains(&name.as_str()));
        let mut row = RunRow::of(index, run, Status::Ok, None);
        row.metrics = choose(all, self.sweep.metrics.as_deref())
            .map_err(|e| SweepError::Invalid(format!("{}: {e}", self.path.display())))?;
        Ok(row)
    }

    /// Flies the runs in `range` on `jobs` threads and writes `out/results.parquet` and
    /// `out/sweep.json`; the sweep's metrics list is checked against the first run that flies
    /// before the others start. Progress goes to stderr about once a second.
    pub fn fly_range(&self, range: Range<usize>, jobs: usize, out: &Path) -> Result<Manifest, SweepError> {
        let io = |path: &Path, e: String| SweepError::Read {
            path: path.display().to_string(),
            message: e,
        };
        std::fs::create_dir_all(out).map_err(|e| io(out, e.to_string()))?;
        let started = Instant::now();
        let total = range.len();
        let mut rows: Vec<RunRow> = Vec::with_capacity(total);
        let mut next = range.start;
        while next < range.end {
            let row = self.fly(next, select)?;
            next += 1;
            let flew = row.status == Status::Ok;
            rows.push(row);
            if flew {
                break;
            }
        }
        let last_print = Mutex::new(Instant::now());
        let first_done = rows.len();
        let progress = |done: usize| {
            let Ok(mut last) = last_print.lock() else { return };
            if last.elapsed() >= Duration::from_secs(1) {
                *last = Instant::now();
                let rate = (first_done + done) as f64 / started.elapsed().as_secs_f64();
                eprintln!("sweep: {}/{total} runs, {rate:.1} runs/s", first_done + done);
            }
        };
        let rest: Vec<usize> = (next..range.end).collect();
        let flown = engine::map_guarded(&rest, jobs, &progress, |&i| {
            self.fly(i, |all, wanted| Ok(keep(all, wanted)))
        })?;
        for (&i, result) in rest.iter().zip(flown) {
            rows.push(result.unwrap_or_else(|panic| RunRow::of(i, &self.runs[i], Status::Panicked, Some(panic))));
        }
        let wall_time_s = started.elapsed().as_secs_f64();
        let results_path = out.join("results.parquet");
        parquet::write(&results_path, &columns(&self.sweep.axes, &rows)).map_err(|e| io(&results_path, e))?;
        let count = |s: Status| rows.iter().filter(|r| r.status == s).count();
        let mut manifest = self.plan();
        manifest.results = Some(ResultsInfo {
            range: [range.start, range.end],
            jobs,
            ok: count(Status::Ok),
            refused: count(Status::Refused),
            failed: count(Status::Failed),
            panicked: count(Status::Panicked),
            wall_time_s,
            runs_per_s: total as f64 / wall_time_s.max(1e-9),
            machine: Machine::this(),
        });
        let manifest_path = out.join("sweep.json");
        let text = serde_json::to_string_pretty(&manifest).map_err(|e| io(&manifest_path, e.to_string()))?;
        std::fs::write(&manifest_path, text + "\n").map_err(|e| io(&manifest_path, e.to_string()))?;
        Ok(manifest)
    }
}
