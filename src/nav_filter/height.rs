//! Which height source is fused: the reference (`EKF2_HGT_REF`) while it works, the other one
//! after a time-out, back to the reference once it has passed its gate for a while; height
//! resets when a source takes over; a barometer that failed its gate while it kept delivering is
//! at fault and never fused again (docs/navigation_filter.md §9).

use crate::math::Vec3;

use super::covariance::{fuse_group, uncorrelate, ScalarObservation};
use super::error_state::ErrorStateFilter;
use super::fusion::{Fusion, FusionOutcome};
use super::nav_params::{HeightSource, NavParams};
use super::reporting::FilterReport;
use super::state::{ERR_BARO_OFFSET, ERR_POS};
use super::status::ResetCounters;

/// State of the height-source choice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct HeightSelection {
    /// The configured reference.
    pub reference: HeightSource,
    /// The source fused for height now.
    pub active: HeightSource,
    /// When `active` became active [s].
    pub active_since_s: f64,
    /// The next sample of the active source resets the height if it fails its gate.
    pub reset_pending: bool,
    /// Since when the (inactive) reference has passed its gate without a break [s].
    pub reference_passing_since_s: Option<f64>,
    /// Last time each source was fused as height (barometer, GNSS) [s].
    last_fused_s: [Option<f64>; 2],
    /// The barometer failed its gate as the active source for `height_timeout_s` while it kept
    /// delivering: stuck or wrong, it is not fused again (PX4's `baro_fault`).
    pub baro_fault: bool,
}

fn slot(s: HeightSource) -> usize {
    match s {
        HeightSource::Baro => 0,
        HeightSource::Gps => 1,
    }
}

impl HeightSelection {
    /// Starts on the reference.
    pub fn new(reference: HeightSource) -> Self {
        Self {
            reference,
            active: reference,
            active_since_s: 0.0,
            reset_pending: false,
            reference_passing_since_s: None,
            last_fused_s: [None; 2],
            baro_fault: false,
        }
    }

    /// Last time `s` was fused as height [s].
    pub fn last_fused_s(&self, s: HeightSource) -> Option<f64> {
        self.last_fused_s[slot(s)]
    }

    /// Notes that `s` was fused (or reset to) at `t_s` [s].
    pub fn mark_fused(&mut self, s: HeightSource, t_s: f64) {
        self.last_fused_s[slot(s)] = Some(t_s);
    }

    /// Notes whether the inactive reference passed its gate at `t_s` [s].
    pub fn note_reference_test(&mut self, passed: bool, t_s: f64) {
        self.reference_passing_since_s = if passed {
            self.reference_passing_since_s.or(Some(t_s))
        } else {
            None
        };
    }

    /// Whether the active height source was fused within `timeout_s` [s] of `now_s` [s]
    /// (docs/navigation_filter.md §12, eq. (12.1)).
    pub fn fused_recently(&self, now_s: f64, timeout_s: f64) -> bool {
        self.last_fused_s(self.active).is_some_and(|t| now_s - t <= timeout_s)
    }

    /// The time-driven rules: fall back after `height_timeout_s` without a fused height sample,
    /// return to the reference after it has passed its gate for `height_timeout_s`;
    /// `available` says whether a source could take over the height now
    /// (docs/navigation_filter.md §9).
    pub fn update(
        &mut self,
        available: impl Fn(HeightSource) -> bool,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        resets: &mut ResetCounters,
    ) {
        let h = *self;
        let timeout = params.height_timeout_s;
        let last = h
            .last_fused_s(h.active)
            .map_or(h.active_since_s, |t| t.max(h.active_since_s));
        if core.t_s - last > timeout {
            let other = h.active.other();
            if available(other) {
                // A barometer that kept delivering while it failed its gate is at fault.
                if h.active == HeightSource::Baro && available(HeightSource::Baro) {
                    self.baro_fault = true;
                }
                self.switch(other, core, params, resets);
            } else {
                self.reset_pending = true;
            }
        } else if h.active != h.reference
            && h.reference_passing_since_s.is_some_and(|s| core.t_s - s >= timeout)
            && available(h.reference)
            && !(h.reference == HeightSource::Baro && h.baro_fault)
        {
            self.switch(h.reference, core, params, resets);
        }
    }

