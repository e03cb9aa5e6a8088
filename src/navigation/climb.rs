//! Rest-to-rest straight move with a quintic (minimum-jerk) time law, used for take-off:
//! `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`, τ = t/T, so velocity and acceleration start and end at zero.

use crate::control::FlatSetpoint;
use crate::math::Vec3;

/// Straight rest-to-rest move from `start_w` to `target_w` [m] in `duration_s` [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClimbProfile {
    /// Start position, world NED [m].
    pub start_w: Vec3,
    /// End position, world NED [m].
    pub target_w: Vec3,
    /// Duration of the move [s]; non-positive jumps to the target.
    pub duration_s: f64,
    /// Heading held throughout [rad].
    pub yaw_rad: f64,
}

impl ClimbProfile {
    /// Setpoint at time `t_s` [s] from the start of the move.
    pub fn setpoint(&self, t_s: f64) -> FlatSetpoint {
        if self.duration_s <= 0.0 || t_s >= self.duration_s {
            return FlatSetpoint::hold(self.target_w, self.yaw_rad);
        }
        let big_t = self.duration_s;
        let tau = (t_s / big_t).max(0.0);
        let s = tau.powi(3) * (10.0 - 15.0 * tau + 6.0 * tau * tau);
        let ds = 30.0 * tau * tau * (1.0 - tau).powi(2) / big_t;
        let dds = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (big_t * big_t);
        let d = self.target_w - self.start_w;
        FlatSetpoint {
            pos_w: Some(self.start_w + d * s),
            vel_w: Some(d * ds),
            acc_w: Some(d * dds),
            ..FlatSetpoint::hold(self.target_w, self.yaw_rad)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_to_rest_and_derivatives_consistent() {
        let p = ClimbProfile {
            start_w: Vec3::zeros(),
            target_w: Vec3::new(0.0, 0.0, -2.0),
            duration_s: 4.0,
            yaw_rad: 0.0,
        };
        assert_eq!(p.setpoint(0.0).vel_w, Some(Vec3::zeros()));
        assert_eq!(p.setpoint(4.0).pos_w, Some(p.target_w));
        let h = 1e-6;
        let t = 1.3;
        let fd = (p.setpoint(t + h).pos_w.unwrap() - p.setpoint(t - h).pos_w.unwrap()) / (2.0 * h);
        assert!((fd - p.setpoint(t).vel_w.unwrap()).norm() < 1e-6);
        let fd = (p.setpoint(t + h).vel_w.unwrap() - p.setpoint(t - h).vel_w.unwrap()) / (2.0 * h);
        assert!((fd - p.setpoint(t).acc_w.unwrap()).norm() < 1e-6);
    }
}
