//! First-order low-pass of a 3-vector, as PX4 filters the rates and accelerations its
//! controllers read (`IMU_GYRO_CUTOFF`, `IMU_ACCEL_CUTOFF`)
//! (docs/navigation_filter.md §17, eq. (17.1)):
//! `y_k = y_{k−1} + α (x_k − y_{k−1})`, `α = 1 − e^{−2π f_c Ts}`, the exact
//! discretisation of `1 / (s / (2π f_c) + 1)` for a signal held over each step; started at the
//! first sample.

use crate::math::Vec3;

/// A first-order low-pass of cut-off `f_c` at sample time `Ts`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowPass3 {
    alpha: f64,
    y: Option<Vec3>,
}

impl LowPass3 {
    /// Cut-off `cutoff_hz` [Hz] at sample time `ts_s` [s]; a cut-off of 0 (or at or above the
    /// Nyquist frequency) passes the signal through.
    pub fn new(cutoff_hz: f64, ts_s: f64) -> Self {
        let pass = !(cutoff_hz > 0.0 && cutoff_hz < 0.5 / ts_s);
        Self {
            alpha: if pass {
                1.0
            } else {
                1.0 - (-std::f64::consts::TAU * cutoff_hz * ts_s).exp()
            },
            y: None,
        }
    }

    /// Feeds `x`; the filtered value.
    pub fn update(&mut self, x: Vec3) -> Vec3 {
        let y = match self.y {
            Some(y) => y + self.alpha * (x - y),
            None => x,
        };
        self.y = Some(y);
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_rises_with_the_time_constant_and_white_noise_shrinks() {
        let ts = 1e-3;
        let mut f = LowPass3::new(40.0, ts);
        assert_eq!(f.update(Vec3::zeros()), Vec3::zeros(), "starts at the first sample");
        let tau = 1.0 / (std::f64::consts::TAU * 40.0);
        let steps = (tau / ts).round() as usize;
        let mut y = Vec3::zeros();
        for _ in 0..steps {
            y = f.update(Vec3::repeat(1.0));
        }
        assert!((y.x - (1.0 - (-(steps as f64) * ts / tau).exp())).abs() < 1e-9, "{y}");
        // Alternating ±1 (the Nyquist frequency) is attenuated to α / (2 − α).
        let mut f = LowPass3::new(40.0, ts);
        let mut last = Vec3::zeros();
        for k in 0..1000 {
            last = f.update(Vec3::repeat(if k % 2 == 0 { 1.0 } else { -1.0 }));
        }
        assert!(last.x.abs() < 0.15, "{last}");
        let mut through = LowPass3::new(0.0, ts);
        assert_eq!(through.update(Vec3::new(1.0, 2.0, 3.0)), Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(through.update(Vec3::new(4.0, 5.0, 6.0)), Vec3::new(4.0, 5.0, 6.0));
    }
}
