//! Sweeps: a base scenario, axes over any of its fields, a design that combines them, and seeds
//! (docs/sweep.md). This module reads and checks a sweep file, lists its runs and names their
//! metrics; running them belongs to the runtime layer. Pure.
//!
//! # Layout
//!
//! - `spec`: the raw TOML schema of a sweep file.
//! - [`design`]: grid, random and Latin-hypercube points of the axes.
//! - [`field`]: scenario fields by dotted path, set in the base scenario's table.
//! - [`metrics`]: a run's summary flattened into named scalars, and the ones a sweep keeps.
//! - [`results`]: the rows of the runs as typed columns in a fixed order.

pub mod design;
pub mod field;
pub mod metrics;
pub mod results;
mod spec;

use std::path::{Path, PathBuf};

use thiserror::Error;

pub use design::{Axis, AxisValues, Design, Point};

/// What is wrong with a sweep file.
#[derive(Debug, Error, PartialEq)]
pub enum SweepError {
    /// The file could not be read.
    #[error("{path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// Not valid TOML, or not a sweep file's schema (the message names the line and field).
    #[error("{origin}: {message}")]
    Syntax {
        /// The file.
        origin: String,
        /// The parser's message.
        message: String,
    },
    /// A value the sweep cannot take (the message names the field).
    #[error("{0}")]
    Invalid(String),
}

/// A checked sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// The base scenario file.
    pub scenario: PathBuf,
    /// The swept fields.
    pub axes: Vec<Axis>,
    /// How they combine.
    pub design: Design,
    /// Seeds each point runs with.
    pub seeds: std::ops::Range<u64>,
    /// The summary fields kept per run; `None`: all.
    pub metrics: Option<Vec<String>>,
}

/// One run of a sweep: the point's index, its values (in axis order) and the seed.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Index of the point in the design.
    pub point: usize,
    /// The axes' values.
    pub values: Point,
    /// The scenario's seed.
    pub seed: u64,
}

