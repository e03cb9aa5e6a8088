//! The results table of a sweep (docs/sweep.md §4): one row per run, columns in a fixed order
//! (`run`, `point`, `seed`, the axes, `status`, `error`, the metrics by name) whose types
//! depend on the axes and on the summary's fields only, so a table built from any subset of the
//! runs (a shard) has the same columns and types. Pure.

use std::collections::BTreeMap;

use super::metrics::Scalar;
use super::{Axis, AxisValues, Point, Run};

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// It flew; its metrics are the summary's.
    Ok,
    /// The scenario refused the run's values (a field or value it cannot take).
    Refused,
    /// The simulation returned an error.
    Failed,
    /// The simulation panicked (a bug, counted instead of ending the sweep).
    Panicked,
}

impl Status {
    /// The name in the `status` column.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Refused => "refused",
            Self::Failed => "failed",
            Self::Panicked => "panicked",
        }
    }
}

/// One run's row.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Index of the run in the whole sweep.
    pub run: usize,
    /// Index of its point.
    pub point: usize,
    /// Its seed.
    pub seed: u64,
    /// The axes' values, in axis order.
    pub values: Point,
    /// How it ended.
    pub status: Status,
    /// Why it did not fly (`None` when it did).
    pub error: Option<String>,
    /// The metrics kept.
    pub metrics: Vec<(String, Scalar)>,
}

impl RunRow {
    /// The row of run `index` of a sweep, `run`, with `status` and `error` and no metrics yet.
    pub fn of(index: usize, run: &Run, status: Status, error: Option<String>) -> Self {
        Self {
            run: index,
            point: run.point,
            seed: run.seed,
            values: run.values.clone(),
            status,
            error,
            metrics: Vec::new(),
        }
    }
}

/// The type of a column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnKind {
    /// 64-bit integers.
    Int,
    /// 64-bit floats.
    Float,
    /// Flags.
    Bool,
    /// UTF-8 text.
    Text,
}

/// One column: a name, a type and a cell per row (`None`: null).
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Column name.
    pub name: String,
    /// Its type.
    pub kind: ColumnKind,
    /// One cell per row, every present cell of `kind`.
    pub cells: Vec<Option<Scalar>>,
}

/// The fixed columns before the axes and between the axes and the metrics.
const FIXED: [&str; 5] = ["run", "point", "seed", "status", "error"];

/// The table of `rows` (in their order) for a sweep over `axes`.
pub fn columns(axes: &[Axis], rows: &[RunRow]) -> Vec<Column> {
    // Indices and seeds as 64-bit integers: a seed above 2^63 − 1 (montecarlo's `--seed`) is
    // stored as its two's complement, as a u64's bits read as an i64.
    let int = |name: &str, f: &dyn Fn(&RunRow) -> u64| Column {
        name: name.into(),
        kind: ColumnKind::Int,
        cells: rows.iter().map(|r| Some(Scalar::Int(f(r) as i64))).collect(),
    };
    let text = |name: &str, f: &dyn Fn(&RunRow) -> Option<String>| Column {
        name: name.into(),
        kind: ColumnKind::Text,
        cells: rows.iter().map(|r| f(r).map(Scalar::Text)).collect(),
    };
    let mut out = vec![
        int("run", &|r| r.run as u64),
        int("point", &|r| r.point as u64),
        int("seed", &|r| r.seed),
    ];
    for (j, axis) in axes.iter().enumerate() {
        let kind = axis_kind(&axis.values);
        out.push(Column {
            name: axis.field.clone(),
            kind,
            cells: rows
                .iter()
                .map(|r| r.values.get(j).map(|v| axis_cell(v, kind)))
                .collect(),
        });
    }
    out.push(text("status", &|r| Some(r.status.name().to_string())));
    out.push(text("error", &|r| r.error.clone()));
    let mut metrics: BTreeMap<&str, Vec<Option<&Scalar>>> = BTreeMap::new();
    for (i, row) in rows.iter().enumerate() {
        for (name, value) in &row.metrics {
            metrics.entry(name).or_insert_with(|| vec![None; rows.len()])[i] = Some(value);
        }
    }
    for (name, cells) in metrics {
        let kind = metric_kind(cells.iter().flatten().copied());
        let taken = FIXED.contains(&name) || axes.iter().any(|a| a.field == name);
        out.push(Column {
            name: if taken {
                format!("summary.{name}")
            } else {
                name.to_string()
            },
            kind,
            cells: cells.into_iter().map(|c| c.map(|s| converted(s, kind))).collect(),
        });
    }
    out
}

/// An axis's column type, from its definition alone.
fn axis_kind(values: &AxisValues) -> ColumnKind {
    match values {
        AxisValues::Uniform { integer: true, .. } => ColumnKind::Int,
        AxisValues::Uniform { .. } => ColumnKind::Float,
        AxisValues::List(list) => {
            let all = |f: fn(&toml::Value) -> bool| list.iter().all(f);
            if all(|v| v.is_integer()) {
                ColumnKind::Int
            } else if all(|v| v.is_integer() || v.is_float()) {
                ColumnKind::Float
            } else if all(toml::Value::is_bool) {
                ColumnKind::Bool
            } else {
                ColumnKind::Text
            }
        }
    }
}

