//! GNSS fusion: quality checks, the origin, delayed velocity and position observations, resets
//! at the start of aiding or after a long rejection, and GNSS height while it is the active
//! height source (docs/navigation_filter.md §6–§7, §9).

use crate::math::Vec3;

use super::covariance::{innovation_variance, uncorrelate, ScalarObservation};
use super::datum::GnssDatum;
use super::delay_buffer::PastState;
use super::error_state::ErrorStateFilter;
use super::fusion::{Fusion, FusionOutcome, GpsFusion, SkipReason};
use super::height::HeightSelection;
use super::nav_params::{HeightSource, NavParams, GPS_CTRL_FUSED};
use super::readings::GpsReading;
use super::reporting::FilterReport;
use super::state::{ERR_POS, ERR_VEL};
use super::status::SourceTrack;

/// The GNSS receiver: where the filter's origin lies among its readings, and its counters
/// (docs/navigation_filter.md §6).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct GnssAid {
    /// Counters and times of the fixes.
    pub track: SourceTrack,
    /// The filter's origin in the GNSS readings' NED frame [m], set at the first usable fix.
    pub origin_w: Option<Vec3>,
    /// The vertical part of `origin_w` (docs/navigation_filter.md §6, eq. (6.5)).
    datum: GnssDatum,
}

/// A usable fix on its way through the three fusions, each against the history as the one
/// before left it (docs/navigation_filter.md §6, eq. (6.1);
/// docs/navigation_filter.md §7, eqs. (7.1)–(7.3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PreparedFix {
    /// Time of validity t_m [s].
    t_meas_s: f64,
    /// The nominal state at `t_meas_s`, as last looked up.
    past: PastState,
    /// Position in the filter's frame [m].
    pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Horizontal position noise variance [m²] (docs/navigation_filter.md §6, eq. (6.2)).
    var_h: f64,
    /// Vertical position noise variance [m²].
    var_v: f64,
    /// Velocity noise variance [m²/s²].
    pub var_vel: f64,
    /// Horizontal position innovation [m], once computed.
    nu_pos_w: Vec3,
}

impl GnssAid {
    /// Stops averaging the height datum (docs/navigation_filter.md §6, eq. (6.5)).
    pub fn freeze_datum(&mut self) {
        self.datum.freeze();
    }

    /// Whether the origin is known and a fix was fused within `timeout_s` [s] of `now_s` [s]:
    /// GNSS could take over the height (docs/navigation_filter.md §9).
    pub fn available(&self, now_s: f64, timeout_s: f64) -> bool {
        self.origin_w.is_some() && self.track.last_fused_s.is_some_and(|t| now_s - t <= timeout_s)
    }

    /// Counts a fix received at `now_s` [s] with the outcomes of its parts
    /// (docs/navigation_filter.md §13).
    pub fn record(&mut self, now_s: f64, result: &GpsFusion) {
        self.track.record_parts(
            now_s,
            &[
                result.velocity.outcome,
                result.horizontal.outcome,
                result.vertical.outcome,
            ],
        );
    }

    /// Whether the receiver's own figures allow the fix (PX4's `EKF2_GPS_CHECK` subset)
    /// (docs/navigation_filter.md §6).
    fn quality_ok(gps: &GpsReading, p: &NavParams) -> bool {
        gps.fix_3d
            && gps.satellites >= p.gps_min_satellites
            && gps.h_acc_m <= p.gps_max_h_acc_m
            && gps.v_acc_m <= p.gps_max_v_acc_m
            && gps.speed_acc_m_s <= p.gps_max_speed_acc_m_s
    }

    /// Checks fix `gps` arriving at `gps.t_s`, valid at `t_s − gps_delay_s`, for a filter that
    /// is `aligned`; predicts the covariance (with `active_height`), finds the state at the time
    /// of validity and sets the origin (docs/navigation_filter.md §6, eqs. (6.2)–(6.3), (6.5);
    /// docs/navigation_filter.md §7, eq. (7.2)). The reason when the fix is skipped.
    pub fn prepare(
        &mut self,
        gps: &GpsReading,
        aligned: bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        active_height: HeightSource,
    ) -> Result<PreparedFix, SkipReason> {
        if !gps.is_finite() {
            return Err(SkipReason::Invalid);
        }
        if !aligned {
            return Err(SkipReason::NotAligned);
        }
        if params.gps_ctrl & GPS_CTRL_FUSED == 0 {
            return Err(SkipReason::Inactive);
        }
        if !Self::quality_ok(gps, params) {
            return Err(SkipReason::Quality);
        }
        core.flush_covariance(params, active_height);
        let t_meas = gps.t_s - params.gps_delay_s;
        let Some(past) = core.past(t_meas) else {
            return Err(SkipReason::Stale);
        };
        let origin = self.origin_w.get_or_insert(gps.pos_w - past.pos_w);
        origin.z = self.datum.observe(gps.pos_w.z, past.pos_w.z, past.vel_w.norm());
        let origin = *origin;
        let p = params;
        Ok(PreparedFix {
            t_meas_s: t_meas,
            past,
            pos_w: gps.pos_w - origin,
            vel_w: gps.vel_w,
            var_h: p.gps_pos_noise_m.max(gps.h_acc_m).powi(2),
            var_v: (1.5 * p.gps_pos_noise_m).max(gps.v_acc_m).powi(2),
            var_vel: p.gps_vel_noise_m_s.max(gps.speed_acc_m_s).powi(2),
            nu_pos_w: Vec3::zeros(),
        })
    }
}

