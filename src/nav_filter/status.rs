//! What the filter reports about itself: validity, height source, per-sensor health, test
//! ratios and innovations, as PX4's `ESTIMATOR_STATUS` does (docs/navigation_filter.md §12–§13).

use crate::math::Vec3;

use super::fusion::FusionOutcome;
use super::nav_params::HeightSource;

/// Health of one sensor (docs/navigation_filter.md §13).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceHealth {
    /// No sample ever received.
    NoData,
    /// The latest sample was fused (or the state was reset to it).
    Fused,
    /// The latest sample failed its innovation gate.
    Rejected,
    /// The latest sample was skipped before the gate (quality, invalid, stale, geometry,
    /// alignment).
    Unusable,
    /// No sample for longer than `sensor_timeout_s`.
    TimedOut,
}

/// One sensor's health and counters (docs/navigation_filter.md §13).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceStatus {
    /// Health now.
    pub health: SourceHealth,
    /// Samples received [-].
    pub received: u32,
    /// Samples fused or reset to [-].
    pub fused: u32,
    /// Samples rejected by the gate [-].
    pub rejected: u32,
    /// Samples skipped before the gate [-].
    pub skipped: u32,
    /// Time since the last fused sample [s], `None` if none was ever fused.
    pub time_since_fused_s: Option<f64>,
}

/// Counters and times of one sensor, updated with every sample.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct SourceTrack {
    pub received: u32,
    pub fused: u32,
    pub rejected: u32,
    pub skipped: u32,
    pub last_received_s: Option<f64>,
    pub last_fused_s: Option<f64>,
    pub last_outcome: Option<FusionOutcome>,
}

impl SourceTrack {
    /// Counts a sample received at `t_s` [s] with this outcome.
    pub fn record(&mut self, t_s: f64, outcome: FusionOutcome) {
        self.received = self.received.saturating_add(1);
        self.last_received_s = Some(t_s);
        self.last_outcome = Some(outcome);
        match outcome {
            FusionOutcome::Fused | FusionOutcome::Reset => {
                self.fused = self.fused.saturating_add(1);
                self.last_fused_s = Some(t_s);
            }
            FusionOutcome::Rejected => self.rejected = self.rejected.saturating_add(1),
            FusionOutcome::Skipped(_) => self.skipped = self.skipped.saturating_add(1),
        }
    }

    /// Counts a sample made of several parts at `t_s` [s]: fused if any part was fused (or
    /// reset to), rejected if any part was rejected (both can hold), skipped if every part was;
    /// the health follows a rejection first (docs/navigation_filter.md §13).
    pub fn record_parts(&mut self, t_s: f64, parts: &[FusionOutcome]) {
        let accepted = parts
            .iter()
            .any(|o| matches!(o, FusionOutcome::Fused | FusionOutcome::Reset));
        let rejected = parts.contains(&FusionOutcome::Rejected);
        self.received = self.received.saturating_add(1);
        self.last_received_s = Some(t_s);
        if accepted {
            self.fused = self.fused.saturating_add(1);
            self.last_fused_s = Some(t_s);
        }
        if rejected {
            self.rejected = self.rejected.saturating_add(1);
        }
        if !accepted && !rejected {
            self.skipped = self.skipped.saturating_add(1);
        }
        self.last_outcome = if rejected {
            Some(FusionOutcome::Rejected)
        } else if accepted {
            Some(FusionOutcome::Fused)
        } else {
            parts.first().copied()
        };
    }

    /// The report at `now_s` [s] with time-out `timeout_s` [s].
    pub fn status(&self, now_s: f64, timeout_s: f64) -> SourceStatus {
        let health = match (self.last_received_s, self.last_outcome) {
            (None, _) | (_, None) => SourceHealth::NoData,
            (Some(t), _) if now_s - t > timeout_s => SourceHealth::TimedOut,
            (_, Some(FusionOutcome::Fused | FusionOutcome::Reset)) => SourceHealth::Fused,
            (_, Some(FusionOutcome::Rejected)) => SourceHealth::Rejected,
            (_, Some(FusionOutcome::Skipped(_))) => SourceHealth::Unusable,
        };
        SourceStatus {
            health,
            received: self.received,
            fused: self.fused,
            rejected: self.rejected,
            skipped: self.skipped,
            time_since_fused_s: self.last_fused_s.map(|t| (now_s - t).max(0.0)),
        }
    }
}

/// Latest test ratio ν² / (gate² S) per measurement kind [-]
/// (docs/navigation_filter.md §5, eq. (5.3)); 0 until the first one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TestRatios {
    /// GNSS velocity (largest of the three axes).
    pub gps_velocity: f64,
    /// GNSS horizontal position (larger of north and east).
    pub gps_horizontal: f64,
    /// GNSS height (computed also while the barometer is the active source).
    pub gps_height: f64,
    /// Barometric height.
    pub baro_height: f64,
    /// Magnetic heading.
    pub heading: f64,
}

