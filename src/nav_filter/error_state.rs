//! The core error-state filter: the nominal state and its covariance, the IMU integration, the
//! covariance prediction, the gated fusion of scalar observations, the state history for delayed
//! measurements and the output lag (docs/navigation_filter.md §1–§5, §7, §16). The aids of the
//! other files decide what to fuse and hand it to this type.

use crate::math::{UnitQuat, Vec3};

use super::covariance::{self, fuse_group, Increments, ProcessNoise, ScalarObservation};
use super::delay_buffer::{DelayBuffer, PastState};
use super::estimate::NavEstimate;
use super::fusion::{Fusion, FusionOutcome};
use super::nav_params::{HeightSource, NavParams};
use super::output::{NavOutput, OutputLag};
use super::predict::{integrate, MAX_IMU_DT_S};
use super::readings::ImuReading;
use super::state::{part, rotate_world, Covariance, ErrorVector, Nominal, ERR_ATT, ERR_POS, ERR_VEL, STATE_DIM};

/// What one integrated IMU interval hands to the aids that follow the IMU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ImuInterval {
    /// The interval's specific force, world NED [m/s²].
    pub f_w: Vec3,
    /// The interval's rate about the vertical [rad/s].
    pub yaw_rate: f64,
    /// The interval [s].
    pub dt_s: f64,
}

/// Nominal state, covariance and what keeps them at the present time.
#[derive(Debug, Clone)]
pub(super) struct ErrorStateFilter {
    /// Nominal state x̂ (docs/navigation_filter.md §1, eq. (1.1)).
    pub x: Nominal,
    /// Error-state covariance P (docs/navigation_filter.md §1, eq. (1.2)).
    pub p: Covariance,
    /// Time of the latest IMU sample [s].
    pub t_s: f64,
    last_imu: Option<ImuReading>,
    /// The latest gyro sample minus the gyro bias [rad/s].
    pub omega_b: Vec3,
    increments: Increments,
    buffer: DelayBuffer,
    /// The corrections not yet blended into the output (docs/navigation_filter.md §16).
    output_lag: OutputLag,
    /// IMU samples not integrated (non-finite, out of order, or after a gap) [-].
    pub imu_dropped: u32,
}

impl ErrorStateFilter {
    /// At rest at the origin with a zero covariance, before any sample; the only allocation is
    /// the state history.
    pub fn new() -> Self {
        Self {
            x: Nominal::default(),
            p: Covariance::zeros(),
            t_s: 0.0,
            last_imu: None,
            omega_b: Vec3::zeros(),
            increments: Increments::default(),
            buffer: DelayBuffer::new(),
            output_lag: OutputLag::default(),
            imu_dropped: 0,
        }
    }

    /// Takes the time of IMU sample `imu`: `None` (counted as dropped) when it is not finite or
    /// not later than the previous one, otherwise the previous sample, if any
    /// (docs/navigation_filter.md §2).
    pub fn accept_imu(&mut self, imu: &ImuReading) -> Option<Option<ImuReading>> {
        if !imu.is_finite() {
            self.imu_dropped = self.imu_dropped.saturating_add(1);
            return None;
        }
        let prev = match self.last_imu {
            Some(prev) if imu.t_s <= prev.t_s => {
                self.imu_dropped = self.imu_dropped.saturating_add(1);
                return None;
            }
            prev => prev,
        };
        self.last_imu = Some(*imu);
        self.t_s = imu.t_s;
        Some(prev)
    }

    /// Integrates the nominal state from `prev` to `imu`, lets the output lag decay over the
    /// interval with time constant `output_tau_s` [s] and records the state in the history;
    /// `None` without a previous sample or after a gap longer than `MAX_IMU_DT_S` (counted)
    /// (docs/navigation_filter.md §2, eqs. (2.2)–(2.3); docs/navigation_filter.md §16, eq. (16.2)).
    pub fn propagate(&mut self, prev: Option<ImuReading>, imu: &ImuReading, output_tau_s: f64) -> Option<ImuInterval> {
        self.omega_b = imu.gyro_b - self.x.gyro_bias_b;
        let prev = prev?;
        let dt = imu.t_s - prev.t_s;
        if dt > MAX_IMU_DT_S {
            self.imu_dropped = self.imu_dropped.saturating_add(1);
            return None;
        }
        let (f_w, yaw_rate) = integrate(&mut self.x, &prev, imu, dt, &mut self.increments);
        self.output_lag.decay(dt, output_tau_s);
        self.buffer.push(PastState {
            t_s: imu.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            q_wb: self.x.q_wb,
        });
        Some(ImuInterval {
            f_w,
            yaw_rate,
            dt_s: dt,
        })
    }

