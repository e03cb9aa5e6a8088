//! Which aids the navigation filter uses (PX4's `EKF2_IMU_CTRL`, `EKF2_GRAV_NOISE`,
//! `EKF2_GPS_CTRL`, `EKF2_MAG_TYPE`), whether arming needs a position (`COM_ARM_WO_GPS`),
//! where the declination comes from (`EKF2_DECL_TYPE`) (docs/navigation_filter.md §6, §10, §20);
//! the switches of the pre-arm checks and of the geofence (`RP_ARM_CHECKS`, `RP_GF_ENABLE`,
//! ArduCopter's `ARMING_CHECK` and `FENCE_ENABLE`).

use crate::params::ParamDef;

/// The aiding sources and arming without GPS (appended after the AUTO vertical speeds).
pub(super) static AIDING_SOURCES: &[ParamDef] = &[
    row!(
        "EKF2_IMU_CTRL",
        Int32,
        [0.0, 7.0],
        "",
        NavFilter,
        "IMU use, a bitmask: 1 gyro bias, 2 accelerometer bias (both always estimated), 4 gravity-vector fusion while nothing aids horizontally",
        |s| f64::from(s.nav.imu_ctrl),
        |s, v| {
            s.nav.imu_ctrl = v as u8;
            Ok(())
        }
    ),
    row!(
        "EKF2_GRAV_NOISE",
        Real32,
        [0.1, 10.0],
        "g0",
        NavFilter,
        "Noise of the gravity-vector observation, as the noise of the unit vector (at least 0.01)",
        value nav.gravity_noise_g
    ),
    row!(
        "EKF2_GPS_CTRL",
        Int32,
        [0.0, 15.0],
        "",
        NavFilter,
        "GNSS use, a bitmask: 1 horizontal position, 2 height, 4 velocity, 8 dual-antenna heading (unused); 0 fuses no GNSS",
        |s| f64::from(s.nav.gps_ctrl),
        |s, v| {
            s.nav.gps_ctrl = v as u8;
            Ok(())
        }
    ),
    row!(
        "EKF2_MAG_TYPE",
        Int32,
        [0.0, 6.0],
        "",
        NavFilter,
        "Magnetometer use: 0 automatic, 1 heading (every value but 5 fuses a heading), 5 none",
        |s| f64::from(s.nav.mag_type),
        |s, v| {
            s.nav.mag_type = v as u8;
            Ok(())
        }
    ),
    row!(
        "COM_ARM_WO_GPS",
        Int32,
        [0.0, 1.0],
        "",
        Commander,
        "Arming without a position estimate in the modes that need none: 0 refused, 1 allowed",
        flag commander.arm_without_gps
    ),
    row!(
        "EKF2_DECL_TYPE",
        Int32,
        [0.0, 3.0],
        "",
        NavFilter,
        "Declination handling, a bitmask: 1 the World Magnetic Model's at home (else EKF2_MAG_DECL), 2 save to EKF2_MAG_DECL at disarm (not acted on)",
        |s| f64::from(s.nav.decl_type),
        |s, v| {
            s.nav.decl_type = v as u8;
            Ok(())
        }
    ),
];

/// The switches ArduCopter's `ARMING_CHECK` and `FENCE_ENABLE` set (appended after the aiding
/// sources).
pub(super) static SWITCHES: &[ParamDef] = &[
    row!(
        "RP_ARM_CHECKS",
        Int32,
        [0.0, 1.0],
        "",
        Commander,
        "1: arming checks the sticks (present, throttle low) and the geofence first; 0 skips them (the estimate and the mode's needs are always checked)",
        flag commander.arming_checks
    ),
    row!(
        "RP_GF_ENABLE",
        Int32,
        [0.0, 1.0],
        "",
        Failsafe,
        "1: the geofence (GF_MAX_* limits, uploaded zones) is checked before arming and acted on; 0: off",
        flag commander.failsafe.geofence_enabled
    ),
];
