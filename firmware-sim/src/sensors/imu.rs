//! The IMU: accelerometer and gyroscope in body FRD, sampled at every plant tick
//! (docs/model.md §10.2, eqs. (10.2)–(10.5)).
//!
//! Each half has white noise given as a **per-sample standard deviation** at the plant's 1 kHz
//! (a noise density N [unit/√Hz] corresponds to N·√1000), a bias that starts at a turn-on value
//! drawn once at construction and then follows a random walk, scaled by the actual time between
//! samples.
//!
//! Faults (docs/model.md §10.6): `Wrong` adds a constant offset — 0.2 rad/s on every gyro axis
//! (beyond EKF2_GYR_B_LIM = 0.15 rad/s, so an estimator cannot learn it as bias), 1 m/s² on every
//! accelerometer axis (beyond EKF2_ABL_LIM = 0.4 m/s²); `Garbage` draws every axis uniformly over
//! the full scale of a common flight-controller IMU, ±2000 °/s and ±16 g.

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

use super::fault::SensorUnit;
use super::fault_layer::{FaultCtx, Reading};
use super::gauss::{gaussian3, uniform3};
use crate::plant::TruthState;
use crate::GRAVITY_M_S2;

/// Gyroscope offset of the `Wrong` fault, every axis [rad/s].
pub const GYRO_WRONG_OFFSET_RAD_S: f64 = 0.2;
/// Accelerometer offset of the `Wrong` fault, every axis [m/s²].
pub const ACCEL_WRONG_OFFSET_M_S2: f64 = 1.0;
/// Gyroscope full scale used by the `Garbage` fault [rad/s] (2000 °/s).
pub const GYRO_FULL_SCALE_RAD_S: f64 = 2000.0 * std::f64::consts::PI / 180.0;
/// Accelerometer full scale used by the `Garbage` fault [m/s²] (16 g).
pub const ACCEL_FULL_SCALE_M_S2: f64 = 16.0 * GRAVITY_M_S2;

/// IMU error parameters; all per axis, body FRD.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuConfig {
    /// Accelerometer white noise, standard deviation per sample [m/s²].
    pub accel_noise_m_s2: f64,
    /// Accelerometer bias random walk: the bias changes by N(0, σ²Δt) over Δt [m/s²/√s].
    pub accel_bias_walk_m_s2_sqrt_s: f64,
    /// Standard deviation of the accelerometer's turn-on bias [m/s²].
    pub accel_turn_on_bias_m_s2: f64,
    /// Gyroscope white noise, standard deviation per sample [rad/s].
    pub gyro_noise_rad_s: f64,
    /// Gyroscope bias random walk [rad/s/√s].
    pub gyro_bias_walk_rad_s_sqrt_s: f64,
    /// Standard deviation of the gyroscope's turn-on bias [rad/s].
    pub gyro_turn_on_bias_rad_s: f64,
}

impl ImuConfig {
    /// PX4 SITL's IMU, the default: white noise at PX4's EKF2 defaults EKF2_ACC_NOISE =
    /// 0.35 m/s² and EKF2_GYR_NOISE = 0.015 rad/s (PX4's SIH simulator uses 0.1 m/s² and
    /// 0.01 rad/s at rest, 0.5–1.7 m/s² and 0.03–0.14 rad/s with motors running), and no bias,
    /// as SIH has none.
    pub fn typical() -> Self {
        Self {
            accel_noise_m_s2: 0.35,
            accel_bias_walk_m_s2_sqrt_s: 0.0,
            accel_turn_on_bias_m_s2: 0.0,
            gyro_noise_rad_s: 0.015,
            gyro_bias_walk_rad_s_sqrt_s: 0.0,
            gyro_turn_on_bias_rad_s: 0.0,
        }
    }

    /// A real IMU: the noise of `typical`, with the bias walk and turn-on bias of the ADIS16448
    /// defaults of PX4's Gazebo IMU plugin (random walk 0.006 m/s²/√s and 4 °/h/√s ≈
    /// 3.88e-5 rad/s/√s; turn-on 20 mg ≈ 0.196 m/s² and 0.5 °/s ≈ 0.0087 rad/s), consistent
    /// with EKF2_ABIAS_INIT = 0.2 m/s². The estimate starts tilted by the horizontal turn-on
    /// bias (up to 3.5° at 3 σ) and its height wanders by about 0.1 m while the GNSS heights
    /// learn the walk.
    pub fn hardware() -> Self {
        Self {
            accel_bias_walk_m_s2_sqrt_s: 0.006,
            accel_turn_on_bias_m_s2: 0.196,
            gyro_bias_walk_rad_s_sqrt_s: 3.8785e-5,
            gyro_turn_on_bias_rad_s: 0.0087,
            ..Self::typical()
        }
    }

