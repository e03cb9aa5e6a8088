//! Flat-output setpoint: position, velocity, acceleration and heading.

use crate::math::Vec3;

/// Reference for the position loops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatSetpoint {
    /// Desired position in world NED [m].
    pub pos_w: Vec3,
    /// Desired velocity in world NED [m/s].
    pub vel_w: Vec3,
    /// Feed-forward acceleration in world NED [m/s²].
    pub acc_w: Vec3,
    /// Desired heading ψ_d [rad].
    pub yaw_rad: f64,
}

impl FlatSetpoint {
    /// Hold `pos_w` [m] at heading `yaw_rad` [rad].
    pub fn hold(pos_w: Vec3, yaw_rad: f64) -> Self {
        Self {
            pos_w,
            vel_w: Vec3::zeros(),
            acc_w: Vec3::zeros(),
            yaw_rad,
        }
    }
}
