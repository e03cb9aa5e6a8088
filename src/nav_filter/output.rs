//! The output the controllers fly on: the nominal state with the filter's corrections blended in
//! over a time constant instead of as steps, as PX4's output predictor does (`EKF2_TAU_VEL`,
//! `EKF2_TAU_POS`) (docs/navigation_filter.md §16, eqs. (16.1)–(16.2)). A GPS fix that moves
//! the estimate by 10 cm then moves the output by 10 cm over about `τ`, not in one tick, so the
//! position controller does not kick the attitude at every fix.

use crate::math::{UnitQuat, Vec3};

use super::state::Nominal;

/// What the output still lags behind the nominal state: the corrections not yet blended in,
/// o = x̂_out − x̂ (docs/navigation_filter.md §16, eq. (16.1)).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct OutputLag {
    pos_w: Vec3,
    vel_w: Vec3,
    /// Rotation from the nominal to the output attitude, world frame [rad].
    att_w: Vec3,
}

/// The smoothed navigation solution (docs/navigation_filter.md §16).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavOutput {
    /// Time of the latest IMU sample [s].
    pub t_s: f64,
    /// Position, local NED relative to the filter's origin [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
    /// Angular velocity, body FRD: the latest gyro sample minus the gyro bias [rad/s].
    pub omega_b: Vec3,
}

impl OutputLag {
    /// A correction `δp`, `δv`, `δθ` was injected into the nominal state: the output keeps
    /// where it was (docs/navigation_filter.md §16, eq. (16.1)).
    pub fn corrected(&mut self, dpos_w: &Vec3, dvel_w: &Vec3, datt_w: &Vec3) {
        self.pos_w -= dpos_w;
        self.vel_w -= dvel_w;
        self.att_w -= datt_w;
    }

    /// One IMU interval `dt_s` [s]: the lag decays as e^{−dt/τ}
    /// (docs/navigation_filter.md §16, eq. (16.2)).
    pub fn decay(&mut self, dt_s: f64, tau_s: f64) {
        let k = (-dt_s / tau_s).exp();
        self.pos_w *= k;
        self.vel_w *= k;
        self.att_w *= k;
    }

    /// The output of nominal state `x`: x̂ ⊞ o.
    pub fn apply(&self, x: &Nominal) -> (Vec3, Vec3, UnitQuat) {
        let q = UnitQuat::from_scaled_axis(self.att_w) * x.q_wb;
        (x.pos_w + self.pos_w, x.vel_w + self.vel_w, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_correction_is_blended_in_over_the_time_constant() {
        let x = Nominal {
            pos_w: Vec3::new(1.0, 0.0, 0.0),
            ..Nominal::default()
        };
        let mut lag = OutputLag::default();
        lag.corrected(&Vec3::new(0.1, 0.0, 0.0), &Vec3::zeros(), &Vec3::zeros());
        let (p, _, _) = lag.apply(&x);
        assert!((p.x - 0.9).abs() < 1e-12, "the output has not moved yet");
        for _ in 0..250 {
            lag.decay(1e-3, 0.25);
        }
        let (p, _, _) = lag.apply(&x);
        assert!(
            (p.x - (1.0 - 0.1 * (-1f64).exp())).abs() < 1e-9,
            "1 − e^{{−1}} of it after τ: {p}"
        );
        for _ in 0..5_000 {
            lag.decay(1e-3, 0.25);
        }
        assert!((lag.apply(&x).0.x - 1.0).abs() < 1e-9);
    }
}
