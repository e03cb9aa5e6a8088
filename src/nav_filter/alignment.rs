//! Alignment at rest: roll and pitch from the averaged specific force, yaw from the averaged
//! magnetic field, the gyro bias from the averaged rate, the barometric altitude of the origin,
//! and the initial covariance (docs/navigation_filter.md §11, eqs. (11.1)–(11.5)).

use crate::math::{Mat3, UnitQuat, Vec3, GRAVITY_M_S2};

use super::delay_buffer::PastState;
use super::fuse_mag::{heading_jacobian, tan_inclination};
use super::params::{HeightSource, NavParams};
use super::readings::ImuReading;
use super::state::{Covariance, Nominal, ERR_ACCEL_BIAS, ERR_ATT, ERR_BARO_OFFSET, ERR_GYRO_BIAS, ERR_POS, ERR_VEL};
use super::NavFilter;

/// Largest | ‖f‖ − g | of a sample counted as "at rest" [m/s²] (docs/navigation_filter.md §11).
const REST_ACCEL_TOL_M_S2: f64 = 1.0;
/// Largest ‖ω‖ of a sample counted as "at rest" [rad/s] (docs/navigation_filter.md §11).
const REST_GYRO_TOL_RAD_S: f64 = 0.25;
/// Smallest horizontal share of the magnetic field that gives a heading [-].
pub(super) const MIN_HORIZONTAL_FIELD_SHARE: f64 = 0.05;

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

impl NavFilter {
    /// Ends the alignment: attitude from the window's means, gyro bias from the mean rate, the
    /// accelerometer bias along gravity from the mean specific force's magnitude, state at the
    /// origin and at rest, initial covariance, barometric altitude of the origin
    /// (docs/navigation_filter.md §11, eqs. (11.1)–(11.3), (11.6)).
    pub(super) fn finish_alignment(&mut self) {
        let (roll, pitch) = tilt_from_accel(&self.aligner.mean_accel_b());
        let decl = self.params.mag_declination_rad;
        let mean_mag = self.aligner.mean_mag_b();
        let yaw = mean_mag.and_then(|m| yaw_from_mag(roll, pitch, &m, decl));
        let q_wb = UnitQuat::from_euler_angles(roll, pitch, yaw.unwrap_or(0.0));
        self.x = Nominal {
            q_wb,
            gyro_bias_b: self.aligner.mean_gyro_b(),
            accel_bias_b: vertical_accel_bias(&self.aligner.mean_accel_b()),
            ..Nominal::default()
        };
        self.omega_b = Vec3::zeros();
        self.yaw_aligned = yaw.is_some();
        self.p = initial_covariance(&self.params, self.height.active, &q_wb, self.aligner.window_s());
        self.mag_tan_inclination = yaw.and(mean_mag).and_then(|m| tan_inclination(&q_wb, &m));
        if let Some(tan_incl) = self.mag_tan_inclination {
            self.yaw_covariance_from_heading(&heading_jacobian(decl, tan_incl));
        }
        self.baro_origin_m = self.aligner.mean_baro_m();
        self.buffer.clear();
        self.buffer.push(PastState {
            t_s: self.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            q_wb: self.x.q_wb,
        });
        self.increments = Default::default();
        self.aligned = true;
        self.height.active_since_s = self.t_s;
    }

    /// Starts the filter aligned at a known state instead of aligning at rest: position `pos_w`
    /// [m] and velocity `vel_w` [m/s] in the GPS readings' NED frame, attitude `q_wb`, at
    /// `t_s` [s], biases unknown (zero, with their initial uncertainty) — a vehicle whose filter
    /// converged before a headless run starts it in the air (docs/navigation_filter.md §11).
    /// The first barometer sample then sets the origin's barometric altitude, as after an
    /// alignment, and the GPS fixes are fused from the first one (the known state counts as
    /// aided at `t_s`).
    pub fn align_at(&mut self, t_s: f64, pos_w: Vec3, vel_w: Vec3, q_wb: UnitQuat) {
        self.t_s = t_s;
        self.x = Nominal {
            pos_w,
            vel_w,
            q_wb,
            ..Nominal::default()
        };
        self.omega_b = Vec3::zeros();
        self.p = initial_covariance(&self.params, self.height.active, &q_wb, 1.0);
        self.yaw_aligned = true;
        self.mag_tan_inclination = None;
        self.origin_w = Some(Vec3::zeros());
        self.baro_origin_m = None;
        // The known state counts as an aiding: the first fixes are fused into it, not reset to.
        self.aiding.last_aiding_s = Some(t_s);
        self.aiding.last_pos_s = Some(t_s);
        self.aiding.last_vel_s = Some(t_s);
        self.height.mark_fused(self.height.active, t_s);
        self.buffer.clear();
        self.buffer.push(PastState {
            t_s,
            pos_w,
            vel_w,
            q_wb,
        });
        self.increments = Default::default();
        self.aligned = true;
        self.height.active_since_s = t_s;
    }