/// An axis value as a cell of `kind`.
fn axis_cell(v: &toml::Value, kind: ColumnKind) -> Scalar {
    let scalar = match v {
        toml::Value::Integer(i) => Scalar::Int(*i),
        toml::Value::Float(x) => Scalar::Float(*x),
        toml::Value::Boolean(b) => Scalar::Bool(*b),
        toml::Value::String(s) => Scalar::Text(s.clone()),
        other => Scalar::Text(other.to_string()),
    };
    converted(&scalar, kind)
}

/// A metric column's type: the one type of its cells, floats for integers mixed with floats,
/// text for any other mixture.
fn metric_kind<'a>(cells: impl Iterator<Item = &'a Scalar>) -> ColumnKind {
    let mut kind: Option<ColumnKind> = None;
    for cell in cells {
        let k = match cell {
            Scalar::Int(_) => ColumnKind::Int,
            Scalar::Float(_) => ColumnKind::Float,
            Scalar::Bool(_) => ColumnKind::Bool,
            Scalar::Text(_) => ColumnKind::Text,
        };
        kind = Some(match (kind, k) {
            (None, k) => k,
            (Some(a), b) if a == b => a,
            (Some(ColumnKind::Int | ColumnKind::Float), ColumnKind::Int | ColumnKind::Float) => ColumnKind::Float,
            _ => ColumnKind::Text,
        });
    }
    kind.unwrap_or(ColumnKind::Text)
}

/// `s` as a cell of `kind` (integers widened to floats; anything else as text).
fn converted(s: &Scalar, kind: ColumnKind) -> Scalar {
    match (s, kind) {
        (Scalar::Int(i), ColumnKind::Int) => Scalar::Int(*i),
        (Scalar::Int(i), ColumnKind::Float) => Scalar::Float(*i as f64),
        (Scalar::Float(x), ColumnKind::Float) => Scalar::Float(*x),
        (Scalar::Bool(b), ColumnKind::Bool) => Scalar::Bool(*b),
        (Scalar::Text(t), _) => Scalar::Text(t.clone()),
        (Scalar::Int(i), _) => Scalar::Text(i.to_string()),
        (Scalar::Float(x), _) => Scalar::Text(x.to_string()),
        (Scalar::Bool(b), _) => Scalar::Text(b.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(run: usize, order: i64, metrics: Vec<(&str, Scalar)>) -> RunRow {
        RunRow {
            run,
            point: run / 2,
            seed: run as u64 % 2,
            values: vec![toml::Value::Integer(order)],
            status: if metrics.is_empty() {
                Status::Refused
            } else {
                Status::Ok
            },
            error: metrics.is_empty().then(|| "estimator.order: too high".to_string()),
            metrics: metrics.into_iter().map(|(n, s)| (n.to_string(), s)).collect(),
        }
    }

    fn axes() -> Vec<Axis> {
        vec![Axis {
            field: "estimator.order".into(),
            also: Vec::new(),
            values: AxisValues::List(vec![toml::Value::Integer(1), toml::Value::Float(2.5)]),
        }]
    }

    #[test]
    fn columns_come_in_a_fixed_order_with_types_from_the_axes_and_the_metrics() {
        let rows = vec![
            row(
                0,
                1,
                vec![
                    ("max_tilt_deg", Scalar::Float(3.0)),
                    ("exit", Scalar::Text("complete".into())),
                ],
            ),
            row(1, 2, vec![]),
            row(2, 1, vec![("max_tilt_deg", Scalar::Int(4)), ("run", Scalar::Int(9))]),
        ];
        let table = columns(&axes(), &rows);
        let names: Vec<&str> = table.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "run",
                "point",
                "seed",
                "estimator.order",
                "status",
                "error",
                "exit",
                "max_tilt_deg",
                "summary.run"
            ]
        );
        let kinds: Vec<ColumnKind> = table.iter().map(|c| c.kind).collect();
        use ColumnKind::*;
        assert_eq!(kinds, [Int, Int, Int, Float, Text, Text, Text, Float, Int]);
        assert_eq!(
            table[3].cells[0],
            Some(Scalar::Float(1.0)),
            "an integer in a float axis is widened"
        );
        assert_eq!(table[4].cells[1], Some(Scalar::Text("refused".into())));
        assert_eq!(
            table[5].cells,
            [None, Some(Scalar::Text("estimator.order: too high".into())), None]
        );
        assert_eq!(
            table[7].cells,
            [Some(Scalar::Float(3.0)), None, Some(Scalar::Float(4.0))]
        );
        assert!(table.iter().all(|c| c.cells.len() == 3));
    }

    #[test]
    fn a_shard_has_the_axis_types_of_the_whole_sweep() {
        let shard = columns(&axes(), &[row(0, 1, vec![])]);
        assert_eq!(
            shard[3].kind,
            ColumnKind::Float,
            "typed by the axis, not by the shard's values"
        );
        let uniform = Axis {
            field: "initial.position[2]".into(),
            also: Vec::new(),
            values: AxisValues::Uniform {
                lo: 0.0,
                hi: 1.0,
                integer: true,
            },
        };
        assert_eq!(columns(&[uniform], &[])[3].kind, ColumnKind::Int);
    }

    #[test]
    fn mixed_metric_values_fall_back_to_text() {
        let kind = metric_kind([Scalar::Bool(true), Scalar::Int(1)].iter());
        assert_eq!(kind, ColumnKind::Text);
        assert_eq!(converted(&Scalar::Bool(true), kind), Scalar::Text("true".into()));
    }
}
