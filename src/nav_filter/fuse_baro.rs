//! Barometric height: ISA altitude above the origin's, observed as height plus an offset state;
//! the active height source, or a secondary one that keeps its offset learned
//! (docs/navigation_filter.md §8–§9).

use super::aiding::Aiding;
use super::covariance::{fuse_group, innovation_variance, uncorrelate, ScalarObservation};
use super::error_state::ErrorStateFilter;
use super::fusion::{Fusion, FusionOutcome, SkipReason};
use super::height::HeightSelection;
use super::isa::pressure_altitude_m;
use super::nav_params::{HeightSource, NavParams};
use super::readings::BaroReading;
use super::reporting::FilterReport;
use super::state::{ErrorVector, ERR_BARO_OFFSET, ERR_POS};
use super::status::SourceTrack;

/// The barometer: the barometric altitude of the origin and the sensor's counters
/// (docs/navigation_filter.md §8).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct BaroAid {
    /// Barometric (ISA) altitude of the origin [m], from the alignment or the first sample.
    pub origin_m: Option<f64>,
    /// Counters and times of the barometer's samples.
    pub track: SourceTrack,
}

impl BaroAid {
    /// The ISA pressure altitude of `baro` [m], `None` when the reading is not valid
    /// (docs/navigation_filter.md §8, eq. (8.1)).
    pub fn altitude_m(baro: &BaroReading) -> Option<f64> {
        pressure_altitude_m(baro.pressure_pa).filter(|_| baro.t_s.is_finite())
    }

    /// Whether the barometer could take over the height at `now_s` [s]: an origin altitude and
    /// a sample within `timeout_s` [s] (docs/navigation_filter.md §9).
    pub fn available(&self, now_s: f64, timeout_s: f64) -> bool {
        self.origin_m.is_some() && self.track.last_received_s.is_some_and(|t| now_s - t <= timeout_s)
    }

    /// Fuses the altitude `altitude_m` [m] of a sample taken at `t_s` [s] by an aligned filter:
    /// `h_b = alt(p) − alt_0 = −p_z + b_h + n` (docs/navigation_filter.md §8, eqs. (8.1)–(8.3)).
    /// While the barometer is the active height source it corrects the height (its offset
    /// frozen); otherwise it is fused to learn the offset, which is re-learned from scratch
    /// after `height_timeout_s` of rejections (docs/navigation_filter.md §9).
    pub fn fuse(
        &mut self,
        altitude_m: f64,
        t_s: f64,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        height: &mut HeightSelection,
        report: &mut FilterReport,
    ) -> Fusion {
        if height.baro_fault {
            return Fusion::skipped(SkipReason::Fault);
        }
        core.flush_covariance(params, height.active);
        let Some(past) = core.past(t_s - params.baro_delay_s) else {
            return Fusion::skipped(SkipReason::Stale);
        };
        let predicted = -past.pos_w.z + core.x.baro_offset_m;
        let origin = *self.origin_m.get_or_insert(altitude_m - predicted);
        let innovation = altitude_m - origin - predicted;
        let mut h = ErrorVector::zeros();
        h[ERR_POS + 2] = -1.0;
        h[ERR_BARO_OFFSET] = 1.0;
        let obs = ScalarObservation {
            h,
            innovation,
            variance: params.baro_noise_m.powi(2),
        };
        report.innovations.baro_height_m = innovation;
        report.innovations.baro_height_var = innovation_variance(&core.p, &obs);
        report.preflight.baro_height(
            core.t_s,
            innovation,
            report.innovations.baro_height_var,
            params.baro_gate_sd,
        );
        let f = if height.active == HeightSource::Baro {
            height.fuse_active(HeightSource::Baro, &obs, params.baro_gate_sd, core, params, report)
        } else {
            self.fuse_secondary(&obs, core, params, height, report)
        };
        report.ratios.baro_height = f.test_ratio;
        f
    }

    /// The barometer while GNSS holds the height: fused for its offset; after
    /// `height_timeout_s` without a fused sample the offset is reset to the innovation
    /// (docs/navigation_filter.md §8, eq. (8.3)).
    fn fuse_secondary(
        &self,
        obs: &ScalarObservation,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        height: &mut HeightSelection,
        report: &mut FilterReport,
    ) -> Fusion {
        let now = core.t_s;
        let update = fuse_group(&mut core.p, std::slice::from_ref(obs), Some(params.baro_gate_sd));
        let outcome = if let Some(dx) = update.dx {
            core.apply(&dx, params);
            FusionOutcome::Fused
        } else if Aiding::timed_out(self.track.last_fused_s, now, params.height_timeout_s) {
            core.x.baro_offset_m += obs.innovation;
            uncorrelate(&mut core.p, ERR_BARO_OFFSET, obs.variance);
            report.resets.baro_offset = report.resets.baro_offset.saturating_add(1);
            FusionOutcome::Reset
        } else {
            FusionOutcome::Rejected
        };
        if height.reference == HeightSource::Baro {
            height.note_reference_test(outcome == FusionOutcome::Fused, now);
        }
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::UnitQuat;
    use crate::nav_filter::alignment::initial_covariance;
    use crate::nav_filter::state::Nominal;

    #[test]
    fn the_first_sample_sets_the_origin_and_a_faulty_barometer_is_never_fused() {
        let params = NavParams {
            height_ref: HeightSource::Baro,
            ..NavParams::default()
        };
        let mut core = ErrorStateFilter::new();
        let p = initial_covariance(&params, HeightSource::Baro, &UnitQuat::identity(), 1.0);
        core.restart(Nominal::default(), p);
        let mut height = HeightSelection::new(HeightSource::Baro);
        let mut report = FilterReport::default();
        let mut baro = BaroAid::default();
        let f = baro.fuse(120.0, 0.0, &mut core, &params, &mut height, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Fused);
        assert_eq!(baro.origin_m, Some(120.0));
        baro.track.record(0.0, f.outcome);
        assert!(baro.available(0.5, 1.0) && !baro.available(1.5, 1.0));
        let f = baro.fuse(121.0, 0.0, &mut core, &params, &mut height, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Fused);
        assert!(core.x.pos_w.z < -0.3, "1 m higher: {}", core.x.pos_w.z);
        assert_eq!(core.x.baro_offset_m, 0.0, "frozen while the barometer is active");
        assert_eq!(report.innovations.baro_height_m, 1.0);
        height.baro_fault = true;
        let f = baro.fuse(121.0, 0.0, &mut core, &params, &mut height, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Skipped(SkipReason::Fault));
        let invalid = BaroReading {
            t_s: 0.0,
            pressure_pa: -1.0,
            temperature_c: 15.0,
        };
        assert_eq!(BaroAid::altitude_m(&invalid), None);
    }
}