impl PreparedFix {
    /// Velocity (6.1): ν = v_gps − v̂(t_m), fused behind `gps_vel_gate_sd`, or the velocity
    /// reset to it when `reset` (docs/navigation_filter.md §6, eq. (6.4)).
    pub fn fuse_velocity(
        &self,
        reset: bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        report: &mut FilterReport,
    ) -> Fusion {
        let p = params;
        let now = core.t_s;
        let nu_vel = self.vel_w - self.past.vel_w;
        let velocity = if reset {
            core.x.vel_w += nu_vel;
            core.correct_history(p, &Vec3::zeros(), &nu_vel, &Vec3::zeros());
            for i in 0..3 {
                uncorrelate(&mut core.p, ERR_VEL + i, self.var_vel);
            }
            report.resets.velocity = report.resets.velocity.saturating_add(1);
            Fusion {
                outcome: FusionOutcome::Reset,
                test_ratio: 0.0,
            }
        } else {
            let group = [0, 1, 2].map(|i| ScalarObservation::of_state(ERR_VEL + i, nu_vel[i], self.var_vel));
            let (f, var) = core.fuse_gated(&group, p.gps_vel_gate_sd, p);
            report.innovations.gps_vel_var = var;
            report.ratios.gps_velocity = f.test_ratio;
            let var = report.innovations.gps_vel_var;
            report.preflight.velocity(now, &nu_vel, &var, p.gps_vel_gate_sd);
            f
        };
        report.innovations.gps_vel_w = nu_vel;
        velocity
    }

    /// Horizontal position (6.1), against the history as corrected by the velocity, fused
    /// behind `gps_pos_gate_sd`, or reset to when `reset`
    /// (docs/navigation_filter.md §6, eq. (6.4)).
    pub fn fuse_horizontal(
        &mut self,
        reset: bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        report: &mut FilterReport,
    ) -> Fusion {
        let p = params;
        let now = core.t_s;
        self.past = core.past(self.t_meas_s).unwrap_or(self.past);
        let nu_pos = self.pos_w - self.past.pos_w;
        self.nu_pos_w = nu_pos;
        if reset {
            let d = Vec3::new(nu_pos.x, nu_pos.y, 0.0);
            core.x.pos_w += d;
            core.correct_history(p, &d, &Vec3::zeros(), &Vec3::zeros());
            uncorrelate(&mut core.p, ERR_POS, self.var_h);
            uncorrelate(&mut core.p, ERR_POS + 1, self.var_h);
            report.resets.horizontal_position = report.resets.horizontal_position.saturating_add(1);
            Fusion {
                outcome: FusionOutcome::Reset,
                test_ratio: 0.0,
            }
        } else {
            let group = [0, 1].map(|i| ScalarObservation::of_state(ERR_POS + i, nu_pos[i], self.var_h));
            let (f, v) = core.fuse_gated(&group, p.gps_pos_gate_sd, p);
            report.innovations.gps_pos_var.x = v.x;
            report.innovations.gps_pos_var.y = v.y;
            report.ratios.gps_horizontal = f.test_ratio;
            let var = report.innovations.gps_pos_var;
            report
                .preflight
                .position(now, (nu_pos.x, nu_pos.y), (var.x, var.y), p.gps_pos_gate_sd);
            f
        }
    }

