//! Truth generator for the filter's tests: a smooth analytic trajectory (position and ZYX
//! Euler angles as `A (1 − cos ω τ)` after a rest period) and sensor readings drawn from it
//! with known Gaussian noise, biases and bias random walks (ChaCha8 + Box–Muller, seeded).

use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::math::{e3, UnitQuat, Vec3, GRAVITY_M_S2};
use crate::nav_filter::isa::pressure_at_altitude_pa;
use crate::nav_filter::{BaroReading, GpsReading, HeightSource, ImuReading, MagReading, NavParams};

/// IMU period of every test [s].
pub const IMU_DT_S: f64 = 1e-3;

/// Motion: each axis `x_i(t) = x0_i + A_i (1 − cos(ω_i τ))`, `τ = max(t − rest_s, 0)`.
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    /// Time at rest before the motion starts [s].
    pub rest_s: f64,
    /// Position amplitudes, NED [m].
    pub pos_amp: Vec3,
    /// Position angular frequencies [rad/s].
    pub pos_freq: Vec3,
    /// Initial roll, pitch, yaw [rad].
    pub euler0: Vec3,
    /// Roll, pitch, yaw amplitudes [rad].
    pub euler_amp: Vec3,
    /// Roll, pitch, yaw angular frequencies [rad/s].
    pub euler_freq: Vec3,
}

impl Motion {
    /// At rest, level, facing `yaw` [rad].
    pub fn hover(yaw: f64) -> Self {
        Self {
            rest_s: 1e9,
            pos_amp: Vec3::zeros(),
            pos_freq: Vec3::zeros(),
            euler0: Vec3::new(0.0, 0.0, yaw),
            euler_amp: Vec3::zeros(),
            euler_freq: Vec3::zeros(),
        }
    }

    /// Curves in all three axes with tilts and large yaw swings, after 5 s at rest.
    pub fn curves() -> Self {
        Self {
            rest_s: 5.0,
            pos_amp: Vec3::new(20.0, -15.0, -3.0),
            pos_freq: Vec3::new(0.15, 0.11, 0.2),
            euler0: Vec3::new(0.02, -0.01, 0.7),
            euler_amp: Vec3::new(0.12, 0.1, 1.2),
            euler_freq: Vec3::new(0.7, 0.5, 0.13),
        }
    }
}

/// The true state at one instant.
#[derive(Debug, Clone, Copy)]
pub struct TrueMotion {
    pub t_s: f64,
    pub pos_w: Vec3,
    pub vel_w: Vec3,
    pub accel_w: Vec3,
    pub q_wb: UnitQuat,
    pub omega_b: Vec3,
}

fn cosine_axis(amp: f64, freq: f64, tau: f64) -> (f64, f64, f64) {
    let (s, c) = (freq * tau).sin_cos();
    (
        amp * (1.0 - c),
        amp * freq * s,
        amp * freq * freq * c * f64::from(u8::from(tau > 0.0)),
    )
}

impl Motion {
    /// The true state at `t_s` [s].
    pub fn at(&self, t_s: f64) -> TrueMotion {
        let tau = (t_s - self.rest_s).max(0.0);
        let (mut pos, mut vel, mut acc, mut eta, mut eta_dot) =
            (Vec3::zeros(), Vec3::zeros(), Vec3::zeros(), self.euler0, Vec3::zeros());
        for i in 0..3 {
            let (x, v, a) = cosine_axis(self.pos_amp[i], self.pos_freq[i], tau);
            (pos[i], vel[i], acc[i]) = (x, v, a);
            let (e, ed, _) = cosine_axis(self.euler_amp[i], self.euler_freq[i], tau);
            eta[i] += e;
            eta_dot[i] = ed;
        }
        let (phi, theta) = (eta.x, eta.y);
        let omega_b = Vec3::new(
            eta_dot.x - eta_dot.z * theta.sin(),
            eta_dot.y * phi.cos() + eta_dot.z * phi.sin() * theta.cos(),
            -eta_dot.y * phi.sin() + eta_dot.z * phi.cos() * theta.cos(),
        );
        TrueMotion {
            t_s,
            pos_w: pos,
            vel_w: vel,
            accel_w: acc,
            q_wb: UnitQuat::from_euler_angles(eta.x, eta.y, eta.z),
            omega_b,
        }
    }
}

