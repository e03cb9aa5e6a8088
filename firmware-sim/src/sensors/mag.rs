//! The magnetometer: a constant Earth field rotated into body FRD, with white noise and a
//! constant hard-iron bias (docs/model.md §10.5, eqs. (10.12)–(10.14)).
//!
//! The field is fixed by its strength, declination D (east of true north) and inclination I
//! (below the horizontal); the defaults are PX4's World Magnetic Model table at PX4's default home
//! near Zurich (47.397742° N, 8.545594° E).
//!
//! Faults (docs/model.md §10.6): `Wrong` adds 0.3 G on every axis, as a magnet or a current-
//! carrying wire next to the compass would; `Garbage` draws every axis uniformly over ±4 G
//! (a LIS3MDL's smallest range).

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

use super::fault_layer::{FaultCtx, Reading};
use super::gauss::{gaussian3, uniform3};
use super::schedule::RateSchedule;
use crate::plant::TruthState;

/// Offset of the `Wrong` fault, every axis [gauss].
pub const MAG_WRONG_OFFSET_GAUSS: f64 = 0.3;
/// Full scale used by the `Garbage` fault [gauss].
pub const MAG_FULL_SCALE_GAUSS: f64 = 4.0;

/// Magnetometer parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagConfig {
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// Earth field strength F [gauss].
    pub strength_gauss: f64,
    /// Declination D, positive east of true north [rad].
    pub declination_rad: f64,
    /// Inclination I, positive below the horizontal [rad].
    pub inclination_rad: f64,
    /// White noise, standard deviation per axis [gauss].
    pub noise_gauss: f64,
    /// Constant hard-iron bias in body FRD [gauss].
    pub bias_b_gauss: Vector3<f64>,
}

impl MagConfig {
    /// 50 Hz at PX4's default home: F = 0.482 G, D = 3.27°, I = 63.14°, bilinear interpolation
    /// of the WMM-2020 grid that PX4 ships (epoch 2023.6). Noise 0.02 G per axis, PX4 SITL's
    /// horizontal figure (EKF2_MAG_NOISE = 0.05 G is the estimator's cautious one); no hard-iron
    /// bias, as PX4 SITL by default (a calibrated compass).
    pub fn typical() -> Self {
        Self {
            rate_hz: 50.0,
            strength_gauss: 0.482,
            declination_rad: 3.27f64.to_radians(),
            inclination_rad: 63.14f64.to_radians(),
            noise_gauss: 0.02,
            bias_b_gauss: Vector3::zeros(),
        }
    }

    /// No noise and no bias; the field as typical.
    pub fn ideal() -> Self {
        Self {
            noise_gauss: 0.0,
            bias_b_gauss: Vector3::zeros(),
            ..Self::typical()
        }
    }

    /// The Earth field in world NED [gauss] (docs/model.md §10.5, eq. (10.12)).
    pub fn earth_field_w(&self) -> Vector3<f64> {
        let (si, ci) = self.inclination_rad.sin_cos();
        let (sd, cd) = self.declination_rad.sin_cos();
        Vector3::new(ci * cd, ci * sd, si) * self.strength_gauss
    }
}

/// One magnetometer sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagSample {
    /// Time of the sample [s].
    pub t_s: f64,
    /// Magnetic field in body FRD [gauss].
    pub field_b: Vector3<f64>,
}

impl MagSample {
    pub(crate) const ZERO: Self = Self {
        t_s: 0.0,
        field_b: Vector3::new(0.0, 0.0, 0.0),
    };
}

impl Reading for MagSample {
    fn t_s(&self) -> f64 {
        self.t_s
    }

    fn restamped(self, t_s: f64) -> Self {
        Self { t_s, ..self }
    }

    fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self {
        Self {
            field_b: uniform3(ctx.rng, MAG_FULL_SCALE_GAUSS),
            ..self
        }
    }

