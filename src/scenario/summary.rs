//! Statistics of a scenario run, accumulated tick by tick, and the `summary.json` they make.

use serde::Serialize;

use crate::math::Vec3;

/// One tick's values the statistics need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickRecord {
    /// Simulated time [s].
    pub t_s: f64,
    /// Position, world NED [m].
    pub pos_w: Vec3,
    /// Reference position, world NED [m].
    pub ref_w: Vec3,
    /// Velocity error [m/s].
    pub vel_error_w: Vec3,
    /// Attitude error (e_R or e_η) [rad].
    pub att_error: Vec3,
    /// Tilt of the body z axis [rad].
    pub tilt_rad: f64,
    /// Applied collective thrust [N].
    pub thrust_n: f64,
    /// Applied torque [N·m].
    pub torque_b: Vec3,
    /// The allocation saturated.
    pub saturated: bool,
    /// The controller held its last output (fault).
    pub controller_fault: bool,
}

/// Running sums over a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunStats {
    ticks: u64,
    sum_sq_pos: Vec3,
    sum_sq_vel: Vec3,
    sum_sq_att: Vec3,
    max_tilt_rad: f64,
    saturated_ticks: u64,
    fault_ticks: u64,
    last: Option<TickRecord>,
    settled_since_s: Option<f64>,
}

/// Half-width of the band the position error must stay in to count as settled [m]
/// (docs/sweep.md §3, eq. (3.2)).
pub const SETTLE_BAND_M: f64 = 0.05;

/// Final and RMS tracking figures.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TrackingSummary {
    /// Ticks accumulated.
    pub ticks: u64,
    /// Final position, world NED [m].
    pub final_position_m: [f64; 3],
    /// Final reference position [m].
    pub final_reference_m: [f64; 3],
    /// Final position error per axis [m].
    pub final_position_error_m: [f64; 3],
    /// Norm of the final position error [m].
    pub final_position_error_norm_m: f64,
    /// Final attitude error per axis [rad].
    pub final_attitude_error_rad: [f64; 3],
    /// RMS position error per axis [m].
    pub rms_position_error_m: [f64; 3],
    /// RMS velocity error per axis [m/s].
    pub rms_velocity_error_m_s: [f64; 3],
    /// RMS attitude error per axis [rad].
    pub rms_attitude_error_rad: [f64; 3],
    /// Largest tilt [deg].
    pub max_tilt_deg: f64,
    /// Time from which the position error stayed within [`SETTLE_BAND_M`] to the end; `None`
    /// when it ended outside (docs/sweep.md §3, eq. (3.2)) [s].
    pub settling_time_s: Option<f64>,
    /// Time with the allocation saturated [s].
    pub saturated_time_s: f64,
    /// Ticks on which the controller held its last output.
    pub controller_fault_ticks: u64,
    /// Final applied thrust [N].
    pub final_thrust_n: f64,
    /// Final applied torque [N·m].
    pub final_torque_n_m: [f64; 3],
}

impl RunStats {
    /// Adds one tick.
    pub fn add(&mut self, r: &TickRecord) {
        let e = r.pos_w - r.ref_w;
        self.ticks += 1;
        self.sum_sq_pos += e.component_mul(&e);
        self.sum_sq_vel += r.vel_error_w.component_mul(&r.vel_error_w);
        self.sum_sq_att += r.att_error.component_mul(&r.att_error);
        self.max_tilt_rad = self.max_tilt_rad.max(r.tilt_rad);
        self.saturated_ticks += u64::from(r.saturated);
        self.fault_ticks += u64::from(r.controller_fault);
        self.last = Some(*r);
        self.settled_since_s = match self.settled_since_s {
            _ if e.norm() > SETTLE_BAND_M => None,
            None => Some(r.t_s),
            since => since,
        };
    }

    /// Figures over the ticks added so far, with step `dt_s` [s].
    pub fn summary(&self, dt_s: f64) -> TrackingSummary {
        let n = self.ticks.max(1) as f64;
        let rms = |s: &Vec3| (s / n).map(f64::sqrt).into();
        let last = self.last.unwrap_or(TickRecord {
            t_s: 0.0,
            pos_w: Vec3::zeros(),
            ref_w: Vec3::zeros(),
            vel_error_w: Vec3::zeros(),
            att_error: Vec3::zeros(),
            tilt_rad: 0.0,
            thrust_n: 0.0,
            torque_b: Vec3::zeros(),
            saturated: false,
            controller_fault: false,
        });
        let e = last.pos_w - last.ref_w;
        TrackingSummary {
            ticks: self.ticks,
            final_position_m: last.pos_w.into(),
            final_reference_m: last.ref_w.into(),
            final_position_error_m: e.into(),
            final_position_error_norm_m: e.norm(),
            final_attitude_error_rad: last.att_error.into(),
            rms_position_error_m: rms(&self.sum_sq_pos),
            rms_velocity_error_m_s: rms(&self.sum_sq_vel),
            rms_attitude_error_rad: rms(&self.sum_sq_att),
            max_tilt_deg: self.max_tilt_rad.to_degrees(),
            settling_time_s: self.settled_since_s,
            saturated_time_s: self.saturated_ticks as f64 * dt_s,
            controller_fault_ticks: self.fault_ticks,
            final_thrust_n: last.thrust_n,
            final_torque_n_m: last.torque_b.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rms_and_final_values() {
        let mut s = RunStats::default();
        for k in 0..4 {
            s.add(&TickRecord {
                t_s: k as f64,
                pos_w: Vec3::new(if k % 2 == 0 { 1.0 } else { -1.0 }, 0.0, 0.0),
                ref_w: Vec3::zeros(),
                vel_error_w: Vec3::new(0.0, 2.0, 0.0),
                att_error: Vec3::zeros(),
                tilt_rad: 0.1 * k as f64,
                thrust_n: 10.0,
                torque_b: Vec3::zeros(),
                saturated: k == 0,
                controller_fault: false,
            });
        }
        let sum = s.summary(0.5);
        assert_eq!(sum.rms_position_error_m, [1.0, 0.0, 0.0]);
        assert_eq!(sum.rms_velocity_error_m_s, [0.0, 2.0, 0.0]);
        assert_eq!(sum.final_position_error_m, [-1.0, 0.0, 0.0]);
        assert_eq!(sum.saturated_time_s, 0.5);
        assert!((sum.max_tilt_deg - 0.3f64.to_degrees()).abs() < 1e-12);
        assert_eq!(sum.settling_time_s, None, "it ended 1 m off");
    }

    #[test]
    fn the_settling_time_is_when_the_error_last_entered_the_band() {
        let mut s = RunStats::default();
        for (k, x) in [0.5, 0.01, 0.2, 0.04, 0.0, 0.03].into_iter().enumerate() {
            s.add(&TickRecord {
                t_s: k as f64,
                pos_w: Vec3::new(x, 0.0, 0.0),
                ref_w: Vec3::zeros(),
                vel_error_w: Vec3::zeros(),
                att_error: Vec3::zeros(),
                tilt_rad: 0.0,
                thrust_n: 10.0,
                torque_b: Vec3::zeros(),
                saturated: false,
                controller_fault: false,
            });
        }
        assert_eq!(s.summary(1.0).settling_time_s, Some(3.0));
    }
}
