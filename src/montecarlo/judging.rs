//! How a Monte Carlo run is judged: the convergence [`Criterion`] (tolerances on the position
//! and geodesic attitude errors over a final window, see `trial.rs`) and the [`Heading`] of the
//! hover setpoint. Pure.

use crate::math::{euler_zyx, wrap_pi};

use super::envelope::Draw;

/// When a run counts as converged (`trial.rs` module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Criterion {
    /// Largest position error over the window [m].
    pub position_m: f64,
    /// Largest geodesic attitude error from the equilibrium attitude over the window [rad].
    pub attitude_rad: f64,
    /// Length of the final window [s].
    pub window_s: f64,
}

impl Default for Criterion {
    /// 0.1 m and 5° over the last second.
    fn default() -> Self {
        Self {
            position_m: 0.1,
            attitude_rad: 5f64.to_radians(),
            window_s: 1.0,
        }
    }
}

/// The heading of the hover setpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Heading {
    /// ψ_sp = 0 (north): the vehicle recovers and turns by up to 180°.
    #[default]
    Zero,
    /// ψ_sp = the initial ZYX yaw: recovery without a heading change.
    Initial,
}

impl Heading {
    /// ψ_sp for a run starting from `draw` [rad].
    pub fn setpoint_yaw_rad(self, draw: &Draw) -> f64 {
        match self {
            Self::Zero => 0.0,
            Self::Initial => euler_zyx(&draw.q_wb.to_rotation_matrix().into_inner()).z,
        }
    }

    /// |ψ_0 − ψ_sp| wrapped to [0, π]: the heading change the run asks for [rad].
    pub fn heading_error_rad(self, draw: &Draw) -> f64 {
        let yaw0 = euler_zyx(&draw.q_wb.to_rotation_matrix().into_inner()).z;
        wrap_pi(yaw0 - self.setpoint_yaw_rad(draw)).abs()
    }
}

impl std::str::FromStr for Heading {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "zero" => Ok(Self::Zero),
            "initial" => Ok(Self::Initial),
            _ => Err(format!("unknown heading {s:?}; expected zero or initial")),
        }
    }
}
