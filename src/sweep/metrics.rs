//! A run's metrics: its `summary.json` flattened into named scalars (docs/sweep.md §3), nested
//! objects joined by dots and array elements indexed (`estimate.tracking.rms_force_error_n[2]`),
//! and the subset a sweep keeps. Pure.

use serde_json::Value;

use super::SweepError;
use crate::suggest::did_you_mean;

/// One scalar of a summary, or one value of an axis.
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar {
    /// A number.
    Float(f64),
    /// A whole number.
    Int(i64),
    /// A flag.
    Bool(bool),
    /// A name (exit status, controller…).
    Text(String),
}

/// Every scalar of `summary` by its flattened name, the keys of each object in name order;
/// a `null` (an estimate that is off, a time never reached) is `None`.
pub fn flatten(summary: &Value) -> Vec<(String, Option<Scalar>)> {
    let mut out = Vec::new();
    walk(summary, String::new(), &mut out);
    out
}

fn walk(v: &Value, name: String, out: &mut Vec<(String, Option<Scalar>)>) {
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                let child_name = if name.is_empty() {
                    k.clone()
                } else {
                    format!("{name}.{k}")
                };
                walk(child, child_name, out);
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                walk(child, format!("{name}[{i}]"), out);
            }
        }
        Value::Number(n) => {
            let m = n
                .as_i64()
                .map_or_else(|| Scalar::Float(n.as_f64().unwrap_or(f64::NAN)), Scalar::Int);
            out.push((name, Some(m)));
        }
        Value::Bool(b) => out.push((name, Some(Scalar::Bool(*b)))),
        Value::String(s) => out.push((name, Some(Scalar::Text(s.clone())))),
        Value::Null => out.push((name, None)),
    }
}

/// Whether the metric `name` is kept by the selection `wanted`: it is a wanted name or lies under
/// one (`final_position_error_m[1]` under `final_position_error_m`, `estimate.order` under
/// `estimate`).
fn is_under(name: &str, wanted: &str) -> bool {
    name == wanted
        || name
            .strip_prefix(wanted)
            .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
}

/// The present metrics of `all` kept by `wanted` (every one when `None`), without checking that
/// each wanted name matched: a run with its estimator off simply has no `estimate` metrics.
pub fn keep(all: Vec<(String, Option<Scalar>)>, wanted: Option<&[String]>) -> Vec<(String, Scalar)> {
    all.into_iter()
        .filter(|(name, _)| wanted.is_none_or(|wanted| wanted.iter().any(|w| is_under(name, w))))
        .filter_map(|(name, value)| Some((name, value?)))
        .collect()
}

/// [`keep`], refusing a wanted name that names no field of `all` with the closest one: the
/// check of a sweep's metrics list against the first run that flies. A name under a `null`
/// (`estimate.mass_kg` of a run with the estimator off) is a field.
pub fn select(
    all: Vec<(String, Option<Scalar>)>,
    wanted: Option<&[String]>,
) -> Result<Vec<(String, Scalar)>, SweepError> {
    for w in wanted.unwrap_or_default() {
        let known =
            |(name, value): &(String, Option<Scalar>)| is_under(name, w) || (value.is_none() && is_under(w, name));
        if !all.iter().any(known) {
            return Err(SweepError::Invalid(format!(
                "metric `{w}` is not in the run's summary{}",
                did_you_mean(w, all.iter().map(|(n, _)| n.as_str()))
            )));
        }
    }
    Ok(keep(all, wanted))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary() -> Value {
        serde_json::json!({
            "exit": "complete",
            "ticks": 5000,
            "final_position_error_m": [0.1, -0.2, 0.0],
            "max_tilt_deg": 12.5,
            "compensation": true,
            "estimate": {"order": 2, "tracking": {"rms_force_error_n": [0.02, 0.04, 0.01]}},
            "events": []
        })
    }

    #[test]
    fn a_summary_flattens_to_named_scalars() {
        let all = flatten(&summary());
        let names: Vec<&str> = all.iter().map(|(n, _)| n.as_str()).collect();
        assert!(names.contains(&"final_position_error_m[1]"));
        assert!(names.contains(&"estimate.tracking.rms_force_error_n[2]"));
        assert!(all.contains(&("exit".into(), Some(Scalar::Text("complete".into())))));
        assert!(all.contains(&("ticks".into(), Some(Scalar::Int(5000)))));
        assert!(all.contains(&("compensation".into(), Some(Scalar::Bool(true)))));
        assert!(all.contains(&("max_tilt_deg".into(), Some(Scalar::Float(12.5)))));
        assert_eq!(
            flatten(&serde_json::json!({"estimate": null})),
            [("estimate".to_string(), None)]
        );
    }

    #[test]
    fn a_selection_keeps_what_is_under_each_name_and_refuses_unknown_ones() {
        let wanted = ["final_position_error_m".to_string(), "exit".to_string()];
        let kept = select(flatten(&summary()), Some(&wanted)).unwrap();
        let names: Vec<&str> = kept.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "exit",
                "final_position_error_m[0]",
                "final_position_error_m[1]",
                "final_position_error_m[2]"
            ]
        );
        let err = select(flatten(&summary()), Some(&["max_tilt_dg".to_string()])).unwrap_err();
        assert!(
            err.to_string()
                .contains("metric `max_tilt_dg` is not in the run's summary"),
            "{err}"
        );
        assert!(err.to_string().contains("did you mean max_tilt_deg?"), "{err}");
        assert_eq!(
            select(flatten(&summary()), None).unwrap().len(),
            flatten(&summary()).len()
        );
        let off = flatten(&serde_json::json!({"exit": "complete", "estimate": null, "settling_time_s": null}));
        let wanted = [
            "estimate.mass_kg".to_string(),
            "settling_time_s".to_string(),
            "exit".to_string(),
        ];
        let kept = select(off, Some(&wanted)).unwrap();
        assert_eq!(
            kept,
            [("exit".to_string(), Scalar::Text("complete".into()))],
            "nulls are known, not kept"
        );
    }
}