    fn wrong(self, _ctx: &mut FaultCtx<'_>) -> Self {
        Self {
            field_b: self.field_b.add_scalar(MAG_WRONG_OFFSET_GAUSS),
            ..self
        }
    }
}

/// The healthy magnetometer.
#[derive(Debug, Clone)]
pub(crate) struct MagModel {
    config: MagConfig,
    field_w: Vector3<f64>,
    rng: ChaCha8Rng,
    schedule: RateSchedule,
}

impl MagModel {
    /// A magnetometer in the configured field.
    pub(crate) fn new(config: MagConfig, rng: ChaCha8Rng) -> Self {
        Self {
            config,
            field_w: config.earth_field_w(),
            rng,
            schedule: RateSchedule::new(config.rate_hz),
        }
    }

    /// The sample of this tick, if one falls due (docs/model.md §10.5, eq. (10.13)); three normals
    /// per sample.
    pub(crate) fn read(&mut self, truth: &TruthState) -> Option<MagSample> {
        if !self.schedule.due(truth.t_s) {
            return None;
        }
        let field_b = truth.body.q_wb.inverse_transform_vector(&self.field_w)
            + self.config.bias_b_gauss
            + gaussian3(&mut self.rng, self.config.noise_gauss);
        Some(MagSample {
            t_s: truth.t_s,
            field_b,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::gauss::seeded_stream;
    use crate::sensors::test_support::{tick_s, truth_at, vec_stats};
    use nalgebra::UnitQuaternion;

    #[test]
    fn field_has_the_configured_strength_declination_and_inclination() {
        let c = MagConfig::typical();
        let m = c.earth_field_w();
        assert!((m.norm() - 0.482).abs() < 1e-12);
        // docs/model.md §10.5, eq. (10.14).
        assert!((m.y.atan2(m.x) - 3.27f64.to_radians()).abs() < 1e-12);
        assert!((m.z.atan2(m.xy().norm()) - 63.14f64.to_radians()).abs() < 1e-12);
        assert!(m.z > 0.0, "points down in the northern hemisphere");
    }

    #[test]
    fn ideal_magnetometer_reads_the_field_in_body_axes_at_fifty_hertz() {
        let c = MagConfig::ideal();
        let mut mag = MagModel::new(c, seeded_stream(1, 5));
        let yaw = 30f64.to_radians();
        let mut n = 0;
        for i in 0..10_000 {
            let mut truth = truth_at(tick_s(i));
            truth.body.q_wb = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
            if let Some(s) = mag.read(&truth) {
                assert_eq!(s.field_b, truth.body.q_wb.inverse_transform_vector(&c.earth_field_w()));
                // Heading from the level body field: ψ = D − atan2(m_y, m_x).
                let heading = c.declination_rad - s.field_b.y.atan2(s.field_b.x);
                assert!((heading - yaw).abs() < 1e-12);
                assert!((s.field_b.norm() - c.strength_gauss).abs() < 1e-12);
                n += 1;
            }
        }
        assert_eq!(n, 500);
    }

    #[test]
    fn noise_and_bias_have_the_configured_sizes() {
        let bias = Vector3::new(0.05, -0.02, 0.01);
        let config = MagConfig {
            noise_gauss: 0.02,
            bias_b_gauss: bias,
            ..MagConfig::ideal()
        };
        let mut mag = MagModel::new(config, seeded_stream(3, 5));
        let field_w = config.earth_field_w();
        let errors: Vec<Vector3<f64>> = (0..30_000)
            .map(|k| mag.read(&truth_at(k as f64 / 50.0)).unwrap().field_b - field_w - bias)
            .collect();
        // 90 000 values: standard errors 0.02/300 on the mean, √(2/90000) ≈ 0.47 % on the variance.
        let (mean, var) = vec_stats(&errors);
        assert!(mean.abs() < 5.0 * 0.02 / 300.0, "mean {mean}");
        assert!((var / 0.0004 - 1.0).abs() < 5.0 * (2.0 / 90_000f64).sqrt(), "var {var}");
    }
}
