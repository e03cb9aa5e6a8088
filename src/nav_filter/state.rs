//! Nominal state, error-state layout and the injection of an error estimate into the nominal state
//! (docs/navigation_filter.md §1, eqs. (1.1)–(1.3); docs/navigation_filter.md §5, eq. (5.7)).

use nalgebra::{SMatrix, SVector};

use crate::math::{UnitQuat, Vec3};

/// Dimension of the error state δx = [δp, δv, δθ, δb_a, δb_g, δb_h] [-].
pub const STATE_DIM: usize = 16;
/// Index of δp (world NED position error [m]) in δx.
pub const ERR_POS: usize = 0;
/// Index of δv (world NED velocity error [m/s]) in δx.
pub const ERR_VEL: usize = 3;
/// Index of δθ (attitude error, a world-frame rotation vector [rad]) in δx.
pub const ERR_ATT: usize = 6;
/// Index of δb_a (accelerometer bias error, body FRD [m/s²]) in δx.
pub const ERR_ACCEL_BIAS: usize = 9;
/// Index of δb_g (gyroscope bias error, body FRD [rad/s]) in δx.
pub const ERR_GYRO_BIAS: usize = 12;
/// Index of δb_h (barometer height offset error [m]) in δx.
pub const ERR_BARO_OFFSET: usize = 15;

/// Error-state covariance P (docs/navigation_filter.md §1, eq. (1.2)).
pub type Covariance = SMatrix<f64, STATE_DIM, STATE_DIM>;
/// An error-state vector δx.
pub type ErrorVector = SVector<f64, STATE_DIM>;

/// The nominal (best-estimate) state x̂ (docs/navigation_filter.md §1, eq. (1.1)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Nominal {
    /// Position, local NED [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
    /// Accelerometer bias, body FRD [m/s²].
    pub accel_bias_b: Vec3,
    /// Gyroscope bias, body FRD [rad/s].
    pub gyro_bias_b: Vec3,
    /// Barometer height offset: barometric height minus true height above the origin [m].
    pub baro_offset_m: f64,
}

impl Default for Nominal {
    fn default() -> Self {
        Self {
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            q_wb: UnitQuat::identity(),
            accel_bias_b: Vec3::zeros(),
            gyro_bias_b: Vec3::zeros(),
            baro_offset_m: 0.0,
        }
    }
}

/// Three consecutive entries of δx starting at `i`.
pub(super) fn part(dx: &ErrorVector, i: usize) -> Vec3 {
    Vec3::new(dx[i], dx[i + 1], dx[i + 2])
}

/// `Exp(δθ) ⊗ q`: a world-frame rotation error applied to an attitude
/// (docs/navigation_filter.md §1, eq. (1.3)).
pub(super) fn rotate_world(q_wb: &UnitQuat, dtheta_w: &Vec3) -> UnitQuat {
    turn_world(q_wb, &UnitQuat::from_scaled_axis(*dtheta_w))
}

/// `turn ⊗ q`, renormalised: [`rotate_world`] with `Exp(δθ)` computed once by the caller, for a
/// correction applied to many attitudes (docs/navigation_filter.md §7, eq. (7.3)).
#[inline]
pub(super) fn turn_world(q_wb: &UnitQuat, turn: &UnitQuat) -> UnitQuat {
    let mut q = turn * q_wb;
    q.renormalize_fast();
    q
}

impl Nominal {
    /// x̂ ⊞ δx: the nominal state corrected by an error estimate
    /// (docs/navigation_filter.md §5, eq. (5.7)).
    pub fn inject(&mut self, dx: &ErrorVector) {
        self.pos_w += part(dx, ERR_POS);
        self.vel_w += part(dx, ERR_VEL);
        self.q_wb = rotate_world(&self.q_wb, &part(dx, ERR_ATT));
        self.accel_bias_b += part(dx, ERR_ACCEL_BIAS);
        self.gyro_bias_b += part(dx, ERR_GYRO_BIAS);
        self.baro_offset_m += dx[ERR_BARO_OFFSET];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn injection_composes_on_the_world_side() {
        let mut x = Nominal {
            q_wb: UnitQuat::from_euler_angles(0.1, 0.2, 0.3),
            ..Nominal::default()
        };
        let before = x.q_wb;
        let mut dx = ErrorVector::zeros();
        dx[ERR_POS] = 1.0;
        dx[ERR_VEL + 2] = -2.0;
        dx[ERR_ATT + 2] = 0.05;
        dx[ERR_GYRO_BIAS + 1] = 0.01;
        dx[ERR_BARO_OFFSET] = 0.5;
        x.inject(&dx);
        assert_eq!(x.pos_w, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(x.vel_w, Vec3::new(0.0, 0.0, -2.0));
        assert_eq!(x.gyro_bias_b, Vec3::new(0.0, 0.01, 0.0));
        assert_eq!(x.baro_offset_m, 0.5);
        // The correction is a world-frame rotation: undoing it on the left restores the attitude.
        let back = UnitQuat::from_scaled_axis(Vec3::new(0.0, 0.0, -0.05)) * x.q_wb;
        assert!(back.angle_to(&before) < 1e-12);
    }
}
