//! Filtered numerical derivative ("dirty derivative") of docs/control.md §3, eqs. (3.1)–(3.2):
//! `D(s) = s / (τ_f s + 1)` discretised with backward Euler,
//!
//! ```text
//! d_k = ( τ_f d_{k−1} + (x_k − x_{k−1}) ) / (τ_f + Ts)                        (3.2)
//! ```
//!
//! initialised from the first sample (`x_{−1} = x_0`, `d = 0`) so a controller starting away
//! from zero sees no start-up spike.

use crate::math::Vec3;

/// Filtered derivative of a 3-vector signal sampled every `ts_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirtyDerivative {
    tau_s: f64,
    ts_s: f64,
    previous: Option<Vec3>,
    derivative: Vec3,
}

impl DirtyDerivative {
    /// Derivative filter with time constant `tau_s` [s] at sample time `ts_s` [s].
    pub fn new(tau_s: f64, ts_s: f64) -> Self {
        Self {
            tau_s,
            ts_s,
            previous: None,
            derivative: Vec3::zeros(),
        }
    }

    /// Feeds sample `x` and returns the filtered derivative [unit of x / s].
    pub fn update(&mut self, x: Vec3) -> Vec3 {
        let previous = self.previous.replace(x).unwrap_or(x);
        self.derivative = (self.tau_s * self.derivative + (x - previous)) / (self.tau_s + self.ts_s);
        self.derivative
    }

    /// Latest derivative without feeding a sample.
    pub fn value(&self) -> Vec3 {
        self.derivative
    }

    /// Forgets the history; the next sample restarts the filter.
    pub fn reset(&mut self) {
        self.previous = None;
        self.derivative = Vec3::zeros();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_sample_gives_no_spike_and_ramp_converges_to_slope() {
        let mut d = DirtyDerivative::new(0.02, 0.001);
        assert_eq!(d.update(Vec3::new(5.0, -3.0, 1.0)), Vec3::zeros());
        let mut out = Vec3::zeros();
        for k in 1..=500 {
            out = d.update(Vec3::new(5.0 + 2.0 * k as f64 * 0.001, -3.0, 1.0));
        }
        assert!((out.x - 2.0).abs() < 1e-6, "{out}");
        assert!(out.y.abs() < 1e-15);
    }

    #[test]
    fn step_response_is_bounded_by_one_over_tau() {
        let mut d = DirtyDerivative::new(0.02, 0.001);
        d.update(Vec3::zeros());
        let peak = d.update(Vec3::new(1.0, 0.0, 0.0)).x;
        assert!((peak - 1.0 / 0.021).abs() < 1e-12);
        assert_eq!(d.value().x, peak);
        d.reset();
        assert_eq!(d.update(Vec3::new(3.0, 0.0, 0.0)), Vec3::zeros());
    }
}
