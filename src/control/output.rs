//! What every controller returns: the body wrench, the attitude it aimed for, its tracking
//! errors and the guards that acted.

use crate::allocation::Wrench;
use crate::math::{Mat3, Vec3};

/// Guards and faults of one controller update (docs/control.md §8).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ControlFlags {
    /// An input (state, setpoint or estimate) or the computed output was not finite; the
    /// controller returned its last good output instead.
    pub non_finite: bool,
    /// Commanded thrust was clamped to `[0, u_T,max]`.
    pub thrust_clamped: bool,
    /// The horizontal acceleration demand was scaled down to respect the tilt limit.
    pub tilt_limited: bool,
    /// The vertical demand asked for less than `g − ε_z` of downward thrust (RPY laws) or
    /// `‖A‖ ≤ ε_A` (geometric); the previous thrust direction was kept.
    pub thrust_direction_held: bool,
    /// `|cos θ|` fell below the RPY singularity guard; the last good output was held.
    pub rpy_singular: bool,
    /// Geometric law: `Ψ = ½ tr(I − R_dᵀ R) ≥ 1` (attitude error beyond 90°), outside the
    /// exponential-stability region of Lee et al.
    pub large_attitude_error: bool,
}

impl ControlFlags {
    /// True when the output is not what the law computed this tick.
    pub fn is_fault(&self) -> bool {
        self.non_finite || self.rpy_singular
    }
}

/// Tracking errors, "current minus desired" (docs/model.md §1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrackingErrors {
    /// e_p, world NED [m] (zero when no position is commanded).
    pub pos_w: Vec3,
    /// ė_p, world NED [m/s].
    pub vel_w: Vec3,
    /// Attitude error: e_R (geometric, body) or e_η (RPY laws) [rad].
    pub attitude: Vec3,
    /// Rate error: e_ω (geometric, body) [rad/s] or ė_η (RPY laws) [rad/s].
    pub rate: Vec3,
}

/// Output of one controller update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlOutput {
    /// Requested collective thrust [N] and body torque FRD [N·m].
    pub wrench: Wrench,
    /// Desired attitude `R_{b,d}` (body → world).
    pub r_wb_desired: Mat3,
    /// Desired roll, pitch, yaw (ZYX) [rad].
    pub eta_desired: Vec3,
    /// Tracking errors.
    pub errors: TrackingErrors,
    /// Guards and faults.
    pub flags: ControlFlags,
}

impl ControlOutput {
    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        self.wrench.thrust_n.is_finite()
            && self.wrench.torque_b.iter().all(|x| x.is_finite())
            && self.r_wb_desired.iter().all(|x| x.is_finite())
    }
}
