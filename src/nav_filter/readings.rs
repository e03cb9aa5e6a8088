//! The flight controller's own sensor readings, as the navigation filter takes them
//! (docs/navigation_filter.md §1). Whoever owns a sensor converts its samples into these; the
//! filter never sees the simulator's types.

use crate::math::Vec3;

/// One inertial sample: specific force and angular rate in body FRD.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuReading {
    /// Sample time [s].
    pub t_s: f64,
    /// Specific force (accelerometer), body FRD [m/s²]; reads −g along z at rest and level.
    pub accel_b: Vec3,
    /// Angular rate (gyroscope), body FRD [rad/s].
    pub gyro_b: Vec3,
}

/// One GNSS fix, already converted to the local NED frame of whoever converts it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsReading {
    /// Arrival time [s]; the fix describes the vehicle at `t_s − gps_delay_s`
    /// (docs/navigation_filter.md §7, eq. (7.1)).
    pub t_s: f64,
    /// Position, local NED [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Reported horizontal position accuracy (1σ) [m].
    pub h_acc_m: f64,
    /// Reported vertical position accuracy (1σ) [m].
    pub v_acc_m: f64,
    /// Reported speed accuracy (1σ) [m/s].
    pub speed_acc_m_s: f64,
    /// Whether the receiver reports a 3-D fix.
    pub fix_3d: bool,
    /// Satellites used in the fix.
    pub satellites: u8,
}

/// One barometer sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaroReading {
    /// Sample time [s].
    pub t_s: f64,
    /// Static pressure [Pa].
    pub pressure_pa: f64,
    /// Sensor temperature [°C]; the ISA conversion does not use it
    /// (docs/navigation_filter.md §8, eq. (8.1)).
    pub temperature_c: f64,
}

/// One magnetometer sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagReading {
    /// Sample time [s].
    pub t_s: f64,
    /// Magnetic field, body FRD [gauss] (calibrated: hard and soft iron removed).
    pub field_b: Vec3,
}

/// Whether every number of a vector is finite.
pub(super) fn finite3(v: &Vec3) -> bool {
    v.iter().all(|c| c.is_finite())
}

impl ImuReading {
    /// Every field finite.
    pub(super) fn is_finite(&self) -> bool {
        self.t_s.is_finite() && finite3(&self.accel_b) && finite3(&self.gyro_b)
    }
}

impl GpsReading {
    /// Every numeric field finite.
    pub(super) fn is_finite(&self) -> bool {
        self.t_s.is_finite()
            && finite3(&self.pos_w)
            && finite3(&self.vel_w)
            && self.h_acc_m.is_finite()
            && self.v_acc_m.is_finite()
            && self.speed_acc_m_s.is_finite()
    }
}
