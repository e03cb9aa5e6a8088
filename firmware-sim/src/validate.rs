//! Small checks that turn a raw file value into a validated one or a [`ParamsError`].

use nalgebra::Vector3;

use crate::params::ParamsError;

/// Builds errors that name the file the text came from.
pub(crate) struct Checker {
    origin: String,
}

impl Checker {
    pub(crate) fn new(origin: &str) -> Self {
        Self {
            origin: origin.to_string(),
        }
    }

    pub(crate) fn error(&self, field: &str, reason: String) -> ParamsError {
        ParamsError {
            origin: self.origin.clone(),
            field: field.to_string(),
            reason,
        }
    }

    /// A TOML syntax or schema error, located by line.
    pub(crate) fn syntax(&self, text: &str, e: &toml::de::Error) -> ParamsError {
        let line = e.span().map(|s| text[..s.start.min(text.len())].lines().count().max(1));
        let field = match line {
            Some(l) => format!("line {l}"),
            None => "(file)".to_string(),
        };
        self.error(&field, e.message().trim().to_string())
    }
}

pub(crate) fn required<T>(check: &Checker, v: Option<T>, field: &str) -> Result<T, ParamsError> {
    v.ok_or_else(|| check.error(field, "missing field".to_string()))
}

pub(crate) fn finite(check: &Checker, v: f64, field: &str) -> Result<f64, ParamsError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(check.error(field, format!("{v} is not a finite number")))
    }
}

pub(crate) fn positive(check: &Checker, v: f64, field: &str) -> Result<f64, ParamsError> {
    let v = finite(check, v, field)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(check.error(field, format!("{v} must be positive")))
    }
}

pub(crate) fn non_negative(check: &Checker, v: f64, field: &str) -> Result<f64, ParamsError> {
    let v = finite(check, v, field)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(check.error(field, format!("{v} must not be negative")))
    }
}

pub(crate) fn vec3(check: &Checker, v: Vec<f64>, field: &str) -> Result<Vector3<f64>, ParamsError> {
    if v.len() != 3 {
        return Err(check.error(field, format!("expected 3 numbers, found {}", v.len())));
    }
    for (i, x) in v.iter().enumerate() {
        finite(check, *x, &format!("{field}[{i}]"))?;
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}
