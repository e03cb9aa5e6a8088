//! The navigation filter's settings, with PX4's EKF2 names, units and defaults
//! (docs/navigation_filter.md).

use crate::nav_filter::HeightSource;
use crate::params::ParamDef;

/// The navigation filter (appended after the navigation-loss failsafe).
pub(super) static NAV_FILTER: &[ParamDef] = &[
    row!(
        "EKF2_HGT_REF",
        Int32,
        [0.0, 1.0],
        "",
        NavFilter,
        "Height reference: 0 barometer, 1 GPS (the other takes over when it times out)",
        |s| match s.nav.height_ref {
            HeightSource::Baro => 0.0,
            HeightSource::Gps => 1.0,
        },
        |s, v| {
            s.nav.height_ref = if v == 0.0 {
                HeightSource::Baro
            } else {
                HeightSource::Gps
            };
            Ok(())
        }
    ),
    row!(
        "EKF2_GPS_DELAY",
        Real32,
        [0.0, 200.0],
        "ms",
        NavFilter,
        "GPS measurement delay relative to the IMU",
        |s| s.nav.gps_delay_s * 1e3,
        |s, v| {
            s.nav.gps_delay_s = v * 1e-3;
            Ok(())
        }
    ),
    row!(
        "EKF2_NOAID_TOUT",
        Int32,
        [500_000.0, 10_000_000.0],
        "us",
        NavFilter,
        "Dead reckoning without GPS after which the horizontal position is invalid",
        |s| (s.nav.noaid_timeout_s * 1e6).round(),
        |s, v| {
            s.nav.noaid_timeout_s = v * 1e-6;
            Ok(())
        }
    ),
    row!(
        "EKF2_MAG_DECL",
        Real32,
        [-180.0, 180.0],
        "deg",
        NavFilter,
        "Magnetic declination (east positive), used when EKF2_DECL_TYPE bit 0 is clear",
        degrees nav.mag_declination_rad
    ),
    row!(
        "EKF2_GPS_P_GATE",
        Real32,
        [1.0, 10.0],
        "SD",
        NavFilter,
        "Gate of the GPS position innovations, in standard deviations",
        value nav.gps_pos_gate_sd
    ),
    row!(
        "EKF2_GPS_V_GATE",
        Real32,
        [1.0, 10.0],
        "SD",
        NavFilter,
        "Gate of the GPS velocity innovations, in standard deviations",
        value nav.gps_vel_gate_sd
    ),
    row!(
        "EKF2_BARO_GATE",
        Real32,
        [1.0, 10.0],
        "SD",
        NavFilter,
        "Gate of the barometric height innovations, in standard deviations",
        value nav.baro_gate_sd
    ),
    row!(
        "EKF2_MAG_GATE",
        Real32,
        [1.0, 10.0],
        "SD",
        NavFilter,
        "Gate of the magnetic heading innovations, in standard deviations",
        value nav.mag_gate_sd
    ),
    row!(
        "EKF2_GPS_P_NOISE",
        Real32,
        [0.01, 10.0],
        "m",
        NavFilter,
        "GPS position noise (the receiver's accuracy is used when larger)",
        value nav.gps_pos_noise_m
    ),
    row!(
        "EKF2_GPS_V_NOISE",
        Real32,
        [0.01, 5.0],
        "m/s",
        NavFilter,
        "GPS velocity noise (the receiver's accuracy is used when larger)",
        value nav.gps_vel_noise_m_s
    ),
    row!(
        "EKF2_BARO_NOISE",
        Real32,
        [0.01, 15.0],
        "m",
        NavFilter,
        "Barometric height noise",
        value nav.baro_noise_m
    ),
    row!(
        "EKF2_HEAD_NOISE",
        Real32,
        [0.01, 1.0],
        "rad",
        NavFilter,
        "Magnetic heading noise",
        value nav.heading_noise_rad
    ),
    row!(
        "EKF2_ACC_NOISE",
        Real32,
        [0.01, 1.0],
        "m/s^2",
        NavFilter,
        "Accelerometer noise of the prediction",
        value nav.accel_noise_m_s2
    ),
    row!(
        "EKF2_GYR_NOISE",
        Real32,
        [0.0001, 0.1],
        "rad/s",
        NavFilter,
        "Gyroscope noise of the prediction",
        value nav.gyro_noise_rad_s
    ),
    row!(
        "EKF2_TAU_VEL",
        Real32,
        [0.1, 1.0],
        "s",
        NavFilter,
        "Time constant over which the filter's corrections reach the output the controllers fly on",
        value nav.output_tau_s
    ),
];
