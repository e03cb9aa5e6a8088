//! The one value that carries an estimate of the external (disturbance) wrench through every
//! layer: the estimator's output, the controller's compensation input (docs/control.md §4–§6,
//! "[− f̂_e]", "[− τ̂_e]"), the flight core's step, the telemetry snapshot and the runs' reports.

use crate::math::Vec3;

/// Estimated external wrench (docs/estimator.md §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WrenchEstimate {
    /// External force f̂_e, world NED [N].
    pub force_w: Vec3,
    /// External torque τ̂_e^b = Q⁻ᵀ τ̂_e, body FRD [N·m].
    pub torque_b: Vec3,
    /// Mass estimate m_e + f̂_ez / g [kg] (docs/estimator.md §5, eq. (5.3)).
    pub mass_kg: f64,
}

impl WrenchEstimate {
    /// No external wrench on a vehicle of mass `mass_kg` [kg].
    pub fn zero(mass_kg: f64) -> Self {
        Self {
            force_w: Vec3::zeros(),
            torque_b: Vec3::zeros(),
            mass_kg,
        }
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.force_w.iter().chain(self.torque_b.iter()).all(|x| x.is_finite()) && self.mass_kg.is_finite()
    }
}
