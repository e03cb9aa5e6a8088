//! The pre-flight checks on the filter's innovations: is the estimate consistent enough to arm on
//! (docs/navigation_filter.md §19, eqs. (19.1)–(19.2))? Each measurement kind keeps its test
//! ratio low-passed with its sign, and a kind whose low-passed ratio's root exceeds 0.5 (an
//! innovation held beyond half its gate, 2.5 σ with PX4's 5 σ gates) fails, as PX4's estimator
//! sets its `pre_flt_fail_innov_*` flags. The height is judged on the mean over the height
//! sources fused in the last second.

use crate::math::Vec3;

/// Time constant of the low-passed test ratios [s] (PX4's 0.5 s).
const RATIO_TAU_S: f64 = 0.5;
/// Largest root of a low-passed test ratio that passes [-] (PX4's `kMinTestRatioPreflight`).
const MAX_ROOT_RATIO: f64 = 0.5;
/// A height source counts as in use when it was checked this recently [s].
const HEIGHT_SOURCE_RECENT_S: f64 = 1.0;

/// Why the estimate is not consistent enough to arm on, in PX4's order and words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PreflightFailure {
    /// The heading is not aligned, or its innovations stay large.
    Heading,
    /// GNSS horizontal velocity innovations stay large.
    HorizontalVelocity,
    /// GNSS vertical velocity innovations stay large.
    VerticalVelocity,
    /// GNSS horizontal position innovations stay large.
    HorizontalPosition,
    /// Height innovations stay large.
    Height,
}

impl PreflightFailure {
    /// What PX4 says ("Preflight Fail: …").
    pub fn text(self) -> &'static str {
        match self {
            Self::Heading => "heading estimate not stable",
            Self::HorizontalVelocity => "horizontal velocity unstable",
            Self::VerticalVelocity => "vertical velocity unstable",
            Self::HorizontalPosition => "horizontal position unstable",
            Self::Height => "height estimate not stable",
        }
    }
}

/// A test ratio low-passed with its innovation's sign
/// (docs/navigation_filter.md §19, eq. (19.1)).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct SignedRatio {
    value: f64,
    last_s: Option<f64>,
}

impl SignedRatio {
    /// Takes the innovation `nu` with variance `var` behind gate `gate_sd` [SD] at `t_s` [s]:
    /// r̄ ← r̄ + α (sign(ν) ν²/(γ² S) − r̄), α = Δt / (Δt + τ).
    fn update(&mut self, t_s: f64, nu: f64, var: f64, gate_sd: f64) {
        if !(var > 0.0 && nu.is_finite()) {
            return;
        }
        let ratio = nu.signum() * nu * nu / (gate_sd * gate_sd * var);
        let dt = self.last_s.map_or(0.0, |t| (t_s - t).max(0.0));
        let alpha = dt / (dt + RATIO_TAU_S);
        self.value += alpha * (ratio - self.value);
        self.last_s = Some(t_s);
    }

    /// √|r̄| [-].
    fn root(&self) -> f64 {
        self.value.abs().sqrt()
    }

    fn recent(&self, now_s: f64) -> bool {
        self.last_s.is_some_and(|t| now_s - t <= HEIGHT_SOURCE_RECENT_S)
    }
}

/// The low-passed ratios of every measurement kind the checks read.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct PreflightChecks {
    heading: SignedRatio,
    vel_north: SignedRatio,
    vel_east: SignedRatio,
    vel_down: SignedRatio,
    pos_north: SignedRatio,
    pos_east: SignedRatio,
    gps_height: SignedRatio,
    baro_height: SignedRatio,
}

impl PreflightChecks {
    /// A heading innovation [rad] with variance [rad²].
    pub fn heading(&mut self, t_s: f64, nu: f64, var: f64, gate_sd: f64) {
        self.heading.update(t_s, nu, var, gate_sd);
    }

    /// A GNSS velocity innovation, NED [m/s], with its variances [m²/s²].
    pub fn velocity(&mut self, t_s: f64, nu: &Vec3, var: &Vec3, gate_sd: f64) {
        self.vel_north.update(t_s, nu.x, var.x, gate_sd);
        self.vel_east.update(t_s, nu.y, var.y, gate_sd);
        self.vel_down.update(t_s, nu.z, var.z, gate_sd);
    }

