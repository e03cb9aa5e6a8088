//! Discrete gusts: the "1 − cosine" shape of MIL-F-8785C, up and back down
//! (docs/model.md §5.2, eq. (5.6)).

use nalgebra::Vector3;

/// One gust: the air's velocity rises smoothly to `peak_w` and falls back to zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gust {
    /// When the gust starts [s].
    pub start_s: f64,
    /// How long it lasts from start to end [s] (peak at half of it).
    pub duration_s: f64,
    /// Peak gust velocity, world NED [m/s].
    pub peak_w: Vector3<f64>,
}

impl Gust {
    /// The gust velocity at `t_s` [s]: peak · ½ (1 − cos(2π (t − t₀) / d)) inside the gust,
    /// zero outside (docs/model.md §5.2, eq. (5.6)).
    pub fn velocity_w(&self, t_s: f64) -> Vector3<f64> {
        let x = (t_s - self.start_s) / self.duration_s;
        if (0.0..=1.0).contains(&x) {
            self.peak_w * (0.5 * (1.0 - (std::f64::consts::TAU * x).cos()))
        } else {
            Vector3::zeros()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rises_to_the_peak_and_back() {
        let g = Gust {
            start_s: 2.0,
            duration_s: 1.0,
            peak_w: Vector3::new(3.0, 0.0, 0.0),
        };
        assert_eq!(g.velocity_w(1.9), Vector3::zeros());
        assert!((g.velocity_w(2.5).x - 3.0).abs() < 1e-12);
        assert!(g.velocity_w(2.25).x > 1.4 && g.velocity_w(2.25).x < 1.6);
        assert!(g.velocity_w(3.0).x.abs() < 1e-12);
        assert_eq!(g.velocity_w(3.1), Vector3::zeros());
    }
}
