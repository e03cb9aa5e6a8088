//! The state sensor: the exact state with Gaussian noise drawn from an injected, seeded ChaCha RNG
//! (docs/model.md §6, eqs. (6.1)–(6.2)).
//!
//! Noise is zero by default, and then the sample equals the truth bit for bit. Normal variates
//! come from the Box–Muller transform on 53-bit uniforms ([`super::gauss`]), so a seed gives the
//! same samples on every platform and every version of this crate.

use nalgebra::{UnitQuaternion, Vector3};
use rand_chacha::ChaCha8Rng;

use super::gauss::gaussian3;
use crate::rigid_body::RigidBodyState;
use crate::GRAVITY_M_S2;

/// Standard deviations of additive white noise.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NoiseParams {
    /// Position noise per axis [m].
    pub position_m: f64,
    /// Velocity noise per axis [m/s].
    pub velocity_m_s: f64,
    /// Attitude noise: rotation-vector components per axis [rad].
    pub attitude_rad: f64,
    /// Gyroscope noise per axis [rad/s].
    pub gyro_rad_s: f64,
    /// Accelerometer noise per axis [m/s²].
    pub accel_m_s2: f64,
}

/// What the flight controller's sensors report at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorSample {
    /// Time of the sample [s].
    pub t_s: f64,
    /// Position in world NED [m].
    pub pos_w: Vector3<f64>,
    /// Velocity in world NED [m/s].
    pub vel_w: Vector3<f64>,
    /// Attitude, body FRD to world NED.
    pub q_wb: UnitQuaternion<f64>,
    /// Angular velocity in body FRD [rad/s].
    pub omega_b: Vector3<f64>,
    /// Specific force (accelerometer) in body FRD [m/s²]; reads −g along z at rest.
    pub accel_b: Vector3<f64>,
}

impl NoiseParams {
    /// A sample at time `t_s` [s] of the true `body` accelerating at `accel_w` (world NED
    /// [m/s²]) with this noise added; the accelerometer reads the specific force
    /// R_wbᵀ (a_w − g e_3) in body FRD.
    pub(crate) fn sample(
        &self,
        t_s: f64,
        body: &RigidBodyState,
        accel_w: Vector3<f64>,
        rng: &mut ChaCha8Rng,
    ) -> SensorSample {
        let specific_w = accel_w - Vector3::new(0.0, 0.0, GRAVITY_M_S2);
        let mut s = SensorSample {
            t_s,
            pos_w: body.pos_w,
            vel_w: body.vel_w,
            q_wb: body.q_wb,
            omega_b: body.omega_b,
            accel_b: body.q_wb.inverse_transform_vector(&specific_w),
        };
        if *self == Self::default() {
            return s;
        }
        s.pos_w += gaussian3(rng, self.position_m);
        s.vel_w += gaussian3(rng, self.velocity_m_s);
        s.q_wb = UnitQuaternion::from_scaled_axis(gaussian3(rng, self.attitude_rad)) * s.q_wb;
        s.omega_b += gaussian3(rng, self.gyro_rad_s);
        s.accel_b += gaussian3(rng, self.accel_m_s2);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::super::gauss::gaussian;
    use super::*;
    use rand_chacha::rand_core::SeedableRng;

    #[test]
    fn gaussian_has_unit_variance() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| gaussian(&mut rng)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "var {var}");
    }

    #[test]
    fn zero_noise_is_exact_and_accel_reads_minus_g_at_rest() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let body = RigidBodyState {
            pos_w: Vector3::new(1.0, 2.0, -3.0),
            vel_w: Vector3::zeros(),
            q_wb: UnitQuaternion::identity(),
            omega_b: Vector3::zeros(),
        };
        let s = NoiseParams::default().sample(0.5, &body, Vector3::zeros(), &mut rng);
        assert_eq!(s.pos_w, body.pos_w);
        assert_eq!(s.accel_b, Vector3::new(0.0, 0.0, -GRAVITY_M_S2));
    }
}
