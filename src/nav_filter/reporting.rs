//! What the fusion steps leave for the filter's report on itself: the latest test ratios and
//! innovations, the low-passed innovations of the pre-flight checks and the reset counters
//! (docs/navigation_filter.md §13, §19).

use super::preflight::{PreflightChecks, PreflightFailure};
use super::status::{Innovations, ResetCounters, TestRatios};

/// The per-measurement figures the status reports, written by each fusion step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FilterReport {
    /// Latest test ratios (docs/navigation_filter.md §5, eq. (5.3)).
    pub ratios: TestRatios,
    /// Latest innovations and their variances (docs/navigation_filter.md §5, eqs. (5.1)–(5.2)).
    pub innovations: Innovations,
    /// The low-passed innovations the pre-flight checks read (docs/navigation_filter.md §19).
    pub preflight: PreflightChecks,
    /// Resets and height-source changes.
    pub resets: ResetCounters,
}

impl FilterReport {
    /// The first pre-flight check that fails at `now_s` [s]: the heading while the filter is not
    /// `aligned`, otherwise the checks on the low-passed innovations given whether the yaw is
    /// aligned (docs/navigation_filter.md §19, eq. (19.2)).
    pub fn preflight_failure(&self, now_s: f64, aligned: bool, yaw_aligned: bool) -> Option<PreflightFailure> {
        if aligned {
            self.preflight.failure(now_s, yaw_aligned)
        } else {
            Some(PreflightFailure::Heading)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unaligned_filter_fails_on_its_heading_and_an_aligned_one_on_its_innovations() {
        let mut r = FilterReport::default();
        assert_eq!(r.preflight_failure(0.0, false, true), Some(PreflightFailure::Heading));
        assert_eq!(r.preflight_failure(0.0, true, false), Some(PreflightFailure::Heading));
        assert_eq!(r.preflight_failure(0.0, true, true), None);
        for k in 0..30 {
            r.preflight.baro_height(0.1 * f64::from(k), 4.0, 1.0, 5.0);
        }
        assert_eq!(r.preflight_failure(3.0, true, true), Some(PreflightFailure::Height));
        assert_eq!(r.preflight_failure(3.0, false, true), Some(PreflightFailure::Heading));
    }
}
