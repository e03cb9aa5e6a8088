//! Rest-to-rest straight move with a quintic (minimum-jerk) time law, used for take-off:
//! `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`, τ = t/T, so velocity and acceleration start and end at zero.
//! A thin wrapper over [`Quintic`].

use super::trajectory::Quintic;
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
    /// The same move as a [`Quintic`] trajectory (heading held).
    pub fn quintic(&self) -> Quintic {
        Quintic {
            start_w: self.start_w,
            goal_w: self.target_w,
            duration_s: self.duration_s,
            start_yaw_rad: self.yaw_rad,
            goal_yaw_rad: self.yaw_rad,
        }
    }

    /// Setpoint at time `t_s` [s] from the start of the move.
    pub fn setpoint(&self, t_s: f64) -> FlatSetpoint {
        self.quintic().sample(t_s).setpoint()
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
