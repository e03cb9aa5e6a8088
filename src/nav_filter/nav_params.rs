//! Tuning of the navigation filter: PX4 EKF2's parameters in SI units, defaults = PX4's
//! defaults (docs/navigation_filter.md §4, §6, §8–§12).

use thiserror::Error;

/// Height source (PX4 `EKF2_HGT_REF`: 0 barometer, 1 GNSS) (docs/navigation_filter.md §9).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeightSource {
    /// Barometric pressure altitude.
    Baro,
    /// GNSS down position.
    Gps,
}

impl HeightSource {
    /// The other source.
    pub fn other(self) -> Self {
        match self {
            Self::Baro => Self::Gps,
            Self::Gps => Self::Baro,
        }
    }
}

/// Filter parameters. Names in brackets are the PX4 parameters they carry over; process noises
/// follow PX4's convention (docs/navigation_filter.md §4, eq. (4.3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavParams {
    /// Covariance prediction period T_p [s] (`EKF2_PREDICT_US` 10 000 µs).
    pub predict_period_s: f64,
    /// Accelerometer noise σ_a [m/s²] (`EKF2_ACC_NOISE` 0.35).
    pub accel_noise_m_s2: f64,
    /// Gyroscope noise σ_g [rad/s] (`EKF2_GYR_NOISE` 0.015).
    pub gyro_noise_rad_s: f64,
    /// Accelerometer bias random walk σ_ba [m/s³] (`EKF2_ACC_B_NOISE` 0.003).
    pub accel_bias_noise_m_s3: f64,
    /// Gyroscope bias random walk σ_bg [rad/s²] (`EKF2_GYR_B_NOISE` 0.001).
    pub gyro_bias_noise_rad_s2: f64,
    /// Barometer offset random walk σ_bh [m/s] while the barometer is not the active height
    /// source (rotorpilot's own; PX4 runs a separate bias estimator).
    pub baro_offset_noise_m_s: f64,
    /// Initial accelerometer bias uncertainty (1σ) [m/s²] (`EKF2_ABIAS_INIT` 0.2).
    pub accel_bias_init_m_s2: f64,
    /// Switch-on gyroscope bias uncertainty (1σ) [rad/s] (`EKF2_GBIAS_INIT` 0.1); the alignment
    /// at rest measures the bias and starts from a smaller uncertainty
    /// (docs/navigation_filter.md §11, eq. (11.3)).
    pub gyro_bias_init_rad_s: f64,
    /// Time from a GNSS fix's validity to its arrival [s] (`EKF2_GPS_DELAY` 110 ms).
    pub gps_delay_s: f64,
    /// Lower bound of the GNSS position noise (1σ) [m] (`EKF2_GPS_P_NOISE` 0.5).
    pub gps_pos_noise_m: f64,
    /// Lower bound of the GNSS velocity noise (1σ) [m/s] (`EKF2_GPS_V_NOISE` 0.3).
    pub gps_vel_noise_m_s: f64,
    /// GNSS position innovation gate, horizontal and height [SD] (`EKF2_GPS_P_GATE` 5).
    pub gps_pos_gate_sd: f64,
    /// GNSS velocity innovation gate [SD] (`EKF2_GPS_V_GATE` 5).
    pub gps_vel_gate_sd: f64,
    /// Fewest satellites for a usable fix [-] (`EKF2_REQ_NSATS` 6).
    pub gps_min_satellites: u8,
    /// Largest reported horizontal accuracy for a usable fix [m] (`EKF2_REQ_EPH` 3).
    pub gps_max_h_acc_m: f64,
    /// Largest reported vertical accuracy for a usable fix [m] (`EKF2_REQ_EPV` 5).
    pub gps_max_v_acc_m: f64,
    /// Largest reported speed accuracy for a usable fix [m/s] (`EKF2_REQ_SACC` 0.5).
    pub gps_max_speed_acc_m_s: f64,
    /// Barometer delay [s] (`EKF2_BARO_DELAY` 0).
    pub baro_delay_s: f64,
    /// Barometric height noise (1σ) [m] (`EKF2_BARO_NOISE` 3.5).
    pub baro_noise_m: f64,
    /// Barometric height innovation gate [SD] (`EKF2_BARO_GATE` 5); GNSS height uses
    /// `gps_pos_gate_sd`, as PX4 does.
    pub baro_gate_sd: f64,
    /// Magnetometer delay [s] (`EKF2_MAG_DELAY` 0).
    pub mag_delay_s: f64,
    /// Magnetic heading noise (1σ) [rad] (`EKF2_HEAD_NOISE` 0.3).
    pub heading_noise_rad: f64,
    /// Magnetic heading innovation gate [SD] (`EKF2_MAG_GATE` 3).
    pub mag_gate_sd: f64,
    /// Magnetic declination, east of true north positive [rad] (`EKF2_MAG_DECL` 0): used when
    /// `decl_type` does not ask for the World Magnetic Model's, or the model gives none
    /// (docs/navigation_filter.md §10, eq. (10.5)).
    pub mag_declination_rad: f64,
    /// Declination handling (`EKF2_DECL_TYPE` 3, a bitmask): bit 0 takes the World Magnetic
    /// Model's declination at home instead of `mag_declination_rad`; bit 1 (PX4 saves the
    /// declination to `EKF2_MAG_DECL` at disarm) is accepted and not acted on.
    pub decl_type: u8,
    /// Height reference (`EKF2_HGT_REF`, GNSS).
    pub height_ref: HeightSource,
    /// Time without a fused height sample after which the active height source is replaced
    /// [s] (PX4's height fusion time-out, 5 s).
    pub height_timeout_s: f64,
    /// Inertial dead-reckoning time after which horizontal position and velocity turn invalid
    /// [s] (`EKF2_NOAID_TOUT` 5 000 000 µs).
    pub noaid_timeout_s: f64,
    /// Noise of the position-hold pseudo-measurement when nothing aids (1σ) [m]
    /// (`EKF2_NOAID_NOISE` 10).
    pub noaid_noise_m: f64,
    /// Time without a sample after which a sensor is reported timed out [s] (rotorpilot's own).
    pub sensor_timeout_s: f64,
    /// Averaging window of the alignment at rest [s] (rotorpilot's own).
    pub align_time_s: f64,
    /// Time constant over which corrections reach the output the controllers fly on [s]
    /// (`EKF2_TAU_VEL` and `EKF2_TAU_POS`, 0.25) (docs/navigation_filter.md §16).
    pub output_tau_s: f64,
    /// IMU use (`EKF2_IMU_CTRL` 7, a bitmask): bit 2 turns gravity-vector fusion on
    /// (docs/navigation_filter.md §20); bits 0 and 1 (gyro and accelerometer bias estimation)
    /// are kept for PX4's tools, rotorpilot always estimates both biases.
    pub imu_ctrl: u8,
    /// Noise of the gravity-vector observation (`EKF2_GRAV_NOISE` 1.0) [g0], used as the noise
    /// of the unit vector, at least 0.01 (docs/navigation_filter.md §20, eq. (20.3)).
    pub gravity_noise_g: f64,
    /// GNSS use (`EKF2_GPS_CTRL` 7, a bitmask: bit 0 horizontal position, bit 1 height, bit 2
    /// velocity); 0 stops GNSS fusion (docs/navigation_filter.md §6).
    pub gps_ctrl: u8,
    /// Magnetometer use (`EKF2_MAG_TYPE` 0 automatic; 5 none stops magnetometer fusion)
    /// (docs/navigation_filter.md §10).
    pub mag_type: u8,
}