impl Sweep {
    /// Reads and checks the sweep file at `path`.
    pub fn load(path: &Path) -> Result<Self, SweepError> {
        let text = std::fs::read_to_string(path).map_err(|e| SweepError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Self::from_toml_str(&text, &path.display().to_string(), dir)
    }

    /// Checks the sweep in `text` (named `origin` in errors); the scenario path is relative to
    /// `base_dir`.
    pub fn from_toml_str(text: &str, origin: &str, base_dir: &Path) -> Result<Self, SweepError> {
        let file: spec::SweepFile = toml::from_str(text).map_err(|e| SweepError::Syntax {
            origin: origin.to_string(),
            message: e.to_string(),
        })?;
        let mut axes: Vec<Axis> = Vec::with_capacity(file.axis.len());
        for (i, a) in file.axis.iter().enumerate() {
            let axis = checked_axis(a)
                .map_err(|why| SweepError::Invalid(format!("{origin}: axis {} (`{}`): {why}", i + 1, a.field)))?;
            let swept: Vec<&String> = axes.iter().flat_map(Axis::fields).collect();
            let mine: Vec<&String> = axis.fields().collect();
            for (k, f) in mine.iter().enumerate() {
                if swept.contains(f) || mine[..k].contains(f) {
                    return Err(SweepError::Invalid(format!("{origin}: field `{f}` swept twice")));
                }
            }
            axes.push(axis);
        }
        let design = checked_design(file.design.as_ref())
            .map_err(|why| SweepError::Invalid(format!("{origin}: [design]: {why}")))?;
        let seeds = file.seeds.as_ref();
        let count = seeds.and_then(|s| s.count).unwrap_or(1);
        if count == 0 {
            return Err(SweepError::Invalid(format!(
                "{origin}: [seeds] count must be at least 1"
            )));
        }
        let first = seeds.and_then(|s| s.first).unwrap_or(0);
        let seeds = first
            ..first
                .checked_add(count)
                .ok_or_else(|| SweepError::Invalid(format!("{origin}: [seeds] run past u64")))?;
        if file.metrics.as_ref().is_some_and(Vec::is_empty) {
            return Err(SweepError::Invalid(format!(
                "{origin}: metrics is empty (leave it out to keep all)"
            )));
        }
        let sweep = Self {
            scenario: base_dir.join(&file.scenario),
            axes,
            design,
            seeds,
            metrics: file.metrics,
        };
        design::check(&sweep.axes, sweep.design).map_err(|e| SweepError::Invalid(format!("{origin}: {e}")))?;
        Ok(sweep)
    }

    /// Every run, point by point and seed by seed within a point.
    pub fn runs(&self) -> Result<Vec<Run>, SweepError> {
        let points = design::points(&self.axes, self.design)?;
        Ok(points
            .into_iter()
            .enumerate()
            .flat_map(|(point, values)| {
                self.seeds.clone().map(move |seed| Run {
                    point,
                    values: values.clone(),
                    seed,
                })
            })
            .collect())
    }

    /// The scenario of `run`: `base` with every axis's field set to the run's value and
    /// `seed` set to the run's seed.
    pub fn scenario_table(&self, base: &toml::Table, run: &Run) -> Result<toml::Table, SweepError> {
        let mut table = base.clone();
        for (axis, value) in self.axes.iter().zip(&run.values) {
            for f in axis.fields() {
                field::set(&mut table, f, value.clone())?;
            }
        }
        let seed = i64::try_from(run.seed)
            .map_err(|_| SweepError::Invalid(format!("seed {} beyond TOML's integers", run.seed)))?;
        table.insert("seed".into(), toml::Value::Integer(seed));
        Ok(table)
    }
}

impl Sweep {
    /// Refuses an axis whose fields the scenario file does not have: each axis's fields set to
    /// its first value in `base` (the base scenario's table) must give a scenario file's schema
    /// (`origin` names the sweep file in errors). Values are not checked (a run may be refused
    /// for its values, an unstable estimator design, say); free-form tables (airframe overrides,
    /// controller gains) are checked only when a run is built.
    pub fn check_axis_fields(&self, base: &toml::Table, origin: &str) -> Result<(), SweepError> {
        for (i, axis) in self.axes.iter().enumerate() {
            let mut table = base.clone();
            let first = design::first_value(&axis.values);
            for f in axis.fields() {
                field::set(&mut table, f, first.clone())?;
            }
            let refused = |why: String| {
                SweepError::Invalid(format!(
                    "{origin}: axis {} (`{}`): the scenario refuses it: {why}",
                    i + 1,
                    axis.field
                ))
            };
            let text = toml::to_string(&table).map_err(|e| refused(e.to_string()))?;
            crate::scenario::Scenario::check_fields(&text, "").map_err(|e| refused(e.reason))?;
        }
        Ok(())
    }
}

/// An axis from its spec: exactly one of `values`, `range` (with `steps`) or `uniform`.
fn checked_axis(a: &spec::AxisSpec) -> Result<Axis, String> {
    for f in std::iter::once(&a.field).chain(&a.also) {
        field::check(f).map_err(|e| e.to_string())?;
    }
    let bounds = |[lo, hi]: [f64; 2], name: &str| {
        if lo.is_finite() && hi.is_finite() && lo <= hi {
            Ok((lo, hi))
        } else {
            Err(format!("{name} must be two finite numbers, low first"))
        }
    };
    let values = match (&a.values, a.range, a.uniform) {
        (Some(v), None, None) if v.is_empty() => return Err("values is empty".into()),
        (Some(v), None, None) => AxisValues::List(v.clone()),
        (None, Some(r), None) => {
            let (lo, hi) = bounds(r, "range")?;
            let steps = a
                .steps
                .ok_or("range needs steps (the number of values, ends included)")?;
            if steps < 2 {
                return Err(format!("steps is {steps}; a range needs at least 2"));
            }
            AxisValues::List(design::range_values(lo, hi, steps, a.integer))
        }
        (None, None, Some(u)) => {
            let (lo, hi) = bounds(u, "uniform")?;
            AxisValues::Uniform {
                lo,
                hi,
                integer: a.integer,
            }
        }
        _ => return Err("give exactly one of values, range or uniform".into()),
    };
    if a.steps.is_some() && a.range.is_none() {
        return Err("steps belongs to a range".into());
    }
    Ok(Axis {
        field: a.field.clone(),
        also: a.also.clone(),
        values,
    })
}

/// The design from its spec (default: the full grid).
fn checked_design(d: Option<&spec::DesignSpec>) -> Result<Design, String> {
    let Some(d) = d else { return Ok(Design::Grid) };
    let sampled = |samples: Option<usize>| match samples {
        Some(n) if n > 0 => Ok(n),
        _ => Err("samples (the number of points drawn, at least 1) is needed".to_string()),
    };
    let seed = d.seed.unwrap_or(0);
    match d.kind.as_deref().unwrap_or("grid") {
        "grid" if d.samples.is_none() && d.seed.is_none() => Ok(Design::Grid),
        "grid" => Err("a grid takes no samples or seed".into()),
        "random" => Ok(Design::Random {
            samples: sampled(d.samples)?,
            seed,
        }),
        "latin_hypercube" => Ok(Design::LatinHypercube {
            samples: sampled(d.samples)?,
            seed,
        }),
        other => Err(format!("kind `{other}`: expected grid, random or latin_hypercube")),
    }
}

#[cfg(test)]
mod tests;
