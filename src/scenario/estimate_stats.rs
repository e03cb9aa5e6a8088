//! How well the wrench estimate followed the truth over a run: RMS errors once the estimator
//! has settled, beside the spread of the true force (a turbulent wind's, say). Pure.

use serde::Serialize;

use crate::math::Vec3;
use crate::wrench_estimator::WrenchEstimate;

/// Passband time constants the estimator is given to settle before its errors count [-]:
/// settle time = this / ω_p (docs/estimator.md §3).
pub const SETTLE_TIME_CONSTANTS: f64 = 5.0;

/// Share of the true force's norm the force estimate must stay within to count as converged
/// [-] (docs/sweep.md §3, eq. (3.3)).
pub const CONVERGED_SHARE: f64 = 0.05;

/// Smallest band of convergence, for a true force near zero [N] (docs/sweep.md §3, eq. (3.3)).
pub const CONVERGED_FLOOR_N: f64 = 0.05;

/// Running sums of the estimate's errors after the settle time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EstimateStats {
    from_s: f64,
    n: u64,
    sum_sq_force: Vec3,
    sum_sq_torque: Vec3,
    sum_true: Vec3,
    sum_sq_true: Vec3,
    converged_since_s: Option<f64>,
    overshoot_share: f64,
}

/// `estimate.tracking` of `summary.json`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EstimateTracking {
    /// Errors count from this simulated time on [s].
    pub from_s: f64,
    /// RMS of f̂_e − f_e per axis, world NED [N]; f_e is the scripted force plus the drag (wind
    /// included) plus the unmodelled weight (m_r − m_e) g on z (docs/estimator.md §5).
    pub rms_force_error_n: [f64; 3],
    /// RMS of τ̂_e − τ_e per axis, body FRD [N·m].
    pub rms_torque_error_n_m: [f64; 3],
    /// Standard deviation of the true f_e per axis over the same ticks [N]: what there was to
    /// follow.
    pub true_force_sd_n: [f64; 3],
}

impl EstimateStats {
    /// Statistics that start counting at `from_s` [s].
    pub fn starting_at(from_s: f64) -> Self {
        Self {
            from_s,
            ..Self::default()
        }
    }

    /// Adds the tick at `t_s` [s] with `estimate` against the true force `force_w` (world NED
    /// [N], the unmodelled weight included) and torque `torque_b` (body FRD [N·m]).
    pub fn add(&mut self, t_s: f64, estimate: Option<&WrenchEstimate>, force_w: Vec3, torque_b: Vec3) {
        let Some(e) = estimate else { return };
        let truth = force_w.norm();
        let band_n = (CONVERGED_SHARE * truth).max(CONVERGED_FLOOR_N);
        self.converged_since_s = match self.converged_since_s {
            _ if (e.force_w - force_w).norm() > band_n => None,
            None => Some(t_s),
            since => since,
        };
        if truth > CONVERGED_FLOOR_N {
            self.overshoot_share = self.overshoot_share.max((e.force_w.norm() - truth) / truth);
        }
        if t_s < self.from_s {
            return;
        }
        self.n += 1;
        self.sum_sq_force += (e.force_w - force_w).map(|x| x * x);
        self.sum_sq_torque += (e.torque_b - torque_b).map(|x| x * x);
        self.sum_true += force_w;
        self.sum_sq_true += force_w.map(|x| x * x);
    }

    /// Time from which the force estimate stayed within its band to the end; `None` when it
    /// ended outside (docs/sweep.md §3, eq. (3.3)) [s].
    pub fn convergence_time_s(&self) -> Option<f64> {
        self.converged_since_s
    }

    /// Largest excess of ‖f̂_e‖ over ‖f_e‖, in percent of ‖f_e‖ (docs/sweep.md §3, eq. (3.4)),
    /// over the ticks where ‖f_e‖ exceeded the band's floor [%].
    pub fn force_overshoot_pct(&self) -> f64 {
        100.0 * self.overshoot_share
    }

    /// The figures, `None` when no tick counted.
    pub fn summary(&self) -> Option<EstimateTracking> {
        if self.n == 0 {
            return None;
        }
        let n = self.n as f64;
        let rms = |s: Vec3| -> [f64; 3] { (s / n).map(f64::sqrt).into() };
        let mean = self.sum_true / n;
        let var = (self.sum_sq_true / n - mean.map(|m| m * m)).map(|v| v.max(0.0));
        Some(EstimateTracking {
            from_s: self.from_s,
            rms_force_error_n: rms(self.sum_sq_force),
            rms_torque_error_n_m: rms(self.sum_sq_torque),
            true_force_sd_n: var.map(f64::sqrt).into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn estimate(fx: f64) -> WrenchEstimate {
        WrenchEstimate {
            force_w: Vec3::new(fx, 0.0, 0.0),
            torque_b: Vec3::zeros(),
            mass_kg: 1.0,
        }
    }

    #[test]
    fn errors_count_after_the_settle_time_only() {
        let mut s = EstimateStats::starting_at(1.0);
        s.add(0.5, Some(&estimate(100.0)), Vec3::zeros(), Vec3::zeros());
        s.add(1.0, Some(&estimate(1.0)), Vec3::new(0.0, 0.0, 0.0), Vec3::zeros());
        s.add(1.5, Some(&estimate(1.0)), Vec3::new(2.0, 0.0, 0.0), Vec3::zeros());
        s.add(2.0, None, Vec3::new(50.0, 0.0, 0.0), Vec3::zeros());
        let t = s.summary().unwrap();
        assert_eq!(t.rms_force_error_n, [1.0, 0.0, 0.0]);
        assert_eq!(t.true_force_sd_n, [1.0, 0.0, 0.0]);
        assert!(EstimateStats::starting_at(9.0).summary().is_none());
    }

    #[test]
    fn convergence_and_overshoot_of_a_step() {
        let mut s = EstimateStats::starting_at(0.0);
        let truth = Vec3::new(2.0, 0.0, 0.0);
        for (k, fx) in [0.0, 1.5, 2.4, 1.95, 2.08, 2.02].into_iter().enumerate() {
            s.add(k as f64, Some(&estimate(fx)), truth, Vec3::zeros());
        }
        assert_eq!(s.convergence_time_s(), Some(3.0), "within 0.1 N from t = 3 s");
        assert!((s.force_overshoot_pct() - 20.0).abs() < 1e-9);
        s.add(6.0, Some(&estimate(1.0)), truth, Vec3::zeros());
        assert_eq!(s.convergence_time_s(), None, "it left the band");
    }
}
