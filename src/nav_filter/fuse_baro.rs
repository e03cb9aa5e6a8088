//! Barometric height: ISA altitude above the origin's, observed as height plus an offset state;
//! the active height source, or a secondary one that keeps its offset learned
//! (docs/navigation_filter.md §8–§9).

use super::aiding::Aiding;
use super::covariance::{fuse_group, innovation_variance, uncorrelate, ScalarObservation};
use super::fusion::{Fusion, FusionOutcome, SkipReason};
use super::isa::pressure_altitude_m;
use super::params::HeightSource;
use super::readings::BaroReading;
use super::state::{ErrorVector, ERR_BARO_OFFSET, ERR_POS};
use super::NavFilter;

impl NavFilter {
    /// Fuses one barometer sample: `h_b = alt(p) − alt_0 = −p_z + b_h + n`
    /// (docs/navigation_filter.md §8, eqs. (8.1)–(8.3)). While the barometer is the active height
    /// source it corrects the height (its offset frozen); otherwise it is fused to learn the
    /// offset, which is re-learned from scratch after `height_timeout_s` of rejections
    /// (docs/navigation_filter.md §9).
    pub fn fuse_baro(&mut self, baro: &BaroReading) -> Fusion {
        let f = self.fuse_baro_sample(baro);
        self.baro.record(self.t_s, f.outcome);
        f
    }

    fn fuse_baro_sample(&mut self, baro: &BaroReading) -> Fusion {
        let Some(altitude_m) = pressure_altitude_m(baro.pressure_pa).filter(|_| baro.t_s.is_finite()) else {
            return Fusion::skipped(SkipReason::Invalid);
        };
        if !self.aligned {
            self.aligner.add_baro(altitude_m);
            return Fusion::skipped(SkipReason::NotAligned);
        }
        if self.height.baro_fault {
            return Fusion::skipped(SkipReason::Fault);
        }
        self.flush_covariance();
        let Some(past) = self.buffer.at(baro.t_s - self.params.baro_delay_s) else {
            return Fusion::skipped(SkipReason::Stale);
        };
        let predicted = -past.pos_w.z + self.x.baro_offset_m;
        let origin = *self.baro_origin_m.get_or_insert(altitude_m - predicted);
        let innovation = altitude_m - origin - predicted;
        let mut h = ErrorVector::zeros();
        h[ERR_POS + 2] = -1.0;
        h[ERR_BARO_OFFSET] = 1.0;
        let obs = ScalarObservation {
            h,
            innovation,
            variance: self.params.baro_noise_m.powi(2),
        };
        self.innovations.baro_height_m = innovation;
        self.innovations.baro_height_var = innovation_variance(&self.p, &obs);
        self.preflight.baro_height(
            self.t_s,
            innovation,
            self.innovations.baro_height_var,
            self.params.baro_gate_sd,
        );
        let f = if self.height.active == HeightSource::Baro {
            self.fuse_active_height(HeightSource::Baro, &obs, self.params.baro_gate_sd)
        } else {
            self.fuse_secondary_baro(&obs)
        };
        self.ratios.baro_height = f.test_ratio;
        f
    }

    /// The barometer while GNSS holds the height: fused for its offset; after
    /// `height_timeout_s` without a fused sample the offset is reset to the innovation
    /// (docs/navigation_filter.md §8, eq. (8.3)).
    fn fuse_secondary_baro(&mut self, obs: &ScalarObservation) -> Fusion {
        let now = self.t_s;
        let update = fuse_group(&mut self.p, std::slice::from_ref(obs), Some(self.params.baro_gate_sd));
        let outcome = if let Some(dx) = update.dx {
            self.apply(&dx);
            FusionOutcome::Fused
        } else if Aiding::timed_out(self.baro.last_fused_s, now, self.params.height_timeout_s) {
            self.x.baro_offset_m += obs.innovation;
            uncorrelate(&mut self.p, ERR_BARO_OFFSET, obs.variance);
            self.resets.baro_offset = self.resets.baro_offset.saturating_add(1);
            FusionOutcome::Reset
        } else {
            FusionOutcome::Rejected
        };
        if self.height.reference == HeightSource::Baro {
            self.height.note_reference_test(outcome == FusionOutcome::Fused, now);
        }
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }
}
