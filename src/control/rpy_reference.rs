//! Shared middle of the RPY laws (docs/control.md §4.3, used by docs/control.md §4, §6): from the outer
//! loop's μ_d to the desired angles η_d with filtered derivatives, and the measured η, η̇ with
//! their errors.
//!
//! φ̇_d, θ̇_d, φ̈_d, θ̈_d come from the filtered derivative `D(s) = s/(τ_f s + 1)` applied once and
//! twice (docs/control.md §3, eq. (3.2)); ψ_d, ψ̇_d, ψ̈_d come from the planner.
//! `e_η = η − η_d` with every angle wrapped into (−π, π]; `η̇ = Q(η)⁻¹ ω_b`
//! (docs/control.md §4.3, eqs. (4.10)–(4.11); docs/control.md §4.2, eq. (4.6)).

use crate::allocation::Wrench;
use crate::math::{euler_zyx, wrap_pi, Mat3, Vec3};
use crate::rpy;

use super::filters::DirtyDerivative;
use super::gains::{ControlLimits, VehicleModel};
use super::reference::{HeadingReference, TranslationReference};
use super::rpy_extraction::{extract, ExtractionLimits};
use super::{ControlFlags, ControlOutput, TrackingErrors};

/// Desired and measured attitude in RPY coordinates for one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RpyTracking {
    /// Collective thrust u_T [N].
    pub thrust_n: f64,
    /// η_d [rad].
    pub eta_d: Vec3,
    /// η̇_d [rad/s].
    pub eta_d_dot: Vec3,
    /// η̈_d [rad/s²].
    pub eta_d_ddot: Vec3,
    /// Measured η [rad].
    pub eta: Vec3,
    /// Measured η̇ = Q⁻¹ ω_b [rad/s].
    pub eta_dot: Vec3,
    /// Q(η).
    pub q: Mat3,
    /// Q(η)⁻¹.
    pub q_inv: Mat3,
    /// e_η [rad].
    pub e_eta: Vec3,
    /// ė_η [rad/s].
    pub e_eta_dot: Vec3,
}

impl RpyTracking {
    /// The law's output for body torque `torque_b` [N·m]: this tick's thrust, desired attitude
    /// and errors (e_p, ė_p from `tr`; e_η, ė_η as the attitude and rate errors).
    pub fn output(&self, torque_b: Vec3, tr: &TranslationReference, flags: ControlFlags) -> ControlOutput {
        ControlOutput {
            wrench: Wrench {
                thrust_n: self.thrust_n,
                torque_b,
            },
            r_wb_desired: rpy::rotation(&self.eta_d),
            eta_desired: self.eta_d,
            errors: TrackingErrors {
                pos_w: tr.e_p,
                vel_w: tr.e_v,
                attitude: self.e_eta,
                rate: self.e_eta_dot,
            },
            flags,
        }
    }
}

/// Filters that turn the extracted angles into η_d, η̇_d, η̈_d.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RpyReference {
    rate: DirtyDerivative,
    acc: DirtyDerivative,
}

impl RpyReference {
    /// Filters with time constant `tau_s` [s] at sample time `ts_s` [s].
    pub fn new(tau_s: f64, ts_s: f64) -> Self {
        Self {
            rate: DirtyDerivative::new(tau_s, ts_s),
            acc: DirtyDerivative::new(tau_s, ts_s),
        }
    }

    /// Forgets the derivative history.
    pub fn reset(&mut self) {
        self.rate.reset();
        self.acc.reset();
    }

    /// Thrust, desired angles and errors for μ_d = `mu` [m/s²]; `None` at the RPY singularity
    /// (|cos θ| below the guard), with `flags.rpy_singular` set.
    pub fn track(
        &mut self,
        mu: Vec3,
        heading: &HeadingReference,
        model: &VehicleModel,
        limits: &ControlLimits,
        x: &super::VehicleState,
        flags: &mut ControlFlags,
    ) -> Option<RpyTracking> {
        let ex = extract(
            mu,
            heading.yaw_rad,
            model.mass_kg,
            &ExtractionLimits {
                tilt_max_rad: limits.tilt_max_rad,
                eps_z_m_s2: limits.eps_z_m_s2,
                thrust_max_n: model.thrust_max_n,
            },
        );
        flags.tilt_limited = ex.tilt_limited;
        flags.thrust_direction_held = ex.vertical_limited;
        flags.thrust_clamped = ex.thrust_clamped;
        let angles = Vec3::new(ex.roll_rad, ex.pitch_rad, 0.0);
        let rate = self.rate.update(angles);
        let acc = self.acc.update(rate);
        let eta = euler_zyx(&x.r_wb);
        let Some(q_inv) = rpy::q_inverse(&eta, limits.cos_theta_min) else {
            flags.rpy_singular = true;
            return None;
        };
        let eta_d = Vec3::new(ex.roll_rad, ex.pitch_rad, heading.yaw_rad);
        let eta_d_dot = Vec3::new(rate.x, rate.y, heading.yaw_rate_rad_s);
        let eta_dot = q_inv * x.omega_b;
        let d = eta - eta_d;
        Some(RpyTracking {
            thrust_n: ex.thrust_n,
            eta_d,
            eta_d_dot,
            eta_d_ddot: Vec3::new(acc.x, acc.y, heading.yaw_acc_rad_s2),
            eta,
            eta_dot,
            q: rpy::q_matrix(&eta),
            q_inv,
            e_eta: Vec3::new(wrap_pi(d.x), wrap_pi(d.y), wrap_pi(d.z)),
            e_eta_dot: eta_dot - eta_d_dot,
        })
    }
}
