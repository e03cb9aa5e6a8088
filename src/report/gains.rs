//! `rotorpilot gains`: a Chebyshev estimator design as JSON or as text.

use serde::Serialize;

use crate::wrench_estimator::{estimator_gains, ChebyshevDesign, DesignError};

/// Estimator design: monic denominator, gains, poles and stability at Ts.
#[derive(Debug, Clone, Serialize)]
pub struct GainsReport {
    /// Order r.
    pub order: usize,
    /// Monic denominator, descending powers of s.
    pub a: Vec<f64>,
    /// Gains K_1 … K_r [1/s].
    #[serde(rename = "K")]
    pub k: Vec<f64>,
    /// Analog poles [re, im] [rad/s].
    pub poles: Vec<[f64; 2]>,
    /// Forward-Euler update stable at Ts.
    pub stable: bool,
    /// Largest stable passband edge for this order and ripple at Ts [rad/s].
    pub max_stable_wp: f64,
}

impl GainsReport {
    /// Report of `design` at sample time `ts_s` [s]; an unstable design is reported, not refused.
    pub fn new(design: &ChebyshevDesign, ts_s: f64) -> Result<Self, DesignError> {
        let ascending = design.monic_denominator()?;
        Ok(Self {
            order: design.order,
            k: estimator_gains(&ascending),
            a: ascending.iter().rev().copied().collect(),
            poles: design.poles()?.into_iter().map(|(re, im)| [re, im]).collect(),
            stable: design.is_stable_at(ts_s)?,
            max_stable_wp: design.max_stable_passband_rad_s(ts_s)?,
        })
    }

    /// Human-readable text.
    pub fn to_text(&self) -> String {
        let list = |v: &[f64]| v.iter().map(|x| format!("{x:.10e}")).collect::<Vec<_>>().join(", ");
        let poles = self
            .poles
            .iter()
            .map(|[re, im]| format!("{re:.6} {im:+.6}j"))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "order {}\ndenominator (descending): {}\nK_1..K_r [1/s]: {}\npoles [rad/s]: {}\nstable: {} (largest stable Wp {:.4} rad/s)\n",
            self.order,
            list(&self.a),
            list(&self.k),
            poles,
            self.stable,
            self.max_stable_wp
        )
    }
}
