//! Raw TOML schema of a sweep file (`rotorpilot sweep SWEEP.toml`, docs/sweep.md §1). Unknown
//! fields are refused, so a typo is an error naming it.

use serde::Deserialize;

/// Top level of a sweep file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SweepFile {
    /// The base scenario, relative to the sweep file's directory.
    pub scenario: String,
    /// `[design]`: how the axes are combined (default: the full grid).
    pub design: Option<DesignSpec>,
    /// `[seeds]`: how many seeds each point is run with.
    pub seeds: Option<SeedsSpec>,
    /// The summary fields kept per run (default: all).
    pub metrics: Option<Vec<String>>,
    /// `[[axis]]` entries.
    #[serde(default)]
    pub axis: Vec<AxisSpec>,
}

/// `[design]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DesignSpec {
    /// `grid` (default), `random` or `latin_hypercube`.
    pub kind: Option<String>,
    /// Points drawn by `random` and `latin_hypercube`.
    pub samples: Option<usize>,
    /// Seed of the draws (default 0).
    pub seed: Option<u64>,
}

/// `[seeds]`: every point runs with seeds `first`, `first + 1`, … (`count` of them).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SeedsSpec {
    pub count: Option<u64>,
    pub first: Option<u64>,
}

/// `[[axis]]`: one scenario field and the values it takes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AxisSpec {
    /// Dotted path of the scenario field, with `[k]` for an array element:
    /// `estimator.order`, `initial.position[2]`.
    pub field: String,
    /// Further fields set to the same value (`kv[1]`, `kv[2]` with `kv[0]`).
    #[serde(default)]
    pub also: Vec<String>,
    /// Explicit values (any TOML values).
    pub values: Option<Vec<toml::Value>>,
    /// `[lo, hi]` in `steps` evenly spaced values, ends included (grid).
    pub range: Option<[f64; 2]>,
    /// Number of values of `range` (≥ 2).
    pub steps: Option<usize>,
    /// `[lo, hi]` drawn uniformly (random, Latin hypercube).
    pub uniform: Option<[f64; 2]>,
    /// Round the values of `range` or `uniform` to integers.
    #[serde(default)]
    pub integer: bool,
}
