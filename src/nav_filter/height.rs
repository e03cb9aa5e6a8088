//! Which height source is fused: the reference (`EKF2_HGT_REF`) while it works, the other one
//! after a time-out, back to the reference once it has passed its gate for a while; height
//! resets when a source takes over; a barometer that failed its gate while it kept delivering is
//! at fault and never fused again (docs/navigation_filter.md §9).

use crate::math::Vec3;

use super::covariance::{fuse_group, uncorrelate, ScalarObservation};
use super::fusion::{Fusion, FusionOutcome};
use super::params::HeightSource;
use super::state::{ERR_BARO_OFFSET, ERR_POS};
use super::NavFilter;

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
}

impl NavFilter {
    /// Whether the active height source was fused within `height_timeout_s`
    /// (docs/navigation_filter.md §12, eq. (12.1)).
    pub(super) fn height_fused_recently(&self) -> bool {
        self.height
            .last_fused_s(self.height.active)
            .is_some_and(|t| self.t_s - t <= self.params.height_timeout_s)
    }

    /// Whether `s` could take over the height now (docs/navigation_filter.md §9).
    fn height_source_available(&self, s: HeightSource) -> bool {
        let recent = |t: Option<f64>| t.is_some_and(|t| self.t_s - t <= self.params.sensor_timeout_s);
        match s {
            HeightSource::Baro => self.baro_origin_m.is_some() && recent(self.baro.last_received_s),
            HeightSource::Gps => self.origin_w.is_some() && recent(self.gps.last_fused_s),
        }
    }

    /// The time-driven rules: fall back after `height_timeout_s` without a fused height sample,
    /// return to the reference after it has passed its gate for `height_timeout_s`
    /// (docs/navigation_filter.md §9).
    pub(super) fn update_height_source(&mut self) {
        let h = self.height;
        let timeout = self.params.height_timeout_s;
        let last = h
            .last_fused_s(h.active)
            .map_or(h.active_since_s, |t| t.max(h.active_since_s));
        if self.t_s - last > timeout {
            let other = h.active.other();
            if self.height_source_available(other) {
                // A barometer that kept delivering while it failed its gate is at fault.
                if h.active == HeightSource::Baro && self.height_source_available(HeightSource::Baro) {
                    self.height.baro_fault = true;
                }
                self.switch_height_source(other);
            } else {
                self.height.reset_pending = true;
            }
        } else if h.active != h.reference
            && h.reference_passing_since_s.is_some_and(|s| self.t_s - s >= timeout)
            && self.height_source_available(h.reference)
            && !(h.reference == HeightSource::Baro && h.baro_fault)
        {
            self.switch_height_source(h.reference);
        }
    }

    /// Makes `to` the active height source; the barometer offset is frozen while the barometer is
    /// active (docs/navigation_filter.md §8, eq. (8.3); docs/navigation_filter.md §9).
    pub(super) fn switch_height_source(&mut self, to: HeightSource) {
        if to == HeightSource::Baro {
            uncorrelate(&mut self.p, ERR_BARO_OFFSET, 0.0);
        } else if self.p[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)] <= 0.0 {
            uncorrelate(&mut self.p, ERR_BARO_OFFSET, self.params.baro_noise_m.powi(2));
        }
        self.height.active = to;
        self.height.active_since_s = self.t_s;
        self.height.reset_pending = true;
        self.height.reference_passing_since_s = None;
        self.resets.height_source_changes = self.resets.height_source_changes.saturating_add(1);
    }

    /// Fuses one height observation of the active source `source` behind gate `gate_sd` [SD]; when
    /// it fails its gate and a reset is pending, the height is reset to it instead
    /// (docs/navigation_filter.md §5, eqs. (5.2)–(5.7); docs/navigation_filter.md §9).
    pub(super) fn fuse_active_height(&mut self, source: HeightSource, obs: &ScalarObservation, gate_sd: f64) -> Fusion {
        let update = fuse_group(&mut self.p, std::slice::from_ref(obs), Some(gate_sd));
        let outcome = if let Some(dx) = update.dx {
            self.apply(&dx);
            FusionOutcome::Fused
        } else if self.height.reset_pending {
            self.reset_height(obs);
            FusionOutcome::Reset
        } else {
            FusionOutcome::Rejected
        };
        if outcome != FusionOutcome::Rejected {
            self.height.mark_fused(source, self.t_s);
            self.height.reset_pending = false;
        }
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }

    /// Moves the height so that `obs` has no innovation, and restarts its variance at the
    /// measurement's (docs/navigation_filter.md §6, eq. (6.4)).
    fn reset_height(&mut self, obs: &ScalarObservation) {
        let c = obs.h[ERR_POS + 2];
        if c == 0.0 {
            return;
        }
        let dz = obs.innovation / c;
        self.x.pos_w.z += dz;
        self.buffer.correct(
            self.history_start_s(),
            &Vec3::new(0.0, 0.0, dz),
            &Vec3::zeros(),
            &Vec3::zeros(),
        );
        uncorrelate(&mut self.p, ERR_POS + 2, obs.variance);
        self.resets.height = self.resets.height.saturating_add(1);
    }
}
