//! Magnetic heading fusion: the yaw of the measured field after removing the estimated roll and
//! pitch, compared with the estimated yaw; the Jacobian uses the reference field (declination
//! parameter, inclination from the alignment) and the magnetometer corrects only the yaw and the
//! gyro bias about the vertical (docs/navigation_filter.md §10).

use crate::math::{wrap_pi, UnitQuat, Vec3};

use super::alignment::{yaw_from_mag, MIN_HORIZONTAL_FIELD_SHARE};
use super::covariance::{fuse_shaped, ScalarObservation};
use super::fusion::{Fusion, FusionOutcome, SkipReason};
use super::params::MAG_TYPE_NONE;
use super::readings::{finite3, MagReading};
use super::state::{ErrorVector, ERR_ATT, ERR_GYRO_BIAS};
use super::NavFilter;

/// Heading innovation ν = ψ_m − ψ̂ [rad] of field `field_b` [gauss] measured at attitude `q_wb`
/// (docs/navigation_filter.md §10, eqs. (10.1)–(10.2)); `None` when the field's horizontal
/// part is too weak.
pub(super) fn heading_innovation(q_wb: &UnitQuat, field_b: &Vec3, declination_rad: f64) -> Option<f64> {
    let (roll, pitch, yaw) = q_wb.euler_angles();
    yaw_from_mag(roll, pitch, field_b, declination_rad).map(|measured| wrap_pi(measured - yaw))
}

/// tan of the inclination (down over horizontal) of field `field_b` [gauss] seen at attitude
/// `q_wb` [-] (docs/navigation_filter.md §10, eq. (10.3)); `None` for a (nearly) vertical field.
pub(super) fn tan_inclination(q_wb: &UnitQuat, field_b: &Vec3) -> Option<f64> {
    let m_w = q_wb * field_b;
    let horizontal = m_w.x.hypot(m_w.y);
    (horizontal > MIN_HORIZONTAL_FIELD_SHARE * m_w.norm() && horizontal > 0.0).then(|| m_w.z / horizontal)
}

/// ∂ν/∂δθ for world-frame attitude errors and a field of declination `declination_rad` [rad]
/// and inclination `tan_inclination` [-]: the yaw one to one, plus how a tilt error turns the
/// field's vertical part into a heading error (docs/navigation_filter.md §10, eq. (10.3)).
pub(super) fn heading_jacobian(declination_rad: f64, tan_inclination: f64) -> Vec3 {
    let (s, c) = declination_rad.sin_cos();
    Vec3::new(-c * tan_inclination, -s * tan_inclination, 1.0)
}

impl NavFilter {
    /// Fuses one magnetometer sample as a heading
    /// (docs/navigation_filter.md §10, eqs. (10.1)–(10.4)); before the alignment it feeds the
    /// alignment, and the first sample after an alignment without one sets the yaw
    /// (docs/navigation_filter.md §11, eq. (11.4)).
    pub fn fuse_mag(&mut self, mag: &MagReading) -> Fusion {
        let f = self.fuse_mag_sample(mag);
        self.mag.record(self.t_s, f.outcome);
        f
    }

    fn fuse_mag_sample(&mut self, mag: &MagReading) -> Fusion {
        if !(mag.t_s.is_finite() && finite3(&mag.field_b)) {
            return Fusion::skipped(SkipReason::Invalid);
        }
        if self.params.mag_type == MAG_TYPE_NONE {
            return Fusion::skipped(SkipReason::Inactive);
        }
        if !self.aligned {
            self.aligner.add_mag(&mag.field_b);
            return Fusion::skipped(SkipReason::NotAligned);
        }
        self.flush_covariance();
        if self.yaw_aligned && self.mag_tan_inclination.is_none() {
            // Started at a known attitude (`align_at`): the first sample gives the field's
            // inclination and is fused, not reset to (one noisy sample is a poor heading).
            self.mag_tan_inclination = tan_inclination(&self.x.q_wb, &mag.field_b);
        }
        let (true, Some(tan_incl)) = (self.yaw_aligned, self.mag_tan_inclination) else {
            return if self.reset_yaw_to_mag(&mag.field_b) {
                Fusion {
                    outcome: FusionOutcome::Reset,
                    test_ratio: 0.0,
                }
            } else {
                Fusion::skipped(SkipReason::Geometry)
            };
        };
        let Some(past) = self.buffer.at(mag.t_s - self.params.mag_delay_s) else {
            return Fusion::skipped(SkipReason::Stale);
        };
        let decl = self.params.mag_declination_rad;
        let Some(innovation) = heading_innovation(&past.q_wb, &mag.field_b, decl) else {
            return Fusion::skipped(SkipReason::Geometry);
        };
        let variance = self.params.heading_noise_rad.powi(2);
        self.fuse_heading(innovation, &heading_jacobian(decl, tan_incl), variance)
    }