    /// A GNSS horizontal position innovation [m] with its variances [m²] (north, east).
    pub fn position(&mut self, t_s: f64, nu: (f64, f64), var: (f64, f64), gate_sd: f64) {
        self.pos_north.update(t_s, nu.0, var.0, gate_sd);
        self.pos_east.update(t_s, nu.1, var.1, gate_sd);
    }

    /// A GNSS height innovation [m] with its variance [m²].
    pub fn gps_height(&mut self, t_s: f64, nu: f64, var: f64, gate_sd: f64) {
        self.gps_height.update(t_s, nu, var, gate_sd);
    }

    /// A barometric height innovation [m] with its variance [m²].
    pub fn baro_height(&mut self, t_s: f64, nu: f64, var: f64, gate_sd: f64) {
        self.baro_height.update(t_s, nu, var, gate_sd);
    }

    /// The first check that fails at `now_s` [s], in PX4's order, given whether the yaw is
    /// aligned (docs/navigation_filter.md §19, eq. (19.2)).
    pub fn failure(&self, now_s: f64, yaw_aligned: bool) -> Option<PreflightFailure> {
        let fails = |r: f64| r > MAX_ROOT_RATIO;
        let (sum, count) = [self.gps_height, self.baro_height]
            .iter()
            .filter(|r| r.recent(now_s))
            .fold((0.0, 0.0), |(sum, count), r| (sum + r.root(), count + 1.0));
        let height = if count > 0.0 { sum / count } else { 0.0 };
        if !yaw_aligned || fails(self.heading.root()) {
            Some(PreflightFailure::Heading)
        } else if fails(self.vel_north.root().max(self.vel_east.root())) {
            Some(PreflightFailure::HorizontalVelocity)
        } else if fails(self.vel_down.root()) {
            Some(PreflightFailure::VerticalVelocity)
        } else if fails(self.pos_north.root().max(self.pos_east.root())) {
            Some(PreflightFailure::HorizontalPosition)
        } else if fails(height) {
            Some(PreflightFailure::Height)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_innovation_beyond_half_the_gate_fails_and_noise_does_not() {
        let mut c = PreflightChecks::default();
        // 10 Hz of ±1 σ noise: passes.
        for k in 0..50 {
            let nu = if k % 2 == 0 { 1.0 } else { -1.0 };
            c.gps_height(0.1 * f64::from(k), nu, 1.0, 5.0);
        }
        assert_eq!(c.failure(5.0, true), None);
        // Held at 3 σ with a 5 σ gate (√(9/25) = 0.6 > 0.5): fails within a second or so.
        let mut failed_at = None;
        for k in 50..100 {
            let t = 0.1 * f64::from(k);
            c.gps_height(t, 3.0, 1.0, 5.0);
            if failed_at.is_none() && c.failure(t, true) == Some(PreflightFailure::Height) {
                failed_at = Some(t);
            }
        }
        let after = failed_at.expect("failed") - 5.0;
        assert!(after > 0.2 && after < 1.5, "{after}");
        // The source falls silent: it no longer counts.
        assert_eq!(c.failure(11.0, true), None);
    }

    #[test]
    fn checks_come_in_px4s_order() {
        let mut c = PreflightChecks::default();
        assert_eq!(c.failure(0.0, false), Some(PreflightFailure::Heading));
        for k in 0..30 {
            let t = 0.1 * f64::from(k);
            c.velocity(t, &Vec3::new(0.0, 0.0, 4.0), &Vec3::new(1.0, 1.0, 1.0), 5.0);
            c.position(t, (4.0, 0.0), (1.0, 1.0), 5.0);
        }
        assert_eq!(c.failure(3.0, true), Some(PreflightFailure::VerticalVelocity));
        assert_eq!(PreflightFailure::VerticalVelocity.text(), "vertical velocity unstable");
        for k in 30..80 {
            c.velocity(0.1 * f64::from(k), &Vec3::zeros(), &Vec3::new(1.0, 1.0, 1.0), 5.0);
        }
        assert_eq!(c.failure(8.0, true), Some(PreflightFailure::HorizontalPosition));
    }
}