    /// Whether `predict_period_s` [s] of IMU data has accumulated (docs/navigation_filter.md §4).
    pub fn prediction_due(&self, predict_period_s: f64) -> bool {
        self.increments.dt_s >= predict_period_s - 1e-6
    }

    /// Predicts the covariance over the increments accumulated so far (also before every fusion,
    /// so that P belongs to the current time); the barometer offset gets process noise unless
    /// `active_height` is the barometer (docs/navigation_filter.md §4, eqs. (4.1)–(4.3)).
    pub fn flush_covariance(&mut self, params: &NavParams, active_height: HeightSource) {
        if self.increments.dt_s <= 0.0 {
            return;
        }
        let p = params;
        let noise = ProcessNoise {
            accel: p.accel_noise_m_s2,
            gyro: p.gyro_noise_rad_s,
            accel_bias: p.accel_bias_noise_m_s3,
            gyro_bias: p.gyro_bias_noise_rad_s2,
            baro_offset: (active_height != HeightSource::Baro).then_some(p.baro_offset_noise_m_s),
            period_s: p.predict_period_s,
        };
        covariance::predict(&mut self.p, &self.increments, &noise);
        self.increments = Increments::default();
    }

    /// Restarts at nominal state `x` with covariance `p`: the history holds only the present,
    /// nothing is accumulated (docs/navigation_filter.md §11).
    pub fn restart(&mut self, x: Nominal, p: Covariance) {
        self.x = x;
        self.omega_b = Vec3::zeros();
        self.p = p;
        self.buffer.clear();
        self.buffer.push(PastState {
            t_s: self.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            q_wb: self.x.q_wb,
        });
        self.increments = Increments::default();
    }

    /// The nominal p, v, q at `t_s` [s], interpolated in the history; `None` when older than it
    /// (docs/navigation_filter.md §7, eq. (7.2)).
    pub fn past(&self, t_s: f64) -> Option<PastState> {
        self.buffer.at(t_s)
    }

    /// Oldest time a future measurement can refer to: now minus the longest configured delay,
    /// with a margin of two IMU periods [s] (docs/navigation_filter.md §7, eq. (7.3)).
    fn history_start_s(&self, params: &NavParams) -> f64 {
        let p = params;
        self.t_s - p.gps_delay_s.max(p.baro_delay_s).max(p.mag_delay_s) - 0.002
    }

    /// Adds a correction of position `dpos_w` [m], velocity `dvel_w` [m/s] and attitude
    /// `dtheta_w` [rad] to the history entries a future measurement can refer to
    /// (docs/navigation_filter.md §7, eq. (7.3)).
    pub fn correct_history(&mut self, params: &NavParams, dpos_w: &Vec3, dvel_w: &Vec3, dtheta_w: &Vec3) {
        let from_s = self.history_start_s(params);
        self.buffer.correct(from_s, dpos_w, dvel_w, dtheta_w);
    }

    /// Injects an error estimate into the nominal state and the state history
    /// (docs/navigation_filter.md §5, eq. (5.7); docs/navigation_filter.md §7, eq. (7.3)).
    pub fn apply(&mut self, dx: &ErrorVector, params: &NavParams) {
        self.x.inject(dx);
        self.output_lag
            .corrected(&part(dx, ERR_POS), &part(dx, ERR_VEL), &part(dx, ERR_ATT));
        self.buffer.correct(
            self.history_start_s(params),
            &part(dx, ERR_POS),
            &part(dx, ERR_VEL),
            &part(dx, ERR_ATT),
        );
    }

