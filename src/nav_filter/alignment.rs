//! The alignment's maths: roll and pitch from the averaged specific force, yaw from the averaged
//! magnetic field, the accelerometer bias along gravity, and the initial covariance
//! (docs/navigation_filter.md §11, eqs. (11.1)–(11.6)). The window and its end are in
//! `aligner`.

use crate::math::{Mat3, UnitQuat, Vec3, GRAVITY_M_S2};

use super::nav_params::{HeightSource, NavParams};
use super::state::{Covariance, ERR_ACCEL_BIAS, ERR_ATT, ERR_BARO_OFFSET, ERR_GYRO_BIAS, ERR_POS, ERR_VEL};

/// Smallest horizontal share of the magnetic field that gives a heading [-].
pub(super) const MIN_HORIZONTAL_FIELD_SHARE: f64 = 0.05;

/// Roll and pitch [rad] of a vehicle at rest reading specific force `f_b` [m/s²]
/// (docs/navigation_filter.md §11, eq. (11.1)).
pub(super) fn tilt_from_accel(f_b: &Vec3) -> (f64, f64) {
    let roll = (-f_b.y).atan2(-f_b.z);
    let pitch = f_b.x.atan2((f_b.y * f_b.y + f_b.z * f_b.z).sqrt());
    (roll, pitch)
}

/// Yaw [rad] that points the horizontal part of `field_b` [gauss] at the declination
/// `declination_rad` [rad], given roll and pitch [rad] (docs/navigation_filter.md §11, eq. (11.2));
/// `None` when the field is (nearly) vertical.
pub(super) fn yaw_from_mag(roll: f64, pitch: f64, field_b: &Vec3, declination_rad: f64) -> Option<f64> {
    let m_level = UnitQuat::from_euler_angles(roll, pitch, 0.0) * field_b;
    let horizontal = m_level.x.hypot(m_level.y);
    (horizontal > MIN_HORIZONTAL_FIELD_SHARE * field_b.norm() && horizontal > 0.0)
        .then(|| crate::math::wrap_pi(declination_rad - m_level.y.atan2(m_level.x)))
}

/// Gyroscope bias uncertainty left after averaging at rest, for what the average cannot see (earth
/// rate, slow motion during the window) (1σ) [rad/s] (docs/navigation_filter.md §11, eq. (11.3)).
const ALIGN_GYRO_BIAS_FLOOR_RAD_S: f64 = 0.002;
/// Tilt uncertainty beyond the accelerometer bias and noise (vibration, slight motion) (1σ)
/// [rad] (docs/navigation_filter.md §11, eq. (11.3)).
const ALIGN_TILT_FLOOR_RAD: f64 = 1e-3;
/// Uncertainty of the accelerometer bias along gravity left after the alignment, beyond the
/// averaged noise: local gravity's departure from the standard value, vibration (1σ) [m/s²]
/// (docs/navigation_filter.md §11, eq. (11.6)).
const ALIGN_VERTICAL_BIAS_FLOOR_M_S2: f64 = 0.01;

/// The accelerometer bias along gravity that the mean specific force `f_b` [m/s²] of a vehicle
/// at rest shows: its magnitude departs from g only by the bias component along the vertical,
/// `b = (g − ‖f̄‖) d`, `d = −f̄/‖f̄‖` the body's down (docs/navigation_filter.md §11, eq. (11.6)).
/// The horizontal components tilt the estimate instead and stay unknown.
pub(super) fn vertical_accel_bias(f_b: &Vec3) -> Vec3 {
    let norm = f_b.norm();
    if norm > 0.0 {
        -f_b / norm * (GRAVITY_M_S2 - norm)
    } else {
        Vec3::zeros()
    }
}

