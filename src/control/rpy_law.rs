//! The skeleton the two RPY laws share (docs/control.md §4.3, §6): the law's outer loop gives μ_d,
//! [`RpyReference`] turns it into u_T, η_d and the errors, the law's inner loop gives τ_b, and
//! the estimate is compensated the same way in both:
//!
//! ```text
//! μ_d = outer(p̈_{b,d}, e_p, ė_p, f̂_e, m)
//! τ_b = inner(η_d…, η, η̇, e_η, ė_η, I_b, ω_b) − τ̂_e^b        (τ̂_e^b = Q⁻ᵀ τ̂_e)
//! ```
//!
//! Only the active law runs and a switch of law resets the filters, so both RPY laws share one
//! [`RpyLaw`] (one set of desired-angle derivative filters).

use crate::math::{Mat3, Vec3};

use super::reference::{LawInput, TranslationReference};
use super::rpy_reference::{RpyReference, RpyTracking};
use super::{ControlFlags, ControlOutput};

/// The two loops that make an RPY law, implemented by its gains.
pub trait RpyGains {
    /// Outer loop: μ_d [m/s²] for the translation reference `tr`, the estimated force `f_hat_w`
    /// (world NED [N], zero without compensation) and the model mass `mass_kg` [kg].
    fn mu(&self, tr: &TranslationReference, f_hat_w: &Vec3, mass_kg: f64) -> Vec3;

    /// Inner loop: τ_b [N·m] (body FRD) for this tick's tracking `t`, the model inertia
    /// `inertia` [kg·m²] and the body rates `omega_b` [rad/s], before the estimate is subtracted.
    fn torque_b(&self, t: &RpyTracking, inertia: &Mat3, omega_b: &Vec3) -> Vec3;
}

/// State of the RPY laws between ticks (the desired-angle derivative filters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RpyLaw {
    reference: RpyReference,
}

impl RpyLaw {
    /// Law sampled every `ts_s` [s] with derivative filter time constant `tau_s` [s].
    pub fn new(ts_s: f64, tau_s: f64) -> Self {
        Self {
            reference: RpyReference::new(tau_s, ts_s),
        }
    }

    /// Forgets the derivative history.
    pub fn reset(&mut self) {
        self.reference.reset();
    }

    /// One tick of the law whose loops `gains` implement; `None` at the RPY singularity
    /// (`flags.rpy_singular` set).
    pub fn update(
        &mut self,
        gains: &impl RpyGains,
        input: &LawInput,
        flags: &mut ControlFlags,
    ) -> Option<ControlOutput> {
        let model = input.model;
        let tr = &input.translation;
        let mu = gains.mu(tr, &input.force_hat_w(), model.mass_kg);
        let t = self
            .reference
            .track(mu, &input.heading, model, input.limits, input.state, flags)?;
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let torque_b = gains.torque_b(&t, &inertia, &input.state.omega_b) - input.torque_hat_b();
        Some(t.output(torque_b, tr, *flags))
    }
}

/// First tick of an RPY law on the homework vehicle holding the origin, and the η-space plant
/// `M η̈ = Qᵀ τ_b − C η̇` (docs/model.md §3, eq. (3.8)) the laws' unit tests check their closed
/// loop with.
#[cfg(test)]
pub(super) mod plant {
    use super::*;
    use crate::control::gains::{ControlLimits, VehicleModel};
    use crate::control::reference::HeadingHold;
    use crate::control::{FlatSetpoint, VehicleState};
    use crate::math::euler_zyx;
    use crate::rpy;

    /// The plant's M(η) and C(η, η̇) at a state, and the η̈ a body torque gives there.
    pub struct EtaPlant {
        /// η of the state [rad].
        pub eta: Vec3,
        /// M(η).
        pub m: Mat3,
        /// C(η, η̇).
        pub c: Mat3,
        /// η̈ [rad/s²] under the law's torque.
        pub eta_ddot: Vec3,
    }

    /// The law's first output (no estimate) from the state `[p_b, ṗ_b, (φ, θ, ψ), ω_b]`
    /// (world NED [m], [m/s]; [rad]; body FRD [rad/s]) and the plant's response to it.
    pub fn first_tick(gains: &impl RpyGains, [pos, vel, angles, omega]: [[f64; 3]; 4]) -> (ControlOutput, EtaPlant) {
        let x = &VehicleState {
            pos_w: pos.into(),
            vel_w: vel.into(),
            omega_b: omega.into(),
            ..VehicleState::at_rest_turned(angles[0], angles[1], angles[2])
        };
        let model = VehicleModel::homework(28.0);
        let limits = ControlLimits::default();
        let sp = FlatSetpoint::hold(Vec3::zeros(), 0.0);
        let input = LawInput::resolve(&model, &limits, x, &sp, &mut HeadingHold::default(), None);
        let mut flags = ControlFlags::default();
        let out = RpyLaw::new(1e-3, 0.02).update(gains, &input, &mut flags).unwrap();
        let eta = euler_zyx(&x.r_wb);
        let eta_dot = rpy::q_inverse(&eta, 1e-3).unwrap() * x.omega_b;
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let m = rpy::mass_matrix(&eta, &inertia);
        let c = rpy::coriolis(&eta, &eta_dot, &inertia);
        let eta_ddot = m.try_inverse().unwrap() * (rpy::q_matrix(&eta).transpose() * out.wrench.torque_b - c * eta_dot);
        (out, EtaPlant { eta, m, c, eta_ddot })
    }
}
