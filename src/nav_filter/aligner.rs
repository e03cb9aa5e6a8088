//! Alignment at rest: the window of IMU, magnetometer and barometer samples while the vehicle
//! stands still, and its end, which sets the attitude, the gyro bias, the accelerometer bias
//! along gravity, the initial covariance and the barometric altitude of the origin
//! (docs/navigation_filter.md §11, eqs. (11.1)–(11.6)).

use crate::math::{UnitQuat, Vec3, GRAVITY_M_S2};

use super::alignment::{initial_covariance, tilt_from_accel, vertical_accel_bias, yaw_from_mag};
use super::error_state::ErrorStateFilter;
use super::fuse_mag::{heading_jacobian, tan_inclination};
use super::nav_params::{HeightSource, NavParams};
use super::readings::ImuReading;
use super::state::Nominal;

/// Largest | ‖f‖ − g | of a sample counted as "at rest" [m/s²] (docs/navigation_filter.md §11).
const REST_ACCEL_TOL_M_S2: f64 = 1.0;
/// Largest ‖ω‖ of a sample counted as "at rest" [rad/s] (docs/navigation_filter.md §11).
const REST_GYRO_TOL_RAD_S: f64 = 0.25;

/// Sums over the alignment window.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Aligner {
    start_s: Option<f64>,
    last_s: f64,
    accel_sum_b: Vec3,
    gyro_sum_b: Vec3,
    imu_count: u32,
    mag_sum_b: Vec3,
    mag_count: u32,
    baro_sum_m: f64,
    baro_count: u32,
    /// Low-passed specific force and rate the rest test reads (single samples are too noisy).
    rest_accel_b: Option<Vec3>,
    rest_gyro_b: Vec3,
}

/// Weight of a new sample in the low-passed values the rest test reads [-]: a time constant of
/// 50 samples (50 ms at 1 kHz), so a noisy IMU at rest stays at rest.
const REST_FILTER_GAIN: f64 = 0.02;

impl Aligner {
    /// Adds one IMU sample; when the low-passed specific force and rate say the vehicle moves,
    /// the window restarts. True once the window spans `window_s` [s]
    /// (docs/navigation_filter.md §11).
    pub fn add_imu(&mut self, imu: &ImuReading, window_s: f64) -> bool {
        let accel = match self.rest_accel_b {
            Some(a) => a + REST_FILTER_GAIN * (imu.accel_b - a),
            None => imu.accel_b,
        };
        let gyro = self.rest_gyro_b + REST_FILTER_GAIN * (imu.gyro_b - self.rest_gyro_b);
        self.rest_accel_b = Some(accel);
        self.rest_gyro_b = gyro;
        let at_rest = (accel.norm() - GRAVITY_M_S2).abs() <= REST_ACCEL_TOL_M_S2 && gyro.norm() <= REST_GYRO_TOL_RAD_S;
        if !at_rest {
            *self = Self {
                rest_accel_b: Some(accel),
                rest_gyro_b: gyro,
                ..Self::default()
            };
            return false;
        }
        let start = *self.start_s.get_or_insert(imu.t_s);
        self.last_s = imu.t_s;
        self.accel_sum_b += imu.accel_b;
        self.gyro_sum_b += imu.gyro_b;
        self.imu_count += 1;
        imu.t_s - start >= window_s
    }

    /// Adds one magnetometer sample [gauss] (ignored before the window starts).
    pub fn add_mag(&mut self, field_b: &Vec3) {
        if self.start_s.is_some() {
            self.mag_sum_b += field_b;
            self.mag_count += 1;
        }
    }

    /// Adds one barometric altitude [m] (ignored before the window starts).
    pub fn add_baro(&mut self, altitude_m: f64) {
        if self.start_s.is_some() {
            self.baro_sum_m += altitude_m;
            self.baro_count += 1;
        }
    }

    fn mean_accel_b(&self) -> Vec3 {
        self.accel_sum_b / f64::from(self.imu_count.max(1))
    }

    fn mean_gyro_b(&self) -> Vec3 {
        self.gyro_sum_b / f64::from(self.imu_count.max(1))
    }

    fn window_s(&self) -> f64 {
        self.start_s.map_or(0.0, |s| self.last_s - s)
    }

    fn mean_mag_b(&self) -> Option<Vec3> {
        (self.mag_count > 0).then(|| self.mag_sum_b / f64::from(self.mag_count))
    }

    fn mean_baro_m(&self) -> Option<f64> {
        (self.baro_count > 0).then(|| self.baro_sum_m / f64::from(self.baro_count))
    }
}

/// The alignment: its window, and whether it ended.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Alignment {
    /// Sums over the window.
    pub aligner: Aligner,
    /// The window ended and the state was set from it.
    pub aligned: bool,
}