    /// Gates and fuses a group of scalars behind `gate_sd` [SD], applying the correction; also
    /// returns the innovation variances of the first three scalars
    /// (docs/navigation_filter.md §5, eqs. (5.2)–(5.7)).
    pub fn fuse_gated(&mut self, group: &[ScalarObservation], gate_sd: f64, params: &NavParams) -> (Fusion, Vec3) {
        let update = fuse_group(&mut self.p, group, Some(gate_sd));
        let [a, b, c] = update.innovation_variance;
        let outcome = match update.dx {
            Some(dx) => {
                self.apply(&dx, params);
                FusionOutcome::Fused
            }
            None => FusionOutcome::Rejected,
        };
        let fusion = Fusion {
            outcome,
            test_ratio: update.test_ratio,
        };
        (fusion, Vec3::new(a, b, c))
    }

    /// Turns the attitude (and its history) by `dyaw` [rad] about the vertical, the tilt error's
    /// covariance turning with it; the caller sets the yaw's variance and counts the reset
    /// (docs/navigation_filter.md §11, eq. (11.4)).
    pub fn turn_yaw(&mut self, dyaw: f64, params: &NavParams) {
        let dtheta_w = Vec3::new(0.0, 0.0, dyaw);
        self.x.q_wb = rotate_world(&self.x.q_wb, &dtheta_w);
        self.correct_history(params, &Vec3::zeros(), &Vec3::zeros(), &dtheta_w);
        // The tilt error turns with the body: P_θ ← Rz P_θ Rzᵀ in every row and column.
        let rz = UnitQuat::from_scaled_axis(dtheta_w).to_rotation_matrix().into_inner();
        let mut g = Covariance::identity();
        g.fixed_view_mut::<3, 3>(ERR_ATT, ERR_ATT).copy_from(&rz);
        self.p = g * self.p * g.transpose();
    }

    /// Yaw row of P after setting the yaw from a heading with Jacobian `h` and noise
    /// `heading_noise_rad` [rad]: the yaw error is the tilt error seen through the field's
    /// inclination plus the heading noise, `δθ_z = −h_xy·δθ_xy + n`
    /// (docs/navigation_filter.md §11, eq. (11.4)).
    pub fn yaw_covariance_from_heading(&mut self, h: &Vec3, heading_noise_rad: f64) {
        let (gx, gy) = (-h.x, -h.y);
        let z = ERR_ATT + 2;
        let tilt_var = gx * gx * self.p[(ERR_ATT, ERR_ATT)]
            + 2.0 * gx * gy * self.p[(ERR_ATT, ERR_ATT + 1)]
            + gy * gy * self.p[(ERR_ATT + 1, ERR_ATT + 1)];
        for j in 0..STATE_DIM {
            if j != z {
                let c = gx * self.p[(ERR_ATT, j)] + gy * self.p[(ERR_ATT + 1, j)];
                self.p[(z, j)] = c;
                self.p[(j, z)] = c;
            }
        }
        self.p[(z, z)] = tilt_var + heading_noise_rad.powi(2);
    }

    /// The nominal state with the standard deviations of position, velocity and attitude
    /// (docs/navigation_filter.md §1, eqs. (1.1)–(1.2)).
    pub fn estimate(&self) -> NavEstimate {
        let std = |i: usize| Vec3::new(self.p[(i, i)], self.p[(i + 1, i + 1)], self.p[(i + 2, i + 2)]).map(f64::sqrt);
        NavEstimate {
            t_s: self.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            q_wb: self.x.q_wb,
            omega_b: self.omega_b,
            accel_bias_b: self.x.accel_bias_b,
            gyro_bias_b: self.x.gyro_bias_b,
            baro_offset_m: self.x.baro_offset_m,
            pos_std_w: std(ERR_POS),
            vel_std_w: std(ERR_VEL),
            att_std_w: std(ERR_ATT),
        }
    }

    /// The nominal state with the corrections blended in over `output_tau_s`
    /// (docs/navigation_filter.md §16, eqs. (16.1)–(16.2)).
    pub fn output(&self) -> NavOutput {
        let (pos_w, vel_w, q_wb) = self.output_lag.apply(&self.x);
        NavOutput {
            t_s: self.t_s,
            pos_w,
            vel_w,
            q_wb,
            omega_b: self.omega_b,
        }
    }
}

#[cfg(test)]
#[path = "error_state_tests.rs"]
mod tests;