/// Sensor errors of the generator; all zero is "ideal sensors".
#[derive(Debug, Clone, Copy)]
pub struct SimulatedErrors {
    /// Accelerometer white noise per 1 kHz sample [m/s²].
    pub accel_noise: f64,
    /// Gyroscope white noise per 1 kHz sample [rad/s].
    pub gyro_noise: f64,
    /// Initial accelerometer bias [m/s²].
    pub accel_bias: Vec3,
    /// Initial gyroscope bias [rad/s].
    pub gyro_bias: Vec3,
    /// Accelerometer bias random-walk density [m/s³/√Hz].
    pub accel_bias_rw: f64,
    /// Gyroscope bias random-walk density [rad/s²/√Hz].
    pub gyro_bias_rw: f64,
    /// GNSS horizontal / vertical position and velocity noise [m], [m], [m/s].
    pub gps_h: f64,
    pub gps_v: f64,
    pub gps_vel: f64,
    /// True GNSS delay [s].
    pub gps_delay_s: f64,
    /// Barometric height noise [m].
    pub baro: f64,
    /// Magnetometer noise per axis [gauss].
    pub mag: f64,
}

impl SimulatedErrors {
    /// Noise levels of a good small drone, with switch-on biases.
    pub fn realistic() -> Self {
        Self {
            accel_noise: 0.1,
            gyro_noise: 0.005,
            accel_bias: Vec3::new(0.1, -0.08, 0.15),
            gyro_bias: Vec3::new(0.01, -0.008, 0.012),
            accel_bias_rw: 1e-3,
            gyro_bias_rw: 1e-4,
            gps_h: 0.5,
            gps_v: 0.8,
            gps_vel: 0.1,
            gps_delay_s: 0.11,
            baro: 0.3,
            mag: 0.002,
        }
    }

    /// No noise, no bias; GNSS still delayed by 110 ms.
    pub fn ideal() -> Self {
        Self {
            accel_noise: 0.0,
            gyro_noise: 0.0,
            accel_bias: Vec3::zeros(),
            gyro_bias: Vec3::zeros(),
            accel_bias_rw: 0.0,
            gyro_bias_rw: 0.0,
            gps_h: 0.0,
            gps_v: 0.0,
            gps_vel: 0.0,
            gps_delay_s: 0.11,
            baro: 0.0,
            mag: 0.0,
        }
    }

    /// Filter parameters that describe these errors exactly
    /// (docs/navigation_filter.md §4, eq. (4.4)); floors keep the ideal case well conditioned.
    pub fn matched_params(&self) -> NavParams {
        let d = NavParams::default();
        let per_period = (IMU_DT_S / d.predict_period_s).sqrt();
        let rw = 1.0 / d.predict_period_s.sqrt();
        NavParams {
            accel_noise_m_s2: (self.accel_noise * per_period).max(1e-3),
            gyro_noise_rad_s: (self.gyro_noise * per_period).max(1e-5),
            accel_bias_noise_m_s3: self.accel_bias_rw * rw,
            gyro_bias_noise_rad_s2: self.gyro_bias_rw * rw,
            gps_delay_s: self.gps_delay_s,
            gps_pos_noise_m: self.gps_h.max(0.01),
            gps_vel_noise_m_s: self.gps_vel.max(0.01),
            baro_noise_m: self.baro.max(0.01),
            heading_noise_rad: (self.mag / FIELD_W.xy().norm()).max(1e-3),
            mag_declination_rad: DECLINATION_RAD,
            height_ref: HeightSource::Gps,
            ..d
        }
    }
}

/// Declination of the generated field [rad] (3°, the filter's default).
pub const DECLINATION_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;
/// Earth field, NED [gauss]: 0.21 G horizontal at 3° east, 0.43 G down.
pub const FIELD_W: Vec3 = Vec3::new(0.209_712_2, 0.010_990_6, 0.43);
/// Altitude of the start point above sea level [m].
pub const GROUND_ALT_M: f64 = 488.0;
/// The GNSS readings' frame is shifted from the truth's by this [m].
pub const GPS_FRAME_OFFSET: Vec3 = Vec3::new(120.0, -45.0, -7.0);

/// Generator of readings from a motion, with seeded noise.
pub struct Truth {
    pub motion: Motion,
    pub errors: SimulatedErrors,
    rng: ChaCha8Rng,
    accel_bias: Vec3,
    gyro_bias: Vec3,
}

