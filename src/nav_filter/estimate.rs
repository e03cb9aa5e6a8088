//! The navigation solution handed to the rest of the flight controller
//! (docs/navigation_filter.md §1, §13).

use crate::math::{UnitQuat, Vec3};

/// The current nominal state and its standard deviations
/// (docs/navigation_filter.md §1, eqs. (1.1)–(1.2)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavEstimate {
    /// Time of the latest IMU sample [s].
    pub t_s: f64,
    /// Position, local NED relative to the filter's origin [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
    /// Angular velocity, body FRD: the latest gyro sample minus the gyro bias [rad/s].
    pub omega_b: Vec3,
    /// Accelerometer bias, body FRD [m/s²].
    pub accel_bias_b: Vec3,
    /// Gyroscope bias, body FRD [rad/s].
    pub gyro_bias_b: Vec3,
    /// Barometer height offset (barometric minus true height above the origin) [m].
    pub baro_offset_m: f64,
    /// Position standard deviations, NED [m].
    pub pos_std_w: Vec3,
    /// Velocity standard deviations, NED [m/s].
    pub vel_std_w: Vec3,
    /// Attitude standard deviations about the world N, E, D axes [rad].
    pub att_std_w: Vec3,
}
