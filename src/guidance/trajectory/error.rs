//! The error of a refused trajectory, and the checks that produce it.

use thiserror::Error;

use crate::math::Vec3;

/// A refused trajectory: the field of the `[trajectory]` table at fault and why, displayed as
/// `trajectory.duration: must be positive, got -1`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("trajectory.{field}: {reason}")]
pub struct TrajectoryError {
    /// Field of the `[trajectory]` table, with an index where it helps (`waypoints[2]`).
    pub field: String,
    /// What is wrong.
    pub reason: String,
}

impl TrajectoryError {
    /// Error for `field` with `reason`.
    pub fn new(field: &str, reason: String) -> Self {
        Self {
            field: field.to_string(),
            reason,
        }
    }
}

/// `v` if it is finite and positive.
pub(crate) fn positive(field: &str, v: f64) -> Result<f64, TrajectoryError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(TrajectoryError::new(field, format!("must be positive, got {v}")))
    }
}

/// `p` [m] as a vector if every component is finite.
pub(crate) fn point(field: &str, p: [f64; 3]) -> Result<Vec3, TrajectoryError> {
    if p.iter().all(|c| c.is_finite()) {
        Ok(Vec3::from(p))
    } else {
        Err(TrajectoryError::new(
            field,
            format!("must be finite numbers, got {p:?}"),
        ))
    }
}

/// `deg` [deg] in radians if it is finite.
pub(crate) fn heading(field: &str, deg: f64) -> Result<f64, TrajectoryError> {
    if deg.is_finite() {
        Ok(deg.to_radians())
    } else {
        Err(TrajectoryError::new(
            field,
            format!("must be a finite angle, got {deg}"),
        ))
    }
}
