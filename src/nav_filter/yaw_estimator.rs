//! Heading from GNSS velocity: a Gaussian-sum filter of [`MODELS`] small EKFs, each with its own
//! heading hypothesis, driven by the heading-free horizontal specific force and the gyro's rate
//! about the vertical and updated with the GNSS horizontal velocity; their weights follow how
//! well each predicts the velocity, and the weighted mean is the heading (PX4's EKF-GSF yaw
//! estimator) (docs/navigation_filter.md §18, eqs. (18.1)–(18.5)). Accelerating or turning, the
//! wrong hypotheses predict the velocity badly and lose their weight; in a steady hover every
//! model predicts equally well and the estimate stays unconverged. Pure, allocation-free.

use nalgebra::{Matrix2, Matrix2x3, Matrix3, Vector2, Vector3};

use crate::math::wrap_pi;

/// Heading hypotheses [-].
pub const MODELS: usize = 5;
/// Horizontal acceleration noise of each model's prediction [m/s²].
const ACCEL_NOISE_M_S2: f64 = 1.0;
/// Noise of the rate about the vertical [rad/s].
const YAW_RATE_NOISE_RAD_S: f64 = 0.02;
/// Smallest model weight, so that a hypothesis can recover [-].
const MIN_WEIGHT: f64 = 1e-4;

/// One heading hypothesis: velocity north and east [m/s], heading [rad] and their covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Model {
    vel: Vector2<f64>,
    yaw: f64,
    p: Matrix3<f64>,
    weight: f64,
}

/// The Gaussian sum of heading hypotheses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YawEstimator {
    models: [Model; MODELS],
    started: bool,
}

impl Default for YawEstimator {
    fn default() -> Self {
        let model = Model {
            vel: Vector2::zeros(),
            yaw: 0.0,
            p: Matrix3::zeros(),
            weight: 1.0 / MODELS as f64,
        };
        Self {
            models: [model; MODELS],
            started: false,
        }
    }
}

impl YawEstimator {
    /// Starts the hypotheses spread evenly around the circle at velocity `vel_ne` [m/s] with
    /// velocity variance `vel_var` [m²/s²] (18.1).
    pub fn start(&mut self, vel_ne: Vector2<f64>, vel_var: f64) {
        let spread = std::f64::consts::TAU / MODELS as f64;
        for (i, m) in self.models.iter_mut().enumerate() {
            *m = Model {
                vel: vel_ne,
                yaw: wrap_pi(-std::f64::consts::PI + (i as f64 + 0.5) * spread),
                p: Matrix3::from_diagonal(&Vector3::new(vel_var, vel_var, (0.5 * spread).powi(2))),
                weight: 1.0 / MODELS as f64,
            };
        }
        self.started = true;
    }

    /// Predicts over `dt_s` [s] with `dvel_level` [m/s], the horizontal velocity increment of the
    /// specific force in the heading-free level frame, and `dyaw` [rad], the gyro's turn about the
    /// vertical (18.2)–(18.3).
    pub fn predict(&mut self, dvel_level: Vector2<f64>, dyaw: f64, dt_s: f64) {
        if !self.started || dt_s <= 0.0 {
            return;
        }
        let q_vel = (ACCEL_NOISE_M_S2 * dt_s).powi(2);
        let q_yaw = (YAW_RATE_NOISE_RAD_S * dt_s).powi(2);
        for m in &mut self.models {
            let (s, c) = m.yaw.sin_cos();
            let (ax, ay) = (dvel_level.x, dvel_level.y);
            m.vel += Vector2::new(c * ax - s * ay, s * ax + c * ay);
            let mut f = Matrix3::identity();
            f[(0, 2)] = -s * ax - c * ay;
            f[(1, 2)] = c * ax - s * ay;
            m.p = f * m.p * f.transpose();
            m.p[(0, 0)] += q_vel;
            m.p[(1, 1)] += q_vel;
            m.p[(2, 2)] += q_yaw;
            m.yaw = wrap_pi(m.yaw + dyaw);
        }
    }