/// One standard normal variate (Box–Muller, cosine branch, 53-bit uniforms).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let uniform = |rng: &mut ChaCha8Rng| (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
    let u1 = 1.0 - uniform(rng);
    let u2 = uniform(rng);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

impl Truth {
    pub fn new(motion: Motion, errors: SimulatedErrors, seed: u64) -> Self {
        Self {
            motion,
            errors,
            rng: ChaCha8Rng::seed_from_u64(seed),
            accel_bias: errors.accel_bias,
            gyro_bias: errors.gyro_bias,
        }
    }

    fn noise3(&mut self, sd: f64) -> Vec3 {
        Vec3::new(
            gaussian(&mut self.rng),
            gaussian(&mut self.rng),
            gaussian(&mut self.rng),
        ) * sd
    }

    /// Current true biases (accelerometer, gyroscope).
    pub fn biases(&self) -> (Vec3, Vec3) {
        (self.accel_bias, self.gyro_bias)
    }

    /// The IMU sample at `t_s`; advances the bias random walks by one IMU period.
    pub fn imu(&mut self, t_s: f64) -> ImuReading {
        let s = self.motion.at(t_s);
        let e = self.errors;
        let step = IMU_DT_S.sqrt();
        let (da, dg) = (self.noise3(e.accel_bias_rw * step), self.noise3(e.gyro_bias_rw * step));
        self.accel_bias += da;
        self.gyro_bias += dg;
        let specific_w = s.accel_w - e3() * GRAVITY_M_S2;
        ImuReading {
            t_s,
            accel_b: s.q_wb.inverse_transform_vector(&specific_w) + self.accel_bias + self.noise3(e.accel_noise),
            gyro_b: s.omega_b + self.gyro_bias + self.noise3(e.gyro_noise),
        }
    }

    /// The GNSS fix arriving at `t_s` (valid `gps_delay_s` earlier), in the shifted frame.
    pub fn gps(&mut self, t_s: f64) -> GpsReading {
        let e = self.errors;
        let s = self.motion.at(t_s - e.gps_delay_s);
        let pos_noise = Vec3::new(
            gaussian(&mut self.rng) * e.gps_h,
            gaussian(&mut self.rng) * e.gps_h,
            gaussian(&mut self.rng) * e.gps_v,
        );
        GpsReading {
            t_s,
            pos_w: s.pos_w + GPS_FRAME_OFFSET + pos_noise,
            vel_w: s.vel_w + self.noise3(e.gps_vel),
            h_acc_m: e.gps_h,
            v_acc_m: e.gps_v,
            speed_acc_m_s: e.gps_vel,
            fix_3d: true,
            satellites: 14,
        }
    }

    /// The barometer sample at `t_s`, with `offset_m` [m] added to the barometric altitude.
    pub fn baro(&mut self, t_s: f64, offset_m: f64) -> BaroReading {
        let s = self.motion.at(t_s);
        let altitude = GROUND_ALT_M - s.pos_w.z + offset_m + gaussian(&mut self.rng) * self.errors.baro;
        BaroReading {
            t_s,
            pressure_pa: pressure_at_altitude_pa(altitude),
            temperature_c: 20.0,
        }
    }

    /// The magnetometer sample at `t_s`.
    pub fn mag(&mut self, t_s: f64) -> MagReading {
        let s = self.motion.at(t_s);
        let field_b = s.q_wb.inverse_transform_vector(&FIELD_W) + self.noise3(self.errors.mag);
        MagReading { t_s, field_b }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_derivatives_match_finite_differences() {
        let m = Motion::curves();
        let h = 1e-5;
        for t in [5.5, 12.0, 40.0] {
            let (a, b, c) = (m.at(t - h), m.at(t), m.at(t + h));
            assert!(((c.pos_w - a.pos_w) / (2.0 * h) - b.vel_w).norm() < 1e-6);
            assert!(((c.vel_w - a.vel_w) / (2.0 * h) - b.accel_w).norm() < 1e-6);
            // ω_b from R(t + h) = R(t) Exp(ω h).
            let omega = (a.q_wb.inverse() * c.q_wb).scaled_axis() / (2.0 * h);
            assert!((omega - b.omega_b).norm() < 1e-6, "{omega} vs {}", b.omega_b);
        }
        assert!((FIELD_W.y.atan2(FIELD_W.x) - DECLINATION_RAD).abs() < 1e-6);
    }
}
