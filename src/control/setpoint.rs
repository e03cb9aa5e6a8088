//! Flat-output setpoint: position, velocity, acceleration, heading and heading rate, each
//! optional (`None` means "not commanded", never NaN).
//!
//! Semantics shared by every controller (PX4's position-control conventions):
//! - position `None`: no position feedback (e_p = 0);
//! - velocity `None`: zero velocity feed-forward if a position is set, no velocity feedback if
//!   neither position nor velocity is set (pure acceleration command);
//! - acceleration `None`: zero feed-forward;
//! - yaw `None`: the controller holds the heading it had when yaw was last commanded (or the
//!   vehicle's heading at the first tick); yaw rate / acceleration `None`: zero feed-forward.

use crate::math::Vec3;

/// Reference for the position and heading loops.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FlatSetpoint {
    /// Desired position in world NED [m].
    pub pos_w: Option<Vec3>,
    /// Desired velocity in world NED [m/s].
    pub vel_w: Option<Vec3>,
    /// Feed-forward acceleration in world NED [m/s²].
    pub acc_w: Option<Vec3>,
    /// Desired heading ψ_d [rad].
    pub yaw_rad: Option<f64>,
    /// Heading-rate feed-forward ψ̇_d [rad/s].
    pub yaw_rate_rad_s: Option<f64>,
    /// Heading-acceleration feed-forward ψ̈_d [rad/s²].
    pub yaw_acc_rad_s2: Option<f64>,
}

impl FlatSetpoint {
    /// Hold `pos_w` [m] at heading `yaw_rad` [rad], at rest.
    pub fn hold(pos_w: Vec3, yaw_rad: f64) -> Self {
        Self {
            pos_w: Some(pos_w),
            vel_w: Some(Vec3::zeros()),
            acc_w: Some(Vec3::zeros()),
            yaw_rad: Some(yaw_rad),
            yaw_rate_rad_s: Some(0.0),
            yaw_acc_rad_s2: Some(0.0),
        }
    }

    /// True when every value that is set is finite.
    pub fn is_finite(&self) -> bool {
        let v = |x: &Option<Vec3>| x.iter().all(|v| v.iter().all(|c| c.is_finite()));
        let s = |x: &Option<f64>| x.iter().all(|v| v.is_finite());
        v(&self.pos_w)
            && v(&self.vel_w)
            && v(&self.acc_w)
            && s(&self.yaw_rad)
            && s(&self.yaw_rate_rad_s)
            && s(&self.yaw_acc_rad_s2)
    }
}
