//! How a Monte Carlo run is judged: the convergence [`Criterion`], the [`Heading`] of the hover
//! setpoint, and the [`Judge`] that watches every tick of a run. Pure.
//!
//! The criterion compares the true state with the equilibrium of the true vehicle under the
//! drawn force f_e:
//!
//! ```text
//! e_p  = ‖p − 0‖                                    position error [m]
//! b3*  = (m g e3 + f_e) / ‖m g e3 + f_e‖            thrust axis that balances weight and f_e
//! b2*  = b3* × b1d / ‖·‖,  b1* = b2* × b3*          b1d = (cos ψ_sp, sin ψ_sp, 0) (Lee et al.)
//! e_R  = arccos((tr(R*ᵀ R) − 1) / 2)                 geodesic attitude error [rad]
//! ```
//!
//! A run *converges* when it completes, no value was ever non-finite, the controller never set
//! a fault flag ([`ControlFlags::is_fault`](crate::control::ControlFlags::is_fault)), and
//! `e_p < position_m` and `e_R < attitude_rad` at every tick of the last `window_s`. Its
//! convergence time is the start of the final stretch inside the tolerances.

use crate::lockstep::{Exit, Observer, Tick};
use crate::math::{e3, euler_zyx, wrap_pi, Mat3, Vec3, GRAVITY_M_S2};
use crate::sitl::{PlantTruth, SimPlant};

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

/// The result of one run that did not panic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialOutcome {
    /// How it ended.
    pub end: Exit,
    /// Met the criterion (module docs).
    pub converged: bool,
    /// Start of the final stretch inside the tolerances, when converged [s].
    pub convergence_time_s: Option<f64>,
    /// Position error at the end [m].
    pub final_position_error_m: f64,
    /// Geodesic attitude error from the equilibrium at the end [rad].
    pub final_attitude_error_rad: f64,
    /// Largest tilt of body z from the vertical [rad].
    pub max_tilt_rad: f64,
    /// Some state, controller output, rotor command or estimate was not finite.
    pub non_finite: bool,
    /// Ticks on which the controller set a fault flag.
    pub fault_ticks: u64,
    /// Ticks on which the allocation saturated.
    pub saturated_ticks: u64,
    /// Ticks flown.
    pub ticks: u64,
}

/// The equilibrium attitude R* of a vehicle of mass `mass_kg` [kg] under force `force_w`
/// [N, world NED] at heading `yaw_rad` [rad] (module docs). Falls back to level when
/// m g e3 + f_e vanishes.
pub fn equilibrium_attitude(mass_kg: f64, force_w: &Vec3, yaw_rad: f64) -> Mat3 {
    let b3 = (mass_kg * GRAVITY_M_S2 * e3() + force_w)
        .try_normalize(1e-9)
        .unwrap_or_else(e3);
    let b1d = Vec3::new(yaw_rad.cos(), yaw_rad.sin(), 0.0);
    let b2 = b3
        .cross(&b1d)
        .try_normalize(1e-9)
        .unwrap_or_else(|| Vec3::new(-yaw_rad.sin(), yaw_rad.cos(), 0.0));
    let b1 = b2.cross(&b3);
    Mat3::from_columns(&[b1, b2, b3])
}

