//! `sweep.json`: what a sweep ran (its files, axes, design, seeds and metrics), with which
//! version, on which machine, and how it went (docs/sweep.md §4). `rotorpilot sweep --plan`
//! prints the same object without the results part.

use serde::Serialize;

use crate::sweep::{AxisValues, Design, Sweep};

/// The manifest of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct Manifest {
    /// rotorpilot's version.
    pub version: &'static str,
    /// The sweep file (absolute).
    pub sweep: String,
    /// Its base scenario (absolute).
    pub scenario: String,
    /// Runs in the whole sweep.
    pub runs: usize,
    /// Points of the design.
    pub points: usize,
    /// Seeds each point runs with.
    pub seeds: SeedRange,
    /// The design.
    pub design: DesignInfo,
    /// The axes, in column order.
    pub axes: Vec<AxisInfo>,
    /// The summary fields kept (`None`: all).
    pub metrics: Option<Vec<String>>,
    /// Every file the sweep reads (absolute): the sweep, its scenario, the scenario's airframe
    /// file when it names one. A campaign ships these to its workers.
    pub inputs: Vec<String>,
    /// How the runs went (absent from `--plan`).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub results: Option<ResultsInfo>,
}

/// `first … first + count − 1`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SeedRange {
    /// First seed.
    pub first: u64,
    /// Seeds per point.
    pub count: u64,
}

/// The design as written.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct DesignInfo {
    /// `grid`, `random` or `latin_hypercube`.
    pub kind: &'static str,
    /// Points drawn (random designs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    /// Seed of the draws (random designs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

/// One axis as swept.
#[derive(Debug, Clone, Serialize)]
pub struct AxisInfo {
    /// The scenario field (the column's name).
    pub field: String,
    /// Further fields set to the same value.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<String>,
    /// Its values (a list or a range).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<toml::Value>>,
    /// Its interval (drawn).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uniform: Option<[f64; 2]>,
    /// Drawn values rounded to integers.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub integer: bool,
}

/// What a run of the sweep (or of a range of its runs) did.
#[derive(Debug, Clone, Serialize)]
pub struct ResultsInfo {
    /// The runs flown: `[first, end)` of the whole sweep's.
    pub range: [usize; 2],
    /// Worker threads.
    pub jobs: usize,
    /// Rows by status.
    pub ok: usize,
    /// Runs whose values the scenario refused.
    pub refused: usize,
    /// Runs whose simulation returned an error.
    pub failed: usize,
    /// Runs that panicked.
    pub panicked: usize,
    /// Wall-clock time of the runs [s].
    pub wall_time_s: f64,
    /// Runs per wall-clock second [1/s].
    pub runs_per_s: f64,
    /// The machine.
    pub machine: Machine,
}

/// Where a sweep ran.
#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    /// Host name.
    pub hostname: String,
    /// Operating system.
    pub os: &'static str,
    /// CPU architecture.
    pub arch: &'static str,
    /// Logical CPUs.
    pub cpus: usize,
}

impl Machine {
    /// This machine.
    pub fn this() -> Self {
        let hostname = std::fs::read_to_string("/etc/hostname")
            .ok()
            .or_else(|| std::env::var("HOSTNAME").ok())
            .map(|h| h.trim().to_string())
            .unwrap_or_default();
        Self {
            hostname,
            os: std::env::consts::OS,
            arch: std::env::consts::ARCH,
            cpus: std::thread::available_parallelism().map_or(1, usize::from),
        }
    }
}

impl Manifest {
    /// The plan of `sweep`, whose sweep and scenario files are `[sweep, scenario]` (`runs` in
    /// all, over `points` points), reading `inputs`.
    pub fn plan(sweep: &Sweep, files: [String; 2], runs: usize, points: usize, inputs: Vec<String>) -> Self {
        let [sweep_path, scenario] = files;
        let design = match sweep.design {
            Design::Grid => DesignInfo {
                kind: "grid",
                samples: None,
                seed: None,
            },
            Design::Random { samples, seed } => DesignInfo {
                kind: "random",
                samples: Some(samples),
                seed: Some(seed),
            },
            Design::LatinHypercube { samples, seed } => DesignInfo {
                kind: "latin_hypercube",
                samples: Some(samples),
                seed: Some(seed),
            },
        };
        let axes = sweep
            .axes
            .iter()
            .map(|a| match &a.values {
                AxisValues::List(v) => AxisInfo {
                    field: a.field.clone(),
                    also: a.also.clone(),
                    values: Some(v.clone()),
                    uniform: None,
                    integer: false,
                },
                AxisValues::Uniform { lo, hi, integer } => AxisInfo {
                    field: a.field.clone(),
                    also: a.also.clone(),
                    values: None,
                    uniform: Some([*lo, *hi]),
                    integer: *integer,
                },
            })
            .collect();
        Self {
            version: env!("CARGO_PKG_VERSION"),
            sweep: sweep_path,
            scenario,
            runs,
            points,
            seeds: SeedRange {
                first: sweep.seeds.start,
                count: sweep.seeds.end - sweep.seeds.start,
            },
            design,
            axes,
            metrics: sweep.metrics.clone(),
            inputs,
            results: None,
        }
    }
}
