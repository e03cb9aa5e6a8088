//! Magnetic heading fusion: the yaw of the measured field after removing the estimated roll and
//! pitch, compared with the estimated yaw; the Jacobian uses the reference field (declination
//! parameter, inclination from the alignment) and the magnetometer corrects only the yaw and the
//! gyro bias about the vertical (docs/navigation_filter.md §10).

use crate::math::{wrap_pi, UnitQuat, Vec3};

use super::alignment::{yaw_from_mag, MIN_HORIZONTAL_FIELD_SHARE};
use super::covariance::{fuse_shaped, ScalarObservation};
use super::error_state::ErrorStateFilter;
use super::fusion::{Fusion, FusionOutcome, SkipReason};
use super::nav_params::{HeightSource, NavParams, MAG_TYPE_NONE};
use super::readings::{finite3, MagReading};
use super::reporting::FilterReport;
use super::state::{ErrorVector, ERR_ATT, ERR_GYRO_BIAS};
use super::status::SourceTrack;

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

/// The magnetometer's heading: its counters, the field's inclination and whether the yaw is set
/// (docs/navigation_filter.md §10–§11).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct MagHeading {
    /// Counters and times of the magnetometer's samples.
    pub track: SourceTrack,
    /// tan of the field's inclination, taken when the yaw is set from the magnetometer [-].
    pub tan_inclination: Option<f64>,
    /// The yaw is set: from the magnetometer (at alignment or later) or a known attitude.
    pub yaw_aligned: bool,
}

impl MagHeading {
    /// Why reading `mag` is not offered at all: not finite, or the magnetometer is not fused
    /// (`EKF2_MAG_TYPE` 5) (docs/navigation_filter.md §20).
    pub fn unusable(mag: &MagReading, params: &NavParams) -> Option<SkipReason> {
        if !(mag.t_s.is_finite() && finite3(&mag.field_b)) {
            return Some(SkipReason::Invalid);
        }
        if params.mag_type == MAG_TYPE_NONE {
            return Some(SkipReason::Inactive);
        }
        None
    }

    /// Whether nothing was fused within `timeout_s` [s] of `now_s` [s]
    /// (docs/navigation_filter.md §18, eq. (18.7)).
    pub fn lost(&self, now_s: f64, timeout_s: f64) -> bool {
        self.track.last_fused_s.is_none_or(|t| now_s - t > timeout_s)
    }

    /// Fuses one magnetometer sample of an aligned filter as a heading
    /// (docs/navigation_filter.md §10, eqs. (10.1)–(10.4)); the first sample after an
    /// alignment without one sets the yaw (docs/navigation_filter.md §11, eq. (11.4)).
    /// `decl` is the declination in use [rad] (docs/navigation_filter.md §10, eq. (10.5)),
    /// `active_height` the height source the covariance prediction works with.
    pub fn fuse(
        &mut self,
        mag: &MagReading,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        decl: f64,
        active_height: HeightSource,
        report: &mut FilterReport,
    ) -> Fusion {
        core.flush_covariance(params, active_height);
        if self.yaw_aligned && self.tan_inclination.is_none() {
            // Started at a known attitude (`align_at`): the first sample gives the field's
            // inclination and is fused, not reset to (one noisy sample is a poor heading).
            self.tan_inclination = tan_inclination(&core.x.q_wb, &mag.field_b);
        }
        let (true, Some(tan_incl)) = (self.yaw_aligned, self.tan_inclination) else {
            return if self.reset_yaw(&mag.field_b, core, params, decl, report) {
                Fusion {
                    outcome: FusionOutcome::Reset,
                    test_ratio: 0.0,
                }
            } else {
                Fusion::skipped(SkipReason::Geometry)
            };
        };
        let Some(past) = core.past(mag.t_s - params.mag_delay_s) else {
            return Fusion::skipped(SkipReason::Stale);
        };
        let Some(innovation) = heading_innovation(&past.q_wb, &mag.field_b, decl) else {
            return Fusion::skipped(SkipReason::Geometry);
        };
        let variance = params.heading_noise_rad.powi(2);
        Self::fuse_heading(
            innovation,
            &heading_jacobian(decl, tan_incl),
            variance,
            core,
            params,
            report,
        )
    }