    /// Makes `to` the active height source; the barometer offset is frozen while the barometer is
    /// active (docs/navigation_filter.md §8, eq. (8.3); docs/navigation_filter.md §9).
    pub fn switch(
        &mut self,
        to: HeightSource,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        resets: &mut ResetCounters,
    ) {
        if to == HeightSource::Baro {
            uncorrelate(&mut core.p, ERR_BARO_OFFSET, 0.0);
        } else if core.p[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)] <= 0.0 {
            uncorrelate(&mut core.p, ERR_BARO_OFFSET, params.baro_noise_m.powi(2));
        }
        self.active = to;
        self.active_since_s = core.t_s;
        self.reset_pending = true;
        self.reference_passing_since_s = None;
        resets.height_source_changes = resets.height_source_changes.saturating_add(1);
    }

    /// Fuses one height observation of the active source `source` behind gate `gate_sd` [SD]; when
    /// it fails its gate and a reset is pending, the height is reset to it instead
    /// (docs/navigation_filter.md §5, eqs. (5.2)–(5.7); docs/navigation_filter.md §9).
    pub fn fuse_active(
        &mut self,
        source: HeightSource,
        obs: &ScalarObservation,
        gate_sd: f64,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        report: &mut FilterReport,
    ) -> Fusion {
        let update = fuse_group(&mut core.p, std::slice::from_ref(obs), Some(gate_sd));
        let outcome = if let Some(dx) = update.dx {
            core.apply(&dx, params);
            FusionOutcome::Fused
        } else if self.reset_pending {
            Self::reset_height(obs, core, params, &mut report.resets);
            FusionOutcome::Reset
        } else {
            FusionOutcome::Rejected
        };
        if outcome != FusionOutcome::Rejected {
            self.mark_fused(source, core.t_s);
            self.reset_pending = false;
        }
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }

    /// Moves the height so that `obs` has no innovation, and restarts its variance at the
    /// measurement's (docs/navigation_filter.md §6, eq. (6.4)).
    fn reset_height(
        obs: &ScalarObservation,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        resets: &mut ResetCounters,
    ) {
        let c = obs.h[ERR_POS + 2];
        if c == 0.0 {
            return;
        }
        let dz = obs.innovation / c;
        core.x.pos_w.z += dz;
        core.correct_history(params, &Vec3::new(0.0, 0.0, dz), &Vec3::zeros(), &Vec3::zeros());
        uncorrelate(&mut core.p, ERR_POS + 2, obs.variance);
        resets.height = resets.height.saturating_add(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn core_at(t_s: f64) -> ErrorStateFilter {
        let mut core = ErrorStateFilter::new();
        core.t_s = t_s;
        core
    }

    #[test]
    fn falls_back_after_the_time_out_and_returns_to_the_reference() {
        let params = NavParams::default();
        let timeout = params.height_timeout_s;
        let mut resets = ResetCounters::default();
        let mut h = HeightSelection::new(HeightSource::Gps);
        h.mark_fused(HeightSource::Gps, 0.0);
        assert!(h.fused_recently(timeout, timeout));
        let mut core = core_at(timeout + 0.1);
        h.update(|_| false, &mut core, &params, &mut resets);
        assert_eq!(h.active, HeightSource::Gps, "no alternative");
        assert!(h.reset_pending);
        h.update(|s| s == HeightSource::Baro, &mut core, &params, &mut resets);
        assert_eq!(h.active, HeightSource::Baro);
        assert_eq!(resets.height_source_changes, 1);
        assert_eq!(core.p[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)], 0.0, "offset frozen");
        // The reference passes its gate for the time-out: back to it.
        h.mark_fused(HeightSource::Baro, core.t_s);
        h.note_reference_test(true, core.t_s);
        let mut core = core_at(core.t_s + timeout);
        h.update(|_| true, &mut core, &params, &mut resets);
        assert_eq!(h.active, HeightSource::Gps);
        assert_eq!(resets.height_source_changes, 2);
        assert_eq!(
            core.p[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)],
            params.baro_noise_m.powi(2),
            "offset learned again"
        );
    }

    #[test]
    fn a_pending_reset_moves_the_height_to_a_rejected_sample() {
        let params = NavParams::default();
        let mut core = core_at(1.0);
        core.p[(ERR_POS + 2, ERR_POS + 2)] = 0.01;
        let mut report = FilterReport::default();
        let mut h = HeightSelection::new(HeightSource::Gps);
        let obs = ScalarObservation::of_state(ERR_POS + 2, 50.0, 1.0);
        h.reset_pending = true;
        let f = h.fuse_active(HeightSource::Gps, &obs, 5.0, &mut core, &params, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Reset);
        assert_eq!(core.x.pos_w.z, 50.0);
        assert_eq!(report.resets.height, 1);
        assert_eq!(h.last_fused_s(HeightSource::Gps), Some(1.0));
        let f = h.fuse_active(HeightSource::Gps, &obs, 5.0, &mut core, &params, &mut report);
        assert_eq!(f.outcome, FusionOutcome::Rejected, "no reset pending any more");
    }
}