    /// No noise and no bias: the IMU reads the truth.
    pub fn ideal() -> Self {
        Self {
            accel_noise_m_s2: 0.0,
            accel_bias_walk_m_s2_sqrt_s: 0.0,
            accel_turn_on_bias_m_s2: 0.0,
            gyro_noise_rad_s: 0.0,
            gyro_bias_walk_rad_s_sqrt_s: 0.0,
            gyro_turn_on_bias_rad_s: 0.0,
        }
    }
}

/// What the IMU delivers at one plant tick. The halves fail separately, so each is an `Option`:
/// `None` when that half delivers nothing (off, slowed, intermittent) while the other does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuSample {
    /// Time of the sample [s].
    pub t_s: f64,
    /// Specific force in body FRD [m/s²]; about −g along z at rest.
    pub accel_b: Option<Vector3<f64>>,
    /// Angular velocity in body FRD [rad/s].
    pub gyro_b: Option<Vector3<f64>>,
}

/// One half of an IMU reading as the fault layer handles it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AxisReading {
    /// Time of the sample [s].
    pub(crate) t_s: f64,
    /// Specific force [m/s²] or angular velocity [rad/s], body FRD.
    pub(crate) v_b: Vector3<f64>,
}

impl AxisReading {
    pub(crate) const ZERO: Self = Self {
        t_s: 0.0,
        v_b: Vector3::new(0.0, 0.0, 0.0),
    };
}

impl Reading for AxisReading {
    fn t_s(&self) -> f64 {
        self.t_s
    }

    fn restamped(self, t_s: f64) -> Self {
        Self { t_s, ..self }
    }

    fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self {
        let full_scale = match ctx.unit {
            SensorUnit::Gyro => GYRO_FULL_SCALE_RAD_S,
            _ => ACCEL_FULL_SCALE_M_S2,
        };
        Self {
            v_b: uniform3(ctx.rng, full_scale),
            ..self
        }
    }

    fn wrong(self, ctx: &mut FaultCtx<'_>) -> Self {
        let offset = match ctx.unit {
            SensorUnit::Gyro => GYRO_WRONG_OFFSET_RAD_S,
            _ => ACCEL_WRONG_OFFSET_M_S2,
        };
        Self {
            v_b: self.v_b.add_scalar(offset),
            ..self
        }
    }
}

/// The healthy IMU: biases and their random walks, white noise.
#[derive(Debug, Clone)]
pub(crate) struct ImuModel {
    config: ImuConfig,
    accel_rng: ChaCha8Rng,
    gyro_rng: ChaCha8Rng,
    accel_bias_b: Vector3<f64>,
    gyro_bias_b: Vector3<f64>,
    last_t_s: Option<f64>,
}

impl ImuModel {
    /// Draws the turn-on biases, the accelerometer's from `accel_rng`, the gyro's from `gyro_rng`.
    pub(crate) fn new(config: ImuConfig, mut accel_rng: ChaCha8Rng, mut gyro_rng: ChaCha8Rng) -> Self {
        let accel_bias_b = gaussian3(&mut accel_rng, config.accel_turn_on_bias_m_s2);
        let gyro_bias_b = gaussian3(&mut gyro_rng, config.gyro_turn_on_bias_rad_s);
        Self {
            config,
            accel_rng,
            gyro_rng,
            accel_bias_b,
            gyro_bias_b,
            last_t_s: None,
        }
    }