    /// Fuses a heading innovation `innovation` [rad] with attitude Jacobian `h_att` and noise
    /// variance `variance` [rad²] behind the magnetometer's gate, correcting only the yaw and the
    /// gyro bias about the vertical (docs/navigation_filter.md §10, eq. (10.4)).
    fn fuse_heading(&mut self, innovation: f64, h_att: &Vec3, variance: f64) -> Fusion {
        let mut h = ErrorVector::zeros();
        h.fixed_rows_mut::<3>(ERR_ATT).copy_from(h_att);
        let obs = ScalarObservation {
            h,
            innovation,
            variance,
        };
        let d = self.x.q_wb.inverse_transform_vector(&Vec3::z());
        let update = fuse_shaped(&mut self.p, &obs, self.params.mag_gate_sd, |k| {
            let yaw = k[ERR_ATT + 2];
            let k_bg = d * d.dot(&k.fixed_rows::<3>(ERR_GYRO_BIAS));
            k.fill(0.0);
            k[ERR_ATT + 2] = yaw;
            k.fixed_rows_mut::<3>(ERR_GYRO_BIAS).copy_from(&k_bg);
        });
        self.innovations.heading_rad = innovation;
        self.innovations.heading_var = update.innovation_variance[0];
        self.preflight.heading(
            self.t_s,
            innovation,
            self.innovations.heading_var,
            self.params.mag_gate_sd,
        );
        self.ratios.heading = update.test_ratio;
        let outcome = match update.dx {
            Some(dx) => {
                self.apply(&dx);
                FusionOutcome::Fused
            }
            None => FusionOutcome::Rejected,
        };
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav_filter::{HeightSource, MagReading, NavFilter, NavParams};

    #[test]
    fn jacobian_matches_finite_differences_including_the_tilt_coupling() {
        let decl: f64 = 0.05;
        let field_w = Vec3::new(0.2 * decl.cos(), 0.2 * decl.sin(), 0.43);
        let q_true = UnitQuat::from_euler_angles(0.3, -0.2, 1.2);
        let m_b = q_true.inverse() * field_w;
        assert!(heading_innovation(&q_true, &m_b, decl).unwrap().abs() < 1e-12);
        let tan_incl = tan_inclination(&q_true, &m_b).unwrap();
        assert!((tan_incl - 0.43 / 0.2).abs() < 1e-12);
        let h = heading_jacobian(decl, tan_incl);
        let eps = 1e-6;
        for axis in 0..3 {
            // True = Exp(δθ) ⊗ estimate, so the estimate is Exp(−δθ) ⊗ true.
            let mut dtheta = Vec3::zeros();
            dtheta[axis] = eps;
            let q_est = UnitQuat::from_scaled_axis(-dtheta) * q_true;
            let nu = heading_innovation(&q_est, &m_b, decl).unwrap();
            assert!(
                (nu / eps - h[axis]).abs() < 1e-4,
                "axis {axis}: {} vs {}",
                nu / eps,
                h[axis]
            );
        }
        // A pure yaw error shows up one to one.
        let q_est = UnitQuat::from_scaled_axis(Vec3::new(0.0, 0.0, -0.1)) * q_true;
        assert!((heading_innovation(&q_est, &m_b, decl).unwrap() - 0.1).abs() < 1e-12);
        assert!(heading_innovation(&UnitQuat::identity(), &Vec3::new(0.0, 0.001, 0.5), 0.0).is_none());
        assert!(tan_inclination(&UnitQuat::identity(), &Vec3::new(0.0, 0.001, 0.5)).is_none());
    }

    #[test]
    fn heading_corrects_yaw_but_never_tilt() {
        let mut f = NavFilter::new(NavParams::default()).unwrap();
        // Aligned level, facing north; the truth has a yaw of 0.1 rad.
        f.aligned = true;
        f.yaw_aligned = true;
        f.mag_tan_inclination = Some(0.43 / 0.21);
        f.p =
            crate::nav_filter::alignment::initial_covariance(f.params(), HeightSource::Gps, &UnitQuat::identity(), 1.0);
        f.buffer.push(crate::nav_filter::delay_buffer::PastState::default());
        let decl = f.params().mag_declination_rad;
        let field_w = Vec3::new(0.21 * decl.cos(), 0.21 * decl.sin(), 0.43);
        let q_true = UnitQuat::from_euler_angles(0.0, 0.0, 0.1);
        let fusion = f.fuse_mag(&MagReading {
            t_s: 0.0,
            field_b: q_true.inverse() * field_w,
        });
        assert!(fusion.accepted(), "{fusion:?}");
        let (roll, pitch, yaw) = f.estimate().q_wb.euler_angles();
        assert_eq!((roll, pitch), (0.0, 0.0));
        assert!(yaw > 0.04, "{yaw}");
        assert_eq!(f.estimate().accel_bias_b, Vec3::zeros());
        assert!(f.covariance().symmetric_eigenvalues().min() > -1e-12);
    }
}
