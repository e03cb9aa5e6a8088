//! What one measurement did to the filter (docs/navigation_filter.md §5, §13).

/// Why a measurement was not offered to the gate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipReason {
    /// The filter is not aligned yet (the sample may still feed the alignment).
    NotAligned,
    /// A number of the reading is not finite, or the pressure is not positive.
    Invalid,
    /// The receiver's own quality figures fail the checks (docs/navigation_filter.md §6).
    Quality,
    /// Older than the state history (docs/navigation_filter.md §7).
    Stale,
    /// The source is not used for this quantity now (e.g. GNSS height while the barometer is
    /// the active height source); the test ratio is still computed and reported.
    Inactive,
    /// The geometry makes the measurement useless (horizontal magnetic field too weak).
    Geometry,
    /// The source failed its gate for `height_timeout_s` while it kept delivering, and is not
    /// fused again (docs/navigation_filter.md §9).
    Fault,
}

/// Result of one measurement, or of one part of a GNSS fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FusionOutcome {
    /// Passed the gate and fused.
    Fused,
    /// The state was reset to the measurement (start of aiding, height-source change, or a
    /// source rejected for longer than its time-out) (docs/navigation_filter.md §6, eq. (6.4)).
    Reset,
    /// Failed the innovation gate: not fused, counted.
    Rejected,
    /// Not offered to the gate.
    Skipped(SkipReason),
}

/// One measurement's outcome and test ratio ν² / (gate² · S)
/// (docs/navigation_filter.md §5, eq. (5.3)); the ratio is 0 when the measurement was skipped
/// before the gate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fusion {
    /// What happened.
    pub outcome: FusionOutcome,
    /// Largest test ratio of the measurement's components [-]; > 1 means rejected.
    pub test_ratio: f64,
}

impl Fusion {
    /// Skipped before the gate.
    pub fn skipped(reason: SkipReason) -> Self {
        Self {
            outcome: FusionOutcome::Skipped(reason),
            test_ratio: 0.0,
        }
    }

    /// Whether the measurement changed the state (fused or reset).
    pub fn accepted(&self) -> bool {
        matches!(self.outcome, FusionOutcome::Fused | FusionOutcome::Reset)
    }
}

/// The three parts of a GNSS fix, each gated on its own (docs/navigation_filter.md §6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsFusion {
    /// NED velocity (gate `gps_vel_gate_sd`).
    pub velocity: Fusion,
    /// North and east position (gate `gps_pos_gate_sd`).
    pub horizontal: Fusion,
    /// Down position (gate `gps_pos_gate_sd`), fused only while GNSS is the active height source.
    pub vertical: Fusion,
}

impl GpsFusion {
    /// The same outcome for all three parts.
    pub fn all(f: Fusion) -> Self {
        Self {
            velocity: f,
            horizontal: f,
            vertical: f,
        }
    }

    /// Whether any part changed the state.
    pub fn accepted(&self) -> bool {
        self.velocity.accepted() || self.horizontal.accepted() || self.vertical.accepted()
    }

    /// Whether any part failed its gate.
    pub fn rejected(&self) -> bool {
        [self.velocity, self.horizontal, self.vertical]
            .iter()
            .any(|f| f.outcome == FusionOutcome::Rejected)
    }
}