    /// Height (6.1): fused while GNSS is the active height source in `height`, otherwise only
    /// its test ratio is computed (docs/navigation_filter.md §9).
    pub fn fuse_height(
        &self,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        height: &mut HeightSelection,
        report: &mut FilterReport,
    ) -> Fusion {
        let p = params;
        let now = core.t_s;
        let past = core.past(self.t_meas_s).unwrap_or(self.past);
        let nu_z = self.pos_w.z - past.pos_w.z;
        report.innovations.gps_pos_w = Vec3::new(self.nu_pos_w.x, self.nu_pos_w.y, nu_z);
        let obs = ScalarObservation::of_state(ERR_POS + 2, nu_z, self.var_v);
        let s = innovation_variance(&core.p, &obs);
        report.innovations.gps_pos_var.z = s;
        report.preflight.gps_height(now, nu_z, s, p.gps_pos_gate_sd);
        let vertical = if height.active == HeightSource::Gps {
            height.fuse_active(HeightSource::Gps, &obs, p.gps_pos_gate_sd, core, p, report)
        } else {
            let ratio = nu_z * nu_z / (p.gps_pos_gate_sd.powi(2) * s);
            if height.reference == HeightSource::Gps {
                height.note_reference_test(ratio <= 1.0, now);
            }
            Fusion {
                outcome: FusionOutcome::Skipped(SkipReason::Inactive),
                test_ratio: ratio,
            }
        };
        report.ratios.gps_height = vertical.test_ratio;
        vertical
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::UnitQuat;
    use crate::nav_filter::alignment::initial_covariance;
    use crate::nav_filter::readings::ImuReading;
    use crate::nav_filter::state::Nominal;

    fn reading(t_s: f64, pos_w: Vec3) -> GpsReading {
        GpsReading {
            t_s,
            pos_w,
            vel_w: Vec3::zeros(),
            h_acc_m: 0.5,
            v_acc_m: 0.8,
            speed_acc_m_s: 0.2,
            fix_3d: true,
            satellites: 10,
        }
    }

    /// An aligned core filter at rest at the origin with history from 0 to 1 s at 100 Hz.
    fn core_for_a_second(params: &NavParams) -> ErrorStateFilter {
        let mut core = ErrorStateFilter::new();
        let p = initial_covariance(params, HeightSource::Gps, &UnitQuat::identity(), 1.0);
        let still = |k: u32| ImuReading {
            t_s: 0.01 * f64::from(k),
            accel_b: Vec3::new(0.0, 0.0, -crate::math::GRAVITY_M_S2),
            gyro_b: Vec3::zeros(),
        };
        core.accept_imu(&still(0));
        core.restart(Nominal::default(), p);
        for k in 1..=100 {
            let prev = core.accept_imu(&still(k)).unwrap();
            core.propagate(prev, &still(k), params.output_tau_s);
        }
        core
    }

    #[test]
    fn skips_come_before_the_state_is_touched_and_the_first_fix_sets_the_origin() {
        let params = NavParams::default();
        let mut core = core_for_a_second(&params);
        let mut gnss = GnssAid::default();
        let at = Vec3::new(100.0, -50.0, -3.0);
        let bad = GpsReading {
            satellites: 4,
            ..reading(1.0, at)
        };
        let gps = HeightSource::Gps;
        let good = reading(1.11, at);
        assert_eq!(
            gnss.prepare(&good, false, &mut core, &params, gps),
            Err(SkipReason::NotAligned)
        );
        assert_eq!(
            gnss.prepare(&bad, true, &mut core, &params, gps),
            Err(SkipReason::Quality)
        );
        assert_eq!(
            gnss.prepare(&reading(0.1, at), true, &mut core, &params, gps),
            Err(SkipReason::Stale),
            "valid before the history"
        );
        assert_eq!(gnss.origin_w, None);
        let fix = gnss
            .prepare(&reading(1.11, at), true, &mut core, &params, HeightSource::Gps)
            .unwrap();
        assert_eq!(gnss.origin_w, Some(at), "the estimate continues where it was");
        assert_eq!(fix.pos_w, Vec3::zeros());
        assert_eq!(fix.var_h, 0.25);
        let inactive = NavParams { gps_ctrl: 0, ..params };
        assert_eq!(
            gnss.prepare(&reading(1.11, at), true, &mut core, &inactive, HeightSource::Gps),
            Err(SkipReason::Inactive)
        );
    }

    #[test]
    fn the_first_fixes_reset_and_later_ones_are_fused_each_part_on_its_own() {
        let params = NavParams::default();
        let mut core = core_for_a_second(&params);
        let mut gnss = GnssAid::default();
        let mut height = HeightSelection::new(HeightSource::Gps);
        let mut report = FilterReport::default();
        let moving = GpsReading {
            vel_w: Vec3::new(1.0, 0.0, 0.0),
            ..reading(1.11, Vec3::zeros())
        };
        let mut fix = gnss
            .prepare(&moving, true, &mut core, &params, HeightSource::Gps)
            .unwrap();
        let velocity = fix.fuse_velocity(true, &mut core, &params, &mut report);
        assert_eq!(velocity.outcome, FusionOutcome::Reset);
        assert_eq!(core.x.vel_w, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(report.resets.velocity, 1);
        let horizontal = fix.fuse_horizontal(false, &mut core, &params, &mut report);
        assert_eq!(horizontal.outcome, FusionOutcome::Fused);
        let vertical = fix.fuse_height(&mut core, &params, &mut height, &mut report);
        assert_eq!(vertical.outcome, FusionOutcome::Fused);
        assert_eq!(height.last_fused_s(HeightSource::Gps), Some(1.0));
        // GNSS height while the barometer holds the height: only its test ratio.
        height.active = HeightSource::Baro;
        let vertical = fix.fuse_height(&mut core, &params, &mut height, &mut report);
        assert_eq!(vertical.outcome, FusionOutcome::Skipped(SkipReason::Inactive));
        gnss.record(
            1.0,
            &GpsFusion {
                velocity,
                horizontal,
                vertical,
            },
        );
        assert!(gnss.available(1.5, 1.0) && !gnss.available(2.5, 1.0));
    }
}
