//! The vehicle state a controller sees.

use crate::math::{Mat3, Vec3};

/// Estimated vehicle state (for now the sensor sample passed through).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleState {
    /// Time of the state [s].
    pub t_s: f64,
    /// Position in world NED [m].
    pub pos_w: Vec3,
    /// Velocity in world NED [m/s].
    pub vel_w: Vec3,
    /// Rotation body FRD → world NED, `R_b`.
    pub r_wb: Mat3,
    /// Angular velocity in body FRD [rad/s].
    pub omega_b: Vec3,
}

impl VehicleState {
    /// At rest, level and heading north, at `pos_w` (world NED [m]) at time `t_s` [s].
    pub fn at_rest(t_s: f64, pos_w: Vec3) -> Self {
        Self {
            t_s,
            pos_w,
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    /// At rest at the origin at time 0 with attitude roll, pitch, yaw (ZYX) = `roll`, `pitch`,
    /// `yaw` [rad].
    #[cfg(test)]
    pub(crate) fn at_rest_turned(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self {
            r_wb: crate::math::UnitQuat::from_euler_angles(roll, pitch, yaw)
                .to_rotation_matrix()
                .into_inner(),
            ..Self::at_rest(0.0, Vec3::zeros())
        }
    }

    /// Tilt of the body z axis from the vertical [rad].
    pub fn tilt_rad(&self) -> f64 {
        self.r_wb[(2, 2)].clamp(-1.0, 1.0).acos()
    }

    /// True when every number is finite (each fixed-size part checked on its own, which the
    /// compiler unrolls: the check runs twice per control tick).
    pub fn is_finite(&self) -> bool {
        let finite = |x: &f64| x.is_finite();
        self.t_s.is_finite()
            && self.pos_w.iter().all(finite)
            && self.vel_w.iter().all(finite)
            && self.omega_b.iter().all(finite)
            && self.r_wb.iter().all(finite)
    }
}