    /// Current accelerometer bias [m/s²] and gyroscope bias [rad/s], body FRD (truth for logs).
    pub(crate) fn biases(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.accel_bias_b, self.gyro_bias_b)
    }

    /// Accelerometer and gyroscope readings of `truth` (docs/model.md §10.2, eqs. (10.2)–(10.4)).
    /// Each half draws six normals per call (bias step, then noise), whatever the configuration.
    pub(crate) fn sample(&mut self, truth: &TruthState) -> (AxisReading, AxisReading) {
        let dt = match self.last_t_s {
            Some(t) if truth.t_s > t => truth.t_s - t,
            _ => 0.0,
        };
        self.last_t_s = Some(truth.t_s);
        let c = &self.config;
        let sqrt_dt = dt.sqrt();
        self.accel_bias_b += gaussian3(&mut self.accel_rng, c.accel_bias_walk_m_s2_sqrt_s * sqrt_dt);
        self.gyro_bias_b += gaussian3(&mut self.gyro_rng, c.gyro_bias_walk_rad_s_sqrt_s * sqrt_dt);
        let q = truth.body.q_wb;
        let specific_w = truth.accel_w - Vector3::new(0.0, 0.0, GRAVITY_M_S2);
        let accel_b = q.inverse_transform_vector(&specific_w)
            + self.accel_bias_b
            + gaussian3(&mut self.accel_rng, c.accel_noise_m_s2);
        let gyro_b = truth.mean_omega_b + self.gyro_bias_b + gaussian3(&mut self.gyro_rng, c.gyro_noise_rad_s);
        (
            AxisReading {
                t_s: truth.t_s,
                v_b: accel_b,
            },
            AxisReading {
                t_s: truth.t_s,
                v_b: gyro_b,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::gauss::seeded_stream;
    use crate::sensors::test_support::{truth_at, vec_stats};
    use crate::sensors::NoiseParams;
    use nalgebra::UnitQuaternion;

    fn model(config: ImuConfig, seed: u64) -> ImuModel {
        ImuModel::new(config, seeded_stream(seed, 1), seeded_stream(seed, 2))
    }

    #[test]
    fn ideal_imu_reads_the_state_sensors_specific_force_and_the_steps_mean_rate() {
        let mut imu = model(ImuConfig::ideal(), 5);
        let mut truth = truth_at(0.25);
        truth.body.q_wb = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1);
        truth.body.omega_b = Vector3::new(0.1, -0.4, 0.7);
        truth.mean_omega_b = Vector3::new(0.2, -0.3, 0.6);
        truth.accel_w = Vector3::new(1.5, -0.5, 2.0);
        let (a, g) = imu.sample(&truth);
        let exact = NoiseParams::default().sample(truth.t_s, &truth.body, truth.accel_w, &mut seeded_stream(0, 0));
        assert_eq!(a.v_b, exact.accel_b);
        assert_eq!(g.v_b, truth.mean_omega_b);
        assert_eq!((a.t_s, g.t_s), (0.25, 0.25));
    }

    #[test]
    fn white_noise_has_the_configured_standard_deviation() {
        let config = ImuConfig {
            accel_noise_m_s2: 0.35,
            gyro_noise_rad_s: 0.015,
            ..ImuConfig::ideal()
        };
        let mut imu = model(config, 11);
        let truth = truth_at(0.0);
        let n = 40_000;
        let (mut accel, mut gyro) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for _ in 0..n {
            let (a, g) = imu.sample(&truth);
            accel.push(a.v_b - Vector3::new(0.0, 0.0, -GRAVITY_M_S2));
            gyro.push(g.v_b);
        }
        // 3n = 120 000 values each: standard errors sd/√(3n) on the mean and √(2/(3n)) ≈ 0.41 %
        // on the variance; allow five of them.
        for (xs, sd) in [(&accel, 0.35), (&gyro, 0.015)] {
            let (mean, var) = vec_stats(xs);
            let m = 3.0 * n as f64;
            assert!(mean.abs() < 5.0 * sd / m.sqrt(), "mean {mean}");
            assert!(
                (var / (sd * sd) - 1.0).abs() < 5.0 * (2.0 / m).sqrt(),
                "var {var} sd {sd}"
            );
        }
    }

    #[test]
    fn turn_on_bias_spread_matches_its_standard_deviation() {
        let config = ImuConfig {
            accel_turn_on_bias_m_s2: 0.196,
            gyro_turn_on_bias_rad_s: 0.0087,
            ..ImuConfig::ideal()
        };
        let (mut accel, mut gyro) = (Vec::new(), Vec::new());
        for seed in 0..4000 {
            let (a, g) = model(config, seed).biases();
            accel.push(a);
            gyro.push(g);
        }
        // 12 000 values: √(2/12000) ≈ 1.3 % standard error on the variance.
        for (xs, sd) in [(&accel, 0.196), (&gyro, 0.0087)] {
            let (mean, var) = vec_stats(xs);
            assert!(mean.abs() < 5.0 * sd / 12_000f64.sqrt(), "mean {mean}");
            assert!((var / (sd * sd) - 1.0).abs() < 0.065, "var {var}");
        }
    }

    #[test]
    fn bias_random_walk_variance_grows_as_sigma_squared_t() {
        let (sa, sg) = (0.006, 3.8785e-5);
        let config = ImuConfig {
            accel_bias_walk_m_s2_sqrt_s: sa,
            gyro_bias_walk_rad_s_sqrt_s: sg,
            ..ImuConfig::ideal()
        };
        let seeds = 1000;
        let (mut a1, mut a2, mut g1, mut g2) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for seed in 0..seeds {
            let mut imu = model(config, 100 + seed);
            for i in 0..=2000 {
                imu.sample(&truth_at(i as f64 * 1e-3));
                if i == 500 || i == 2000 {
                    let (a, g) = imu.biases();
                    let (av, gv) = if i == 500 {
                        (&mut a1, &mut g1)
                    } else {
                        (&mut a2, &mut g2)
                    };
                    av.push(a);
                    gv.push(g);
                }
            }
        }
        // Var b(t) = σ² t with zero turn-on bias (docs/model.md §10.2, eq. (10.5)). 3000 values per
        // time: √(2/3000) ≈ 2.6 % standard error; allow five.
        for (xs, sd, t) in [(&a1, sa, 0.5), (&a2, sa, 2.0), (&g1, sg, 0.5), (&g2, sg, 2.0)] {
            let (_, var) = vec_stats(xs);
            assert!(
                (var / (sd * sd * t) - 1.0).abs() < 0.13,
                "t {t}: var {var} vs {}",
                sd * sd * t
            );
        }
    }
}