    /// Yaw row of P after setting the yaw from a heading with Jacobian `h`: the yaw error is the
    /// tilt error seen through the field's inclination plus the heading noise,
    /// `δθ_z = −h_xy·δθ_xy + n` (docs/navigation_filter.md §11, eq. (11.4)).
    fn yaw_covariance_from_heading(&mut self, h: &Vec3) {
        let (gx, gy) = (-h.x, -h.y);
        let z = ERR_ATT + 2;
        let tilt_var = gx * gx * self.p[(ERR_ATT, ERR_ATT)]
            + 2.0 * gx * gy * self.p[(ERR_ATT, ERR_ATT + 1)]
            + gy * gy * self.p[(ERR_ATT + 1, ERR_ATT + 1)];
        for j in 0..super::state::STATE_DIM {
            if j != z {
                let c = gx * self.p[(ERR_ATT, j)] + gy * self.p[(ERR_ATT + 1, j)];
                self.p[(z, j)] = c;
                self.p[(j, z)] = c;
            }
        }
        self.p[(z, z)] = tilt_var + self.params.heading_noise_rad.powi(2);
    }

    /// Sets the yaw from one magnetometer sample, keeping roll and pitch; the attitude rows of P
    /// turn with the yaw change and the yaw row restarts as at alignment
    /// (docs/navigation_filter.md §11, eqs. (11.4)–(11.5)). False when the field gives no
    /// heading.
    pub(super) fn reset_yaw_to_mag(&mut self, field_b: &Vec3) -> bool {
        let (roll, pitch, yaw) = self.x.q_wb.euler_angles();
        let Some(new_yaw) = yaw_from_mag(roll, pitch, field_b, self.params.mag_declination_rad) else {
            return false;
        };
        let Some(tan_incl) = self
            .mag_tan_inclination
            .or_else(|| tan_inclination(&self.x.q_wb, field_b))
        else {
            return false;
        };
        self.turn_yaw(crate::math::wrap_pi(new_yaw - yaw));
        self.mag_tan_inclination = Some(tan_incl);
        self.yaw_covariance_from_heading(&heading_jacobian(self.params.mag_declination_rad, tan_incl));
        self.yaw_aligned = true;
        true
    }

    /// Turns the attitude (and its history) by `dyaw` [rad] about the vertical, the tilt error's
    /// covariance turning with it, and counts a yaw reset; the caller sets the yaw's variance
    /// (docs/navigation_filter.md §11, eq. (11.4)).
    pub(super) fn turn_yaw(&mut self, dyaw: f64) {
        let dtheta_w = Vec3::new(0.0, 0.0, dyaw);
        self.x.q_wb = super::state::rotate_world(&self.x.q_wb, &dtheta_w);
        self.buffer
            .correct(self.history_start_s(), &Vec3::zeros(), &Vec3::zeros(), &dtheta_w);
        // The tilt error turns with the body: P_θ ← Rz P_θ Rzᵀ in every row and column.
        let rz = UnitQuat::from_scaled_axis(dtheta_w).to_rotation_matrix().into_inner();
        let mut g = Covariance::identity();
        g.fixed_view_mut::<3, 3>(ERR_ATT, ERR_ATT).copy_from(&rz);
        self.p = g * self.p * g.transpose();
        self.resets.yaw = self.resets.yaw.saturating_add(1);
    }
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
}