    /// Updates every hypothesis with a GNSS horizontal velocity `vel_ne` [m/s] of variance
    /// `vel_var` [m²/s²] and re-weights them by the likelihood of their innovations (18.4).
    pub fn fuse_velocity(&mut self, vel_ne: Vector2<f64>, vel_var: f64) {
        if !self.started {
            self.start(vel_ne, vel_var);
            return;
        }
        let h = Matrix2x3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let mut total = 0.0;
        for m in &mut self.models {
            let nu = vel_ne - m.vel;
            let s = h * m.p * h.transpose() + Matrix2::identity() * vel_var;
            let Some(s_inv) = s.try_inverse() else { continue };
            let det = s.determinant();
            let likelihood = (-0.5 * nu.dot(&(s_inv * nu))).exp() / (std::f64::consts::TAU * det.max(1e-12).sqrt());
            let k = m.p * h.transpose() * s_inv;
            let dx = k * nu;
            m.vel += dx.fixed_rows::<2>(0);
            m.yaw = wrap_pi(m.yaw + dx.z);
            let i_kh = Matrix3::identity() - k * h;
            m.p = i_kh * m.p * i_kh.transpose() + k * k.transpose() * vel_var;
            m.p = 0.5 * (m.p + m.p.transpose());
            m.weight *= likelihood;
            total += m.weight;
        }
        for m in &mut self.models {
            m.weight = if total > 0.0 {
                m.weight / total
            } else {
                1.0 / MODELS as f64
            }
            .max(MIN_WEIGHT);
        }
        let sum: f64 = self.models.iter().map(|m| m.weight).sum();
        for m in &mut self.models {
            m.weight /= sum;
        }
    }

    /// The heading [rad] and its variance [rad²]: the weighted circular mean of the hypotheses,
    /// and their weighted variances plus spread about it (18.5); `None` before the start.
    pub fn yaw(&self) -> Option<(f64, f64)> {
        if !self.started {
            return None;
        }
        let (s, c) = self.models.iter().fold((0.0, 0.0), |(s, c), m| {
            (s + m.weight * m.yaw.sin(), c + m.weight * m.yaw.cos())
        });
        let mean = s.atan2(c);
        let var = self
            .models
            .iter()
            .map(|m| m.weight * (m.p[(2, 2)] + wrap_pi(m.yaw - mean).powi(2)))
            .sum();
        Some((mean, var))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vehicle flying circles at 5 m/s heading `yaw0` + the turn: the estimator, started with
    /// no idea of the heading, finds it from the velocity alone.
    fn fly(yaw_true0: f64, seconds: f64) -> (f64, f64, f64) {
        let mut est = YawEstimator::default();
        let (speed, turn_rate, dt) = (5.0, 0.2, 0.01);
        let mut yaw_true = yaw_true0;
        for k in 0..(seconds / dt) as usize {
            // Flying forward along its heading: centripetal acceleration to the left (body y).
            let accel_body = Vector2::new(0.0, speed * turn_rate);
            let dvel_level = accel_body * dt;
            est.predict(dvel_level, turn_rate * dt, dt);
            yaw_true = wrap_pi(yaw_true + turn_rate * dt);
            if k % 10 == 0 {
                let vel = Vector2::new(yaw_true.cos(), yaw_true.sin()) * speed;
                est.fuse_velocity(vel, 0.3f64.powi(2));
            }
        }
        let (yaw, var) = est.yaw().unwrap();
        (wrap_pi(yaw - yaw_true), var, yaw_true)
    }

    #[test]
    fn turning_flight_reveals_the_heading_from_any_start() {
        for yaw0 in [-3.0, -1.2, 0.0, 0.7, 2.9] {
            let (err, var, _) = fly(yaw0, 30.0);
            assert!(
                err.abs() < 3f64.to_radians(),
                "start {yaw0}: error {}°",
                err.to_degrees()
            );
            assert!(
                var.sqrt() < 5f64.to_radians(),
                "start {yaw0}: σ {}°",
                var.sqrt().to_degrees()
            );
        }
    }

    #[test]
    fn a_hover_leaves_the_heading_unknown() {
        let mut est = YawEstimator::default();
        for k in 0..3000 {
            est.predict(Vector2::zeros(), 0.0, 0.01);
            if k % 10 == 0 {
                est.fuse_velocity(Vector2::zeros(), 0.09);
            }
        }
        let (_, var) = est.yaw().unwrap();
        assert!(var.sqrt() > 45f64.to_radians(), "σ {}°", var.sqrt().to_degrees());
        assert!(YawEstimator::default().yaw().is_none());
    }
}