/// `EKF2_IMU_CTRL` bit turning gravity-vector fusion on (docs/navigation_filter.md §20).
pub const IMU_CTRL_GRAVITY: u8 = 1 << 2;
/// `EKF2_GPS_CTRL` bits of the parts rotorpilot fuses: horizontal position, height, velocity.
pub const GPS_CTRL_FUSED: u8 = 0b111;
/// `EKF2_DECL_TYPE` bit taking the declination from the World Magnetic Model at home.
pub const DECL_TYPE_USE_GEO: u8 = 1;
/// `EKF2_MAG_TYPE` value for "no magnetometer fusion".
pub const MAG_TYPE_NONE: u8 = 5;

impl Default for NavParams {
    fn default() -> Self {
        Self {
            predict_period_s: 0.01,
            accel_noise_m_s2: 0.35,
            gyro_noise_rad_s: 0.015,
            accel_bias_noise_m_s3: 0.003,
            gyro_bias_noise_rad_s2: 0.001,
            baro_offset_noise_m_s: 0.05,
            accel_bias_init_m_s2: 0.2,
            gyro_bias_init_rad_s: 0.1,
            gps_delay_s: 0.110,
            gps_pos_noise_m: 0.5,
            gps_vel_noise_m_s: 0.3,
            gps_pos_gate_sd: 5.0,
            gps_vel_gate_sd: 5.0,
            gps_min_satellites: 6,
            gps_max_h_acc_m: 3.0,
            gps_max_v_acc_m: 5.0,
            gps_max_speed_acc_m_s: 0.5,
            baro_delay_s: 0.0,
            baro_noise_m: 3.5,
            baro_gate_sd: 5.0,
            mag_delay_s: 0.0,
            heading_noise_rad: 0.3,
            mag_gate_sd: 3.0,
            mag_declination_rad: 0.0,
            decl_type: 3,
            height_ref: HeightSource::Gps,
            height_timeout_s: 5.0,
            noaid_timeout_s: 5.0,
            noaid_noise_m: 10.0,
            sensor_timeout_s: 1.0,
            align_time_s: 1.0,
            output_tau_s: 0.25,
            imu_ctrl: 7,
            gravity_noise_g: 1.0,
            gps_ctrl: 7,
            mag_type: 0,
        }
    }
}

