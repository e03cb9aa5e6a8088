//! Prediction: the nominal state integrated at every IMU sample and the increments accumulated
//! for the covariance prediction (docs/navigation_filter.md §2, §4).

use crate::math::{e3, UnitQuat, Vec3, GRAVITY_M_S2};

use super::covariance::Increments;
use super::readings::ImuReading;
use super::state::Nominal;

/// Longest IMU interval integrated [s]; a longer gap is skipped and counted
/// (docs/navigation_filter.md §2).
pub(super) const MAX_IMU_DT_S: f64 = 0.1;

/// One IMU interval of the nominal kinematics, trapezoidal in the rates and the specific force,
/// accumulating the increments (docs/navigation_filter.md §2, eqs. (2.2)–(2.3)); returns the
/// interval's specific force, world NED [m/s²], and its rate about the vertical [rad/s] (the yaw
/// estimator's inputs, docs/navigation_filter.md §18, eq. (18.6)).
pub(super) fn integrate(
    x: &mut Nominal,
    prev: &ImuReading,
    cur: &ImuReading,
    dt: f64,
    inc: &mut Increments,
) -> (Vec3, f64) {
    let r0 = x.q_wb.to_rotation_matrix().into_inner();
    let omega_b = 0.5 * (prev.gyro_b + cur.gyro_b) - x.gyro_bias_b;
    let mut q = x.q_wb * UnitQuat::from_scaled_axis(omega_b * dt);
    q.renormalize_fast();
    let r1 = q.to_rotation_matrix().into_inner();
    let f_w = 0.5 * (r0 * (prev.accel_b - x.accel_bias_b) + r1 * (cur.accel_b - x.accel_bias_b));
    let vel_w = x.vel_w + (f_w + e3() * GRAVITY_M_S2) * dt;
    x.pos_w += 0.5 * (x.vel_w + vel_w) * dt;
    x.vel_w = vel_w;
    x.q_wb = q;
    inc.dt_s += dt;
    inc.dvel_w += f_w * dt;
    inc.rot_dt += 0.5 * (r0 + r1) * dt;
    (f_w, (r1 * omega_b).z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::nav_filter::covariance;
    use crate::nav_filter::state::{ErrorVector, ERR_ATT, ERR_GYRO_BIAS, ERR_POS, ERR_VEL, STATE_DIM};

    fn imu(k: usize) -> ImuReading {
        let t = k as f64 * 1e-3;
        ImuReading {
            t_s: t,
            accel_b: Vec3::new(1.0 + t, -0.5, -9.0 + 3.0 * t),
            gyro_b: Vec3::new(0.3, -0.2 + 5.0 * t, 0.5),
        }
    }

    fn start() -> Nominal {
        Nominal {
            pos_w: Vec3::new(1.0, 2.0, -3.0),
            vel_w: Vec3::new(2.0, -1.0, 0.5),
            q_wb: UnitQuat::from_euler_angles(0.2, -0.3, 1.0),
            accel_bias_b: Vec3::new(0.05, -0.02, 0.1),
            gyro_bias_b: Vec3::new(0.01, 0.0, -0.01),
            baro_offset_m: 0.0,
        }
    }

    fn run(mut x: Nominal) -> (Nominal, Increments) {
        let mut inc = Increments::default();
        for k in 1..=10 {
            integrate(&mut x, &imu(k - 1), &imu(k), 1e-3, &mut inc);
        }
        (x, inc)
    }

    /// x' ⊟ x in the error-state coordinates of docs/navigation_filter.md §1, eq. (1.3).
    fn difference(a: &Nominal, b: &Nominal) -> ErrorVector {
        let mut d = ErrorVector::zeros();
        let th = (a.q_wb * b.q_wb.inverse()).scaled_axis();
        for i in 0..3 {
            d[ERR_POS + i] = a.pos_w[i] - b.pos_w[i];
            d[ERR_VEL + i] = a.vel_w[i] - b.vel_w[i];
            d[ERR_ATT + i] = th[i];
            d[9 + i] = a.accel_bias_b[i] - b.accel_bias_b[i];
            d[ERR_GYRO_BIAS + i] = a.gyro_bias_b[i] - b.gyro_bias_b[i];
        }
        d
    }

    #[test]
    fn transition_matches_finite_differences_of_the_integration() {
        let (x1, inc) = run(start());
        assert!((inc.dt_s - 0.01).abs() < 1e-12);
        let phi = covariance::transition(&inc);
        let eps = 1e-6;
        for j in 0..STATE_DIM - 1 {
            let mut dx = ErrorVector::zeros();
            dx[j] = eps;
            let mut x0 = start();
            x0.inject(&dx);
            let (x1p, _) = run(x0);
            let numeric = difference(&x1p, &x1);
            let predicted = phi * dx;
            let err = (numeric - predicted).norm() / eps;
            assert!(
                err < 2e-4,
                "column {j}: error {err:e}\nnumeric {numeric}\npredicted {predicted}"
            );
        }
    }

    #[test]
    fn level_rest_stays_at_rest() {
        let mut x = Nominal::default();
        let mut inc = Increments::default();
        let still = |k: usize| ImuReading {
            t_s: k as f64 * 1e-3,
            accel_b: Vec3::new(0.0, 0.0, -GRAVITY_M_S2),
            gyro_b: Vec3::zeros(),
        };
        for k in 1..=1000 {
            integrate(&mut x, &still(k - 1), &still(k), 1e-3, &mut inc);
        }
        assert!(x.pos_w.norm() < 1e-12 && x.vel_w.norm() < 1e-12);
    }
}