/// Geodesic angle between two rotations, `arccos((tr(Aᵀ B) − 1)/2)` [rad].
pub fn rotation_angle(a: &Mat3, b: &Mat3) -> f64 {
    (((a.transpose() * b).trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
}

/// Watches a run tick by tick against the criterion (module docs).
///
/// Samples are numbered by the tick they follow: sample 0 is the initial state, sample k+1 the
/// state after tick k. `settled_from` is the first sample of the current in-tolerance stretch.
#[derive(Debug, Clone)]
pub struct Judge {
    criterion: Criterion,
    r_eq: Mat3,
    settled_from: Option<u64>,
    final_position_m: f64,
    final_attitude_rad: f64,
    max_tilt_rad: f64,
    non_finite: bool,
    fault_ticks: u64,
    saturated_ticks: u64,
    flown: u64,
}

impl Judge {
    /// A judge of `criterion` around the equilibrium attitude `r_eq`, starting from `initial`.
    pub fn new(criterion: Criterion, r_eq: Mat3, initial: &PlantTruth) -> Self {
        let mut judge = Self {
            criterion,
            r_eq,
            settled_from: None,
            final_position_m: 0.0,
            final_attitude_rad: 0.0,
            max_tilt_rad: 0.0,
            non_finite: false,
            fault_ticks: 0,
            saturated_ticks: 0,
            flown: 0,
        };
        let (e_p, e_r, tilt) = judge.errors(initial);
        judge.settled_from = judge.inside(e_p, e_r).then_some(0);
        (judge.final_position_m, judge.final_attitude_rad, judge.max_tilt_rad) = (e_p, e_r, tilt);
        judge
    }

    /// Position error [m], geodesic attitude error [rad] and tilt [rad] of `truth`.
    fn errors(&self, truth: &PlantTruth) -> (f64, f64, f64) {
        let r = truth.q_wb.to_rotation_matrix().into_inner();
        (
            truth.pos_w.norm(),
            rotation_angle(&self.r_eq, &r),
            r[(2, 2)].clamp(-1.0, 1.0).acos(),
        )
    }

    fn inside(&self, e_p: f64, e_r: f64) -> bool {
        e_p < self.criterion.position_m && e_r < self.criterion.attitude_rad
    }

    /// The verdict on a run that ended with `end`, converged only when it stayed inside the
    /// tolerances for the last `window_ticks` ticks of step `dt_s` [s].
    pub fn outcome(&self, end: Exit, window_ticks: u64, dt_s: f64) -> TrialOutcome {
        let converged = end == Exit::Complete
            && !self.non_finite
            && self.fault_ticks == 0
            && self.settled_from.is_some_and(|k| self.flown - k >= window_ticks);
        TrialOutcome {
            end,
            converged,
            convergence_time_s: self.settled_from.filter(|_| converged).map(|k| k as f64 * dt_s),
            final_position_error_m: self.final_position_m,
            final_attitude_error_rad: self.final_attitude_rad,
            max_tilt_rad: self.max_tilt_rad,
            non_finite: self.non_finite,
            fault_ticks: self.fault_ticks,
            saturated_ticks: self.saturated_ticks,
            ticks: self.flown,
        }
    }
}

impl<R> Observer<R> for Judge {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        self.flown += 1;
        let truth = plant.truth();
        let state = &tick.control.state;
        let step = tick.control.step.as_ref();
        let estimate_finite = step
            .and_then(|s| s.estimate)
            .is_none_or(|e| e.force_w.iter().chain(e.torque_b.iter()).all(|x| x.is_finite()) && e.mass_kg.is_finite());
        self.non_finite |= !(state.is_finite()
            && step.is_none_or(|s| s.control.is_finite())
            && tick.control.rotor_speeds().as_slice().iter().all(|w| w.is_finite())
            && estimate_finite
            && truth.pos_w.iter().chain(truth.vel_w.iter()).all(|x| x.is_finite())
            && truth.omega_b.iter().all(|x| x.is_finite())
            && truth.q_wb.coords.iter().all(|x| x.is_finite()));
        self.fault_ticks += u64::from(step.is_some_and(|s| s.control.flags.is_fault()));
        self.saturated_ticks += u64::from(step.is_some_and(|s| s.allocation.saturation.is_saturated()));
        let (e_p, e_r, tilt) = self.errors(&truth);
        (self.final_position_m, self.final_attitude_rad) = (e_p, e_r);
        self.max_tilt_rad = self.max_tilt_rad.max(tilt);
        self.settled_from = match (self.inside(e_p, e_r), self.settled_from) {
            (true, Some(k)) => Some(k),
            (true, None) => Some(self.flown),
            (false, _) => None,
        };
        None
    }
}