    /// Sets the yaw from one magnetometer sample `field_b` [gauss] with declination `decl` [rad],
    /// keeping roll and pitch; the attitude rows of P turn with the yaw change, the yaw row
    /// restarts as at alignment and a yaw reset is counted
    /// (docs/navigation_filter.md §11, eqs. (11.4)–(11.5)). False when the field gives no heading.
    pub fn reset_yaw(
        &mut self,
        field_b: &Vec3,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        decl: f64,
        report: &mut FilterReport,
    ) -> bool {
        let (roll, pitch, yaw) = core.x.q_wb.euler_angles();
        let Some(new_yaw) = yaw_from_mag(roll, pitch, field_b, decl) else {
            return false;
        };
        let Some(tan_incl) = self.tan_inclination.or_else(|| tan_inclination(&core.x.q_wb, field_b)) else {
            return false;
        };
        core.turn_yaw(wrap_pi(new_yaw - yaw), params);
        report.resets.yaw = report.resets.yaw.saturating_add(1);
        self.tan_inclination = Some(tan_incl);
        core.yaw_covariance_from_heading(&heading_jacobian(decl, tan_incl), params.heading_noise_rad);
        self.yaw_aligned = true;
        true
    }

    /// Fuses a heading innovation `innovation` [rad] with attitude Jacobian `h_att` and noise
    /// variance `variance` [rad²] behind the magnetometer's gate, correcting only the yaw and the
    /// gyro bias about the vertical (docs/navigation_filter.md §10, eq. (10.4)).
    fn fuse_heading(
        innovation: f64,
        h_att: &Vec3,
        variance: f64,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        report: &mut FilterReport,
    ) -> Fusion {
        let mut h = ErrorVector::zeros();
        h.fixed_rows_mut::<3>(ERR_ATT).copy_from(h_att);
        let obs = ScalarObservation {
            h,
            innovation,
            variance,
        };
        let d = core.x.q_wb.inverse_transform_vector(&Vec3::z());
        let update = fuse_shaped(&mut core.p, &obs, params.mag_gate_sd, |k| {
            let yaw = k[ERR_ATT + 2];
            let k_bg = d * d.dot(&k.fixed_rows::<3>(ERR_GYRO_BIAS));
            k.fill(0.0);
            k[ERR_ATT + 2] = yaw;
            k.fixed_rows_mut::<3>(ERR_GYRO_BIAS).copy_from(&k_bg);
        });
        report.innovations.heading_rad = innovation;
        report.innovations.heading_var = update.innovation_variance[0];
        report
            .preflight
            .heading(core.t_s, innovation, report.innovations.heading_var, params.mag_gate_sd);
        report.ratios.heading = update.test_ratio;
        let outcome = match update.dx {
            Some(dx) => {
                core.apply(&dx, params);
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
        f.alignment.aligned = true;
        f.mag.yaw_aligned = true;
        f.mag.tan_inclination = Some(0.43 / 0.21);
        let p =
            crate::nav_filter::alignment::initial_covariance(f.params(), HeightSource::Gps, &UnitQuat::identity(), 1.0);
        f.core.restart(crate::nav_filter::state::Nominal::default(), p);
        let decl = f.declination_rad();
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

    #[test]
    fn the_first_sample_after_an_alignment_without_a_heading_sets_the_yaw() {
        let params = NavParams::default();
        let mut core = ErrorStateFilter::new();
        let p =
            crate::nav_filter::alignment::initial_covariance(&params, HeightSource::Gps, &UnitQuat::identity(), 1.0);
        core.restart(crate::nav_filter::state::Nominal::default(), p);
        let mut report = FilterReport::default();
        let mut mag = MagHeading::default();
        let decl = params.mag_declination_rad;
        let field_w = Vec3::new(0.21 * decl.cos(), 0.21 * decl.sin(), 0.43);
        let q_true = UnitQuat::from_euler_angles(0.0, 0.0, 0.7);
        let reading = MagReading {
            t_s: 0.0,
            field_b: q_true.inverse() * field_w,
        };
        assert_eq!(MagHeading::unusable(&reading, &params), None);
        let f = mag.fuse(&reading, &mut core, &params, decl, HeightSource::Gps, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Reset);
        assert!(mag.yaw_aligned && mag.tan_inclination.is_some());
        assert_eq!(report.resets.yaw, 1);
        assert!((core.x.q_wb.euler_angles().2 - 0.7).abs() < 1e-9);
        // The next sample is fused as a heading.
        let f = mag.fuse(&reading, &mut core, &params, decl, HeightSource::Gps, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Fused);
        assert!(mag.lost(10.0, 1.0), "fusing is the caller's to record");
        mag.track.record(0.0, f.outcome);
        assert!(!mag.lost(0.5, 1.0));
        let silent = NavParams {
            mag_type: MAG_TYPE_NONE,
            ..params
        };
        assert_eq!(MagHeading::unusable(&reading, &silent), Some(SkipReason::Inactive));
    }
}
