//! Point-to-point rest-to-rest move with the minimum-jerk (quintic) time law
//! `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`, τ = t/T: velocity and acceleration are zero at both ends. The
//! heading follows the same law along the shorter way round.

use super::TrajectorySample;
use crate::math::{wrap_pi, Vec3};

/// Minimum-jerk time law and its τ-derivatives `[s, s′, s″, s‴]` at `tau` ∈ [0, 1].
pub(crate) fn min_jerk(tau: f64) -> [f64; 4] {
    let t2 = tau * tau;
    [
        t2 * tau * (10.0 - 15.0 * tau + 6.0 * t2),
        30.0 * t2 * (1.0 - tau) * (1.0 - tau),
        60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2),
        60.0 - 360.0 * tau + 360.0 * t2,
    ]
}

/// Integral of the minimum-jerk law, `∫₀^τ s(u) du = 2.5τ⁴ − 3τ⁵ + τ⁶`; equals ½ at τ = 1.
pub(crate) fn min_jerk_integral(tau: f64) -> f64 {
    let t4 = tau.powi(4);
    t4 * (2.5 - 3.0 * tau + tau * tau)
}

/// Straight rest-to-rest move from `start_w` to `goal_w` in `duration_s`, turning from
/// `start_yaw_rad` to `goal_yaw_rad` along the shorter way. Before t = 0 it holds the start, from
/// t = T on the goal, at rest; a non-positive duration jumps to the goal at t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quintic {
    /// Start position, world NED [m].
    pub start_w: Vec3,
    /// Goal position, world NED [m].
    pub goal_w: Vec3,
    /// Duration T of the move [s].
    pub duration_s: f64,
    /// Heading at the start [rad].
    pub start_yaw_rad: f64,
    /// Heading at the goal [rad].
    pub goal_yaw_rad: f64,
}

impl Quintic {
    /// Sample at time `t_s` [s] from the start of the move.
    pub fn sample(&self, t_s: f64) -> TrajectorySample {
        let big_t = self.duration_s;
        let start = || TrajectorySample::at_rest(self.start_w, self.start_yaw_rad);
        let goal = || TrajectorySample::at_rest(self.goal_w, self.goal_yaw_rad);
        if big_t.is_nan() || big_t <= 0.0 {
            return if t_s < 0.0 { start() } else { goal() };
        }
        if t_s >= big_t {
            return goal();
        }
        if t_s <= 0.0 {
            return start();
        }
        let [s, ds, dds, ddds] = min_jerk(t_s / big_t);
        let (k1, k2, k3) = (1.0 / big_t, 1.0 / (big_t * big_t), 1.0 / big_t.powi(3));
        let d = self.goal_w - self.start_w;
        let dyaw = wrap_pi(self.goal_yaw_rad - self.start_yaw_rad);
        TrajectorySample {
            pos_w: self.start_w + d * s,
            vel_w: d * (ds * k1),
            acc_w: d * (dds * k2),
            jerk_w: d * (ddds * k3),
            yaw_rad: wrap_pi(self.start_yaw_rad + dyaw * s),
            yaw_rate_rad_s: dyaw * ds * k1,
            yaw_acc_rad_s2: dyaw * dds * k2,
        }
    }

    /// Peak speed of the move, `1.875·L/T` [m/s] (at τ = ½).
    pub fn peak_speed_m_s(&self) -> f64 {
        1.875 * (self.goal_w - self.start_w).norm() / self.duration_s
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{assert_derivatives, random_times};
    use super::*;

    fn q() -> Quintic {
        Quintic {
            start_w: Vec3::new(1.0, -2.0, -1.0),
            goal_w: Vec3::new(4.0, 2.0, -3.0),
            duration_s: 3.0,
            start_yaw_rad: 3.0,
            goal_yaw_rad: -3.0,
        }
    }

    #[test]
    fn time_law_integral_and_ends() {
        assert_eq!(min_jerk(0.0)[..3], [0.0, 0.0, 0.0]);
        assert_eq!(min_jerk(1.0)[..3], [1.0, 0.0, 0.0]);
        assert!((min_jerk_integral(1.0) - 0.5).abs() < 1e-15);
        assert!((min_jerk(0.5)[1] - 1.875).abs() < 1e-15);
    }

    #[test]
    fn derivatives_consistent() {
        let q = q();
        let mut times = random_times(1, -0.5, 3.5, 200);
        times.extend([1e-4, 1e-3, 3.0 - 1e-4, 3.0 - 1e-3, 3.0 + 1e-4]);
        assert_derivatives(|t| q.sample(t), &times);
    }

    #[test]
    fn rest_to_rest_endpoints_exact() {
        let q = q();
        assert_eq!(q.sample(0.0), TrajectorySample::at_rest(q.start_w, 3.0));
        assert_eq!(q.sample(-1.0), TrajectorySample::at_rest(q.start_w, 3.0));
        assert_eq!(q.sample(3.0), TrajectorySample::at_rest(q.goal_w, -3.0));
        assert_eq!(q.sample(9.0), TrajectorySample::at_rest(q.goal_w, -3.0));
        let mid = q.sample(1.5);
        assert!((mid.vel_w.norm() - q.peak_speed_m_s()).abs() < 1e-12);
        // 3 → −3 rad goes the short way through ±π: the heading increases.
        assert!(mid.yaw_rate_rad_s > 0.0);
        let expect = wrap_pi(3.0 + wrap_pi(-6.0) * 0.5);
        assert!((mid.yaw_rad - expect).abs() < 1e-12);
    }

    #[test]
    fn non_positive_duration_jumps_at_zero() {
        let q = Quintic { duration_s: 0.0, ..q() };
        assert_eq!(q.sample(-0.1).pos_w, q.start_w);
        assert_eq!(q.sample(0.0).pos_w, q.goal_w);
    }
}