/// Latest innovations ν = z − h(x̂) and their variances S per measurement kind
/// (docs/navigation_filter.md §5, eqs. (5.1)–(5.2)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Innovations {
    /// GNSS velocity innovation, NED [m/s].
    pub gps_vel_w: Vec3,
    /// GNSS velocity innovation variances [m²/s²].
    pub gps_vel_var: Vec3,
    /// GNSS position innovation, NED [m].
    pub gps_pos_w: Vec3,
    /// GNSS position innovation variances [m²].
    pub gps_pos_var: Vec3,
    /// Barometric height innovation (up) [m].
    pub baro_height_m: f64,
    /// Barometric height innovation variance [m²].
    pub baro_height_var: f64,
    /// Heading innovation [rad].
    pub heading_rad: f64,
    /// Heading innovation variance [rad²].
    pub heading_var: f64,
}

impl Default for Innovations {
    fn default() -> Self {
        Self {
            gps_vel_w: Vec3::zeros(),
            gps_vel_var: Vec3::zeros(),
            gps_pos_w: Vec3::zeros(),
            gps_pos_var: Vec3::zeros(),
            baro_height_m: 0.0,
            baro_height_var: 0.0,
            heading_rad: 0.0,
            heading_var: 0.0,
        }
    }
}

/// How often the state was reset or the height source changed [-]
/// (docs/navigation_filter.md §6, §9, §11).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ResetCounters {
    /// Horizontal position reset to GNSS.
    pub horizontal_position: u32,
    /// Velocity reset to GNSS.
    pub velocity: u32,
    /// Height reset to the active height source.
    pub height: u32,
    /// Yaw reset to the magnetometer.
    pub yaw: u32,
    /// Barometer offset re-learned after a long rejection.
    pub baro_offset: u32,
    /// Changes of the active height source.
    pub height_source_changes: u32,
}

/// The filter's report on itself (docs/navigation_filter.md §12–§13).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavStatus {
    /// Time of the latest IMU sample [s].
    pub t_s: f64,
    /// Roll and pitch aligned and propagated.
    pub attitude_valid: bool,
    /// Yaw set from the magnetometer (at alignment or later).
    pub yaw_aligned: bool,
    /// Horizontal position usable: aided within `noaid_timeout_s`.
    pub horizontal_position_valid: bool,
    /// Height usable: the active height source fused within `height_timeout_s`.
    pub vertical_position_valid: bool,
    /// Velocity usable: aided within `noaid_timeout_s`.
    pub velocity_valid: bool,
    /// Horizontally aided before, but nothing for more than `DEAD_RECKONING_AFTER_S`.
    pub dead_reckoning: bool,
    /// The position-hold pseudo-measurement is being fused
    /// (docs/navigation_filter.md §12, eq. (12.2)).
    pub position_hold: bool,
    /// Time since the last fused horizontal aiding (GNSS position or velocity) [s], `None` if
    /// never aided.
    pub time_since_aiding_s: Option<f64>,
    /// Height reference chosen (`EKF2_HGT_REF`).
    pub height_ref: HeightSource,
    /// Height source fused now.
    pub active_height: HeightSource,
    /// GNSS health.
    pub gps: SourceStatus,
    /// Barometer health.
    pub baro: SourceStatus,
    /// Magnetometer health.
    pub mag: SourceStatus,
    /// Latest test ratios.
    pub test_ratios: TestRatios,
    /// Latest innovations.
    pub innovations: Innovations,
    /// The first pre-flight check that fails, `None` when the estimate is consistent enough to
    /// arm on (docs/navigation_filter.md §19).
    pub preflight: Option<super::PreflightFailure>,
    /// Resets and height-source changes.
    pub resets: ResetCounters,
    /// The filter's origin in the GNSS readings' NED frame [m], set at the first good fix.
    pub origin_w: Option<Vec3>,
    /// Barometric (ISA) altitude of the origin [m], captured at alignment.
    pub baro_origin_m: Option<f64>,
    /// IMU samples not integrated (non-finite, out of order, or after a gap) [-].
    pub imu_dropped: u32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav_filter::fusion::SkipReason;

    #[test]
    fn health_follows_the_latest_sample_and_times_out() {
        let mut s = SourceTrack::default();
        assert_eq!(s.status(0.0, 1.0).health, SourceHealth::NoData);
        s.record(1.0, FusionOutcome::Fused);
        assert_eq!(s.status(1.5, 1.0).health, SourceHealth::Fused);
        s.record(1.6, FusionOutcome::Rejected);
        let r = s.status(1.7, 1.0);
        assert_eq!(r.health, SourceHealth::Rejected);
        assert_eq!((r.received, r.fused, r.rejected), (2, 1, 1));
        assert!((r.time_since_fused_s.unwrap() - 0.7).abs() < 1e-12);
        s.record(1.8, FusionOutcome::Skipped(SkipReason::Quality));
        assert_eq!(s.status(1.9, 1.0).health, SourceHealth::Unusable);
        assert_eq!(s.status(2.9, 1.0).health, SourceHealth::TimedOut);
        s.record_parts(
            3.0,
            &[
                FusionOutcome::Fused,
                FusionOutcome::Rejected,
                FusionOutcome::Skipped(SkipReason::Inactive),
            ],
        );
        let r = s.status(3.0, 1.0);
        assert_eq!(r.health, SourceHealth::Rejected);
        assert_eq!((r.received, r.fused, r.rejected, r.skipped), (4, 2, 2, 1));
        assert_eq!(r.time_since_fused_s, Some(0.0));
    }
}
