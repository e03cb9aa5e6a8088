//! The magnetometer: a constant Earth field rotated into body FRD, with white noise and a
//! constant hard-iron bias (docs/model.md §10.5, eqs. (10.12)–(10.14)).
//!
//! The field is the World Magnetic Model's at the vehicle's home ([`super::earth_field`];
//! docs/model.md §10.5, eq. (10.19)), fixed for the run; an airframe file may fix its strength, declination D (east of
//! true north) or inclination I (below the horizontal) instead.
//!
//! Faults (docs/model.md §10.6): `Wrong` adds 0.3 G on every axis, as a magnet or a current-
//! carrying wire next to the compass would; `Garbage` draws every axis uniformly over ±4 G
//! (a LIS3MDL's smallest range).

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

use super::earth_field::{EarthField, EarthFieldError, GeoSite};
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
    /// Earth field strength F [gauss]; `None`: the World Magnetic Model's at home.
    pub strength_gauss: Option<f64>,
    /// Declination D, positive east of true north [rad]; `None`: the model's at home.
    pub declination_rad: Option<f64>,
    /// Inclination I, positive below the horizontal [rad]; `None`: the model's at home.
    pub inclination_rad: Option<f64>,
    /// White noise, standard deviation per axis [gauss].
    pub noise_gauss: f64,
    /// Constant hard-iron bias in body FRD [gauss].
    pub bias_b_gauss: Vector3<f64>,
}

impl MagConfig {
    /// 50 Hz in the World Magnetic Model's field at home (at PX4's default home F = 0.483 G,
    /// D = 3.42°, I = 63.50°). Noise 0.02 G per axis, PX4 SITL's horizontal figure
    /// (EKF2_MAG_NOISE = 0.05 G is the estimator's cautious one); no hard-iron bias, as PX4 SITL
    /// by default (a calibrated compass).
    pub fn typical() -> Self {
        Self {
            rate_hz: 50.0,
            strength_gauss: None,
            declination_rad: None,
            inclination_rad: None,
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

    /// The Earth field this magnetometer reads at `home`: the World Magnetic Model's there
    /// (docs/model.md §10.5, eq. (10.19)), with the parts this configuration fixes in place of the
    /// model's (no look-up when it fixes all three).
    pub fn field_at(&self, home: &GeoSite) -> Result<EarthField, EarthFieldError> {
        let model = match (self.strength_gauss, self.declination_rad, self.inclination_rad) {
            (Some(strength_gauss), Some(declination_rad), Some(inclination_rad)) => EarthField {
                strength_gauss,
                declination_rad,
                inclination_rad,
            },
            _ => EarthField::at(home)?,
        };
        Ok(EarthField {
            strength_gauss: self.strength_gauss.unwrap_or(model.strength_gauss),
            declination_rad: self.declination_rad.unwrap_or(model.declination_rad),
            inclination_rad: self.inclination_rad.unwrap_or(model.inclination_rad),
        })
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
    /// A magnetometer in the Earth field `field`.
    pub(crate) fn new(config: MagConfig, field: &EarthField, rng: ChaCha8Rng) -> Self {
        Self {
            config,
            field_w: field.field_w(),
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

    const HOME: GeoSite = GeoSite::PX4_DEFAULT_HOME;

    #[test]
    fn field_is_the_models_at_home_unless_fixed() {
        let model = EarthField::at(&HOME).unwrap();
        assert_eq!(MagConfig::typical().field_at(&HOME).unwrap(), model);
        let cmac = GeoSite {
            lat_deg: -35.363261,
            lon_deg: 149.165230,
            alt_m: 584.0,
        };
        let down_under = MagConfig::typical().field_at(&cmac).unwrap();
        assert!(down_under.field_w().z < 0.0, "points up in the southern hemisphere");
        // docs/model.md §10.5, eq. (10.14): one part fixed, the others the model's.
        let c = MagConfig {
            declination_rad: Some(-0.2),
            ..MagConfig::typical()
        };
        let f = c.field_at(&HOME).unwrap();
        assert_eq!(f.declination_rad, -0.2);
        assert_eq!(
            (f.strength_gauss, f.inclination_rad),
            (model.strength_gauss, model.inclination_rad)
        );
        // All three fixed: no look-up, so no place is needed.
        let fixed = MagConfig {
            strength_gauss: Some(0.5),
            declination_rad: Some(0.1),
            inclination_rad: Some(1.0),
            ..MagConfig::typical()
        };
        let nowhere = GeoSite {
            lat_deg: f64::NAN,
            ..HOME
        };
        assert_eq!(
            fixed.field_at(&nowhere),
            Ok(EarthField {
                strength_gauss: 0.5,
                declination_rad: 0.1,
                inclination_rad: 1.0
            })
        );
        assert!(MagConfig::typical().field_at(&nowhere).is_err());
    }

    #[test]
    fn ideal_magnetometer_reads_the_field_in_body_axes_at_fifty_hertz() {
        let c = MagConfig::ideal();
        let field = c.field_at(&HOME).unwrap();
        let mut mag = MagModel::new(c, &field, seeded_stream(1, 5));
        let yaw = 30f64.to_radians();
        let mut n = 0;
        for i in 0..10_000 {
            let mut truth = truth_at(tick_s(i));
            truth.body.q_wb = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
            if let Some(s) = mag.read(&truth) {
                assert_eq!(s.field_b, truth.body.q_wb.inverse_transform_vector(&field.field_w()));
                // Heading from the level body field: ψ = D − atan2(m_y, m_x).
                let heading = field.declination_rad - s.field_b.y.atan2(s.field_b.x);
                assert!((heading - yaw).abs() < 1e-12);
                assert!((s.field_b.norm() - field.strength_gauss).abs() < 1e-12);
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
        let field = config.field_at(&HOME).unwrap();
        let mut mag = MagModel::new(config, &field, seeded_stream(3, 5));
        let field_w = field.field_w();
        let errors: Vec<Vector3<f64>> = (0..30_000)
            .map(|k| mag.read(&truth_at(k as f64 / 50.0)).unwrap().field_b - field_w - bias)
            .collect();
        // 90 000 values: standard errors 0.02/300 on the mean, √(2/90000) ≈ 0.47 % on the variance.
        let (mean, var) = vec_stats(&errors);
        assert!(mean.abs() < 5.0 * 0.02 / 300.0, "mean {mean}");
        assert!((var / 0.0004 - 1.0).abs() < 5.0 * (2.0 / 90_000f64).sqrt(), "var {var}");
    }
}