/// Longest sensor delay the state history covers [s] (PX4's `EKF2_DELAY_MAX` is 200 ms)
/// (docs/navigation_filter.md §7).
pub const MAX_DELAY_S: f64 = 0.2;

/// A parameter set the filter refuses.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NavParamsError {
    /// A value outside its range (or not a number).
    #[error("navigation filter parameter {name} = {value} must be in [{min}, {max}]")]
    OutOfRange {
        /// Field name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
}

impl NavParams {
    /// Checks every field against its range (docs/navigation_filter.md §4, §7).
    pub fn validate(&self) -> Result<(), NavParamsError> {
        let big = 1e6;
        let checks: [(&'static str, f64, f64, f64); 35] = [
            ("predict_period_s", self.predict_period_s, 1e-3, 0.02),
            ("accel_noise_m_s2", self.accel_noise_m_s2, 1e-6, 10.0),
            ("gyro_noise_rad_s", self.gyro_noise_rad_s, 1e-7, 1.0),
            ("accel_bias_noise_m_s3", self.accel_bias_noise_m_s3, 0.0, 1.0),
            ("gyro_bias_noise_rad_s2", self.gyro_bias_noise_rad_s2, 0.0, 1.0),
            ("baro_offset_noise_m_s", self.baro_offset_noise_m_s, 0.0, 10.0),
            ("accel_bias_init_m_s2", self.accel_bias_init_m_s2, 1e-6, 5.0),
            ("gyro_bias_init_rad_s", self.gyro_bias_init_rad_s, 1e-7, 1.0),
            ("gps_delay_s", self.gps_delay_s, 0.0, MAX_DELAY_S),
            ("gps_pos_noise_m", self.gps_pos_noise_m, 1e-3, 100.0),
            ("gps_vel_noise_m_s", self.gps_vel_noise_m_s, 1e-3, 10.0),
            ("gps_pos_gate_sd", self.gps_pos_gate_sd, 1.0, big),
            ("gps_vel_gate_sd", self.gps_vel_gate_sd, 1.0, big),
            ("gps_min_satellites", f64::from(self.gps_min_satellites), 0.0, 64.0),
            ("gps_max_h_acc_m", self.gps_max_h_acc_m, 0.0, big),
            ("gps_max_v_acc_m", self.gps_max_v_acc_m, 0.0, big),
            ("gps_max_speed_acc_m_s", self.gps_max_speed_acc_m_s, 0.0, big),
            ("baro_delay_s", self.baro_delay_s, 0.0, MAX_DELAY_S),
            ("baro_noise_m", self.baro_noise_m, 1e-3, 100.0),
            ("baro_gate_sd", self.baro_gate_sd, 1.0, big),
            ("mag_delay_s", self.mag_delay_s, 0.0, MAX_DELAY_S),
            ("heading_noise_rad", self.heading_noise_rad, 1e-4, 3.0),
            ("mag_gate_sd", self.mag_gate_sd, 1.0, big),
            (
                "mag_declination_rad",
                self.mag_declination_rad,
                -std::f64::consts::PI,
                std::f64::consts::PI,
            ),
            ("height_timeout_s", self.height_timeout_s, 0.1, 600.0),
            ("noaid_timeout_s", self.noaid_timeout_s, 0.1, 600.0),
            ("noaid_noise_m", self.noaid_noise_m, 0.1, 1000.0),
            ("sensor_timeout_s", self.sensor_timeout_s, 0.01, 600.0),
            ("align_time_s", self.align_time_s, 0.01, 60.0),
            ("output_tau_s", self.output_tau_s, 0.01, 10.0),
            ("imu_ctrl", f64::from(self.imu_ctrl), 0.0, 7.0),
            ("gravity_noise_g", self.gravity_noise_g, 0.1, 10.0),
            ("gps_ctrl", f64::from(self.gps_ctrl), 0.0, 15.0),
            ("mag_type", f64::from(self.mag_type), 0.0, 6.0),
            ("decl_type", f64::from(self.decl_type), 0.0, 3.0),
        ];
        for (name, value, min, max) in checks {
            if !(value.is_finite() && value >= min && value <= max) {
                return Err(NavParamsError::OutOfRange { name, value, min, max });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_px4_and_valid() {
        let p = NavParams::default();
        assert_eq!(p.validate(), Ok(()));
        assert_eq!((p.accel_noise_m_s2, p.gyro_noise_rad_s), (0.35, 0.015));
        assert_eq!((p.accel_bias_noise_m_s3, p.gyro_bias_noise_rad_s2), (0.003, 0.001));
        assert_eq!(
            (p.gps_pos_gate_sd, p.gps_vel_gate_sd, p.baro_gate_sd, p.mag_gate_sd),
            (5.0, 5.0, 5.0, 3.0)
        );
        assert_eq!(
            (p.gps_delay_s, p.noaid_timeout_s, p.predict_period_s),
            (0.110, 5.0, 0.01)
        );
        assert_eq!(
            (p.mag_declination_rad, p.decl_type),
            (0.0, 3),
            "the model's declination by default"
        );
    }

    #[test]
    fn out_of_range_names_the_field() {
        let p = NavParams {
            gps_delay_s: 0.5,
            ..NavParams::default()
        };
        let Err(NavParamsError::OutOfRange { name, .. }) = p.validate() else {
            panic!("accepted")
        };
        assert_eq!(name, "gps_delay_s");
        let p = NavParams {
            baro_noise_m: f64::NAN,
            ..NavParams::default()
        };
        assert!(p.validate().is_err());
        assert_eq!(HeightSource::Baro.other(), HeightSource::Gps);
    }
}