/// What the end of the alignment found for the other parts of the filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct AlignmentOutcome {
    /// The yaw was set from the magnetometer.
    pub yaw_aligned: bool,
    /// tan of the field's inclination when the yaw was set [-].
    pub tan_inclination: Option<f64>,
    /// The mean barometric altitude over the window [m], `None` without barometer samples.
    pub baro_origin_m: Option<f64>,
}

impl Alignment {
    /// Ends the alignment: attitude from the window's means (the yaw with declination `decl`
    /// [rad]), gyro bias from the mean rate, the accelerometer bias along gravity from the mean
    /// specific force's magnitude, state at the origin and at rest, initial covariance (for
    /// `active_height`), barometric altitude of the origin
    /// (docs/navigation_filter.md §11, eqs. (11.1)–(11.3), (11.6)).
    pub fn finish(
        &mut self,
        core: &mut ErrorStateFilter,
        params: &NavParams,
        decl: f64,
        active_height: HeightSource,
    ) -> AlignmentOutcome {
        let (roll, pitch) = tilt_from_accel(&self.aligner.mean_accel_b());
        let mean_mag = self.aligner.mean_mag_b();
        let yaw = mean_mag.and_then(|m| yaw_from_mag(roll, pitch, &m, decl));
        let q_wb = UnitQuat::from_euler_angles(roll, pitch, yaw.unwrap_or(0.0));
        let x = Nominal {
            q_wb,
            gyro_bias_b: self.aligner.mean_gyro_b(),
            accel_bias_b: vertical_accel_bias(&self.aligner.mean_accel_b()),
            ..Nominal::default()
        };
        let p = initial_covariance(params, active_height, &q_wb, self.aligner.window_s());
        core.restart(x, p);
        let tan_incl = yaw.and(mean_mag).and_then(|m| tan_inclination(&q_wb, &m));
        if let Some(tan_incl) = tan_incl {
            core.yaw_covariance_from_heading(&heading_jacobian(decl, tan_incl), params.heading_noise_rad);
        }
        self.aligned = true;
        AlignmentOutcome {
            yaw_aligned: yaw.is_some(),
            tan_inclination: tan_incl,
            baro_origin_m: self.aligner.mean_baro_m(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_restarts_the_window_and_a_noisy_sample_does_not() {
        let mut a = Aligner::default();
        let rest = |t: f64| ImuReading {
            t_s: t,
            accel_b: Vec3::new(0.0, 0.0, -GRAVITY_M_S2),
            gyro_b: Vec3::zeros(),
        };
        let turning = |t: f64| ImuReading {
            gyro_b: Vec3::new(1.0, 0.0, 0.0),
            ..rest(t)
        };
        assert!(!a.add_imu(&rest(0.0), 0.5));
        // One sample far off (an IMU's noise) keeps the window...
        assert!(!a.add_imu(&turning(0.1), 0.5));
        assert!(a.add_imu(&rest(0.5), 0.5), "0.5 s at rest");
        // ...a turn of 0.1 s restarts it.
        let mut a = Aligner::default();
        assert!(!a.add_imu(&rest(0.0), 0.5));
        for k in 0..100 {
            assert!(!a.add_imu(&turning(0.2 + 1e-3 * f64::from(k)), 0.5));
        }
        for k in 0..200 {
            assert!(
                !a.add_imu(&rest(0.3 + 1e-3 * f64::from(k)), 0.5),
                "settling after the turn"
            );
        }
        assert!(!a.add_imu(&rest(0.6), 0.5), "the window restarted with the turn");
        assert!(a.add_imu(&rest(1.2), 0.5));
    }

    #[test]
    fn the_end_of_the_window_sets_the_state_from_its_means() {
        let params = NavParams::default();
        let q = UnitQuat::from_euler_angles(0.05, -0.02, 0.0);
        let f_b = q.inverse() * Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
        let mut a = Alignment::default();
        for k in 0..=500 {
            let imu = ImuReading {
                t_s: 1e-3 * f64::from(k),
                accel_b: f_b,
                gyro_b: Vec3::new(0.001, 0.0, -0.002),
            };
            a.aligner.add_imu(&imu, params.align_time_s);
        }
        a.aligner.add_baro(100.0);
        a.aligner.add_baro(102.0);
        let mut core = ErrorStateFilter::new();
        let out = a.finish(&mut core, &params, params.mag_declination_rad, HeightSource::Gps);
        assert!(a.aligned);
        assert_eq!(out.baro_origin_m, Some(101.0));
        assert!(!out.yaw_aligned && out.tan_inclination.is_none(), "no magnetometer");
        let (roll, pitch, _) = core.x.q_wb.euler_angles();
        assert!((roll - 0.05).abs() < 1e-9 && (pitch + 0.02).abs() < 1e-9);
        assert!((core.x.gyro_bias_b - Vec3::new(0.001, 0.0, -0.002)).norm() < 1e-15);
        assert_eq!(core.x.pos_w, Vec3::zeros());
        assert!(core.p[(0, 0)] > 0.0);
    }
}