/// Initial covariance after an alignment of `window_s` [s] at attitude `q_wb`: the tilt error is
/// the accelerometer bias seen through gravity, so the two are fully correlated; the gyro bias
/// is known to the precision of its average; yaw gets the heading noise (the caller adds what a
/// tilt error does to the heading) (docs/navigation_filter.md §11, eq. (11.3)).
pub(super) fn initial_covariance(
    p: &NavParams,
    active_height: HeightSource,
    q_wb: &UnitQuat,
    window_s: f64,
) -> Covariance {
    let mut cov = Covariance::zeros();
    let pos = p.gps_pos_noise_m * p.gps_pos_noise_m;
    let height = match active_height {
        HeightSource::Gps => (1.5 * p.gps_pos_noise_m).powi(2),
        HeightSource::Baro => p.baro_noise_m * p.baro_noise_m,
    };
    let vel = p.gps_vel_noise_m_s * p.gps_vel_noise_m_s;
    let averaged = p.predict_period_s / window_s.max(p.predict_period_s);
    let gyro_bias = (p.gyro_noise_rad_s.powi(2) * averaged + ALIGN_GYRO_BIAS_FLOOR_RAD_S.powi(2))
        .min(p.gyro_bias_init_rad_s.powi(2));
    let tilt_noise = p.accel_noise_m_s2.powi(2) * averaged / GRAVITY_M_S2.powi(2) + ALIGN_TILT_FLOOR_RAD.powi(2);
    let vertical_bias = (p.accel_noise_m_s2.powi(2) * averaged + ALIGN_VERTICAL_BIAS_FLOOR_M_S2.powi(2))
        .min(p.accel_bias_init_m_s2.powi(2));
    let diagonal = [
        (ERR_POS, [pos, pos, height]),
        (ERR_VEL, [vel, vel, 2.25 * vel]),
        (ERR_ATT, [tilt_noise, tilt_noise, p.heading_noise_rad.powi(2)]),
        (ERR_GYRO_BIAS, [gyro_bias; 3]),
    ];
    for (start, values) in diagonal {
        for (i, v) in values.iter().enumerate() {
            cov[(start + i, start + i)] = *v;
        }
    }
    // δθ_tilt = M δb_a, M = [row E of R; −row N of R; 0] / g (docs/navigation_filter.md §11, eq. (11.3)).
    let r = q_wb.to_rotation_matrix().into_inner();
    let mut m = Mat3::zeros();
    m.set_row(0, &(r.row(1) / GRAVITY_M_S2));
    m.set_row(1, &(-r.row(0) / GRAVITY_M_S2));
    let var_ba = p.accel_bias_init_m_s2.powi(2);
    // P_ba = var_ba (I − d dᵀ) + var_v d dᵀ: the bias along the body's down d was measured
    // (docs/navigation_filter.md §11, eq. (11.6)); M d = 0, so the tilt rows see only the horizontal part.
    let d = r.row(2).transpose();
    let p_ba = var_ba * (Mat3::identity() - d * d.transpose()) + vertical_bias * d * d.transpose();
    let tilt_from_bias = m * p_ba * m.transpose();
    let cross = m * p_ba;
    for i in 0..3 {
        for j in 0..3 {
            cov[(ERR_ATT + i, ERR_ATT + j)] += tilt_from_bias[(i, j)];
            cov[(ERR_ATT + i, ERR_ACCEL_BIAS + j)] = cross[(i, j)];
            cov[(ERR_ACCEL_BIAS + j, ERR_ATT + i)] = cross[(i, j)];
            cov[(ERR_ACCEL_BIAS + i, ERR_ACCEL_BIAS + j)] = p_ba[(i, j)];
        }
    }
    if active_height == HeightSource::Gps {
        cov[(ERR_BARO_OFFSET, ERR_BARO_OFFSET)] = p.baro_noise_m * p.baro_noise_m;
    }
    cov
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilt_and_yaw_recover_a_known_attitude() {
        let (roll, pitch, yaw) = (0.2, -0.15, 2.0);
        let q = UnitQuat::from_euler_angles(roll, pitch, yaw);
        let f_b = q.inverse() * Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
        let (r, p) = tilt_from_accel(&f_b);
        assert!((r - roll).abs() < 1e-12 && (p - pitch).abs() < 1e-12);
        let decl: f64 = 0.05;
        let field_w = Vec3::new(0.2 * decl.cos(), 0.2 * decl.sin(), 0.45);
        let m_b = q.inverse() * field_w;
        assert!((yaw_from_mag(r, p, &m_b, decl).unwrap() - yaw).abs() < 1e-12);
        assert!(yaw_from_mag(0.0, 0.0, &Vec3::new(0.0, 0.0, 0.5), decl).is_none());
    }

    #[test]
    fn initial_tilt_error_is_the_accelerometer_bias_seen_through_gravity() {
        let p = NavParams::default();
        let q = UnitQuat::from_euler_angles(0.05, -0.1, 2.0);
        let cov = initial_covariance(&p, HeightSource::Gps, &q, 1.0);
        assert!(cov.symmetric_eigenvalues().min() > -1e-15);
        // A bias δb makes the alignment tilt by δθ with δθ × e3 = −R δb / g: check with a pitch.
        let db = Vec3::new(0.1, -0.05, 0.02);
        let f_true = q.inverse() * Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
        let (roll, pitch) = tilt_from_accel(&(f_true + db));
        let q_est = UnitQuat::from_euler_angles(roll, pitch, 2.0);
        let dtheta = (q * q_est.inverse()).scaled_axis();
        let r = q_est.to_rotation_matrix().into_inner();
        let predicted = Vec3::new(r.row(1).dot(&db.transpose()), -r.row(0).dot(&db.transpose()), 0.0) / GRAVITY_M_S2;
        assert!((dtheta.xy() - predicted.xy()).norm() < 1e-4, "{dtheta} vs {predicted}");
        // P_θ,ba = M P_ba with the same M (the tilt is that bias seen through gravity).
        let r = q.to_rotation_matrix().into_inner();
        let var_ba = p.accel_bias_init_m_s2.powi(2);
        for j in 0..3 {
            assert!((cov[(ERR_ATT, ERR_ACCEL_BIAS + j)] - r[(1, j)] / GRAVITY_M_S2 * var_ba).abs() < 1e-15);
            assert!((cov[(ERR_ATT + 1, ERR_ACCEL_BIAS + j)] + r[(0, j)] / GRAVITY_M_S2 * var_ba).abs() < 1e-15);
            assert_eq!(cov[(ERR_ATT + 2, ERR_ACCEL_BIAS + j)], 0.0);
        }
        assert!((cov[(ERR_ATT, ERR_ATT)].sqrt() - 0.2 / GRAVITY_M_S2).abs() < 2e-3);
    }

    #[test]
    fn the_bias_along_gravity_is_read_from_the_specific_forces_magnitude() {
        let q = UnitQuat::from_euler_angles(0.1, -0.05, 1.0);
        let f_true = q.inverse() * Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
        let bias = Vec3::new(0.15, -0.1, 0.2);
        let f = f_true + bias;
        let b = vertical_accel_bias(&f);
        let down = q.inverse() * Vec3::z();
        // The part along the body's down is recovered (to second order in the bias), along the
        // measured down; what is left is horizontal.
        assert!((b.dot(&down) - bias.dot(&down)).abs() < 5e-3, "{b} vs {bias}");
        assert!(b.cross(&f).norm() < 1e-12);
        let p = NavParams::default();
        let cov = initial_covariance(&p, HeightSource::Gps, &q, 1.0);
        assert!(cov.symmetric_eigenvalues().min() > -1e-15);
        let p_ba = cov.fixed_view::<3, 3>(ERR_ACCEL_BIAS, ERR_ACCEL_BIAS);
        assert!(
            (down.transpose() * p_ba * down)[(0, 0)].sqrt() < 0.05,
            "measured along gravity"
        );
    }
}
