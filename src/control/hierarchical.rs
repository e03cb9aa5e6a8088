//! Hierarchical controller in RPY coordinates (course material; docs/control.md §4): an outer
//! position loop producing μ_d, then u_T, φ_d, θ_d (docs/control.md §4.1, with the homework's
//! sign corrected, docs/homework.md §3, E1), and an inner attitude loop by feedback
//! linearisation (docs/control.md §4.2); the loops are [`RpyGains`] of [`HierarchicalGains`],
//! run by [`RpyLaw`](super::rpy_law::RpyLaw):
//!
//! ```text
//! μ_d = p̈_{b,d} − K_P e_p − K_D ė_p  [− f̂_e / m]                             (4.1)
//! τ̃   = η̈_{b,d} − K_η e_η − K_ė ė_η                                          (4.7)
//! τ_b = I_b Q τ̃ + ω × I_b ω + I_b Q̇ η̇_b  [− Q⁻ᵀ τ̂_e]                          (4.8)
//! closed loop:  ë_η + K_ė ė_η + K_η e_η = M⁻¹ (τ_e − τ̂_e)                     (4.9)
//! ```
//!
//! `I_b Q τ̃ = Q⁻ᵀ M τ̃` and the middle terms are `Q⁻ᵀ C η̇` (docs/model.md §3, eq. (3.11)), so
//! neither M⁻¹ nor C is formed.

use crate::math::{Mat3, Vec3};
use crate::rpy;

use super::gains::HierarchicalGains;
use super::reference::TranslationReference;
use super::rpy_law::RpyGains;
use super::rpy_reference::RpyTracking;

impl RpyGains for HierarchicalGains {
    /// `μ_d = p̈_{b,d} − K_P e_p − K_D ė_p − f̂_e / m` (docs/control.md §4.1, eq. (4.1)).
    fn mu(&self, tr: &TranslationReference, f_hat_w: &Vec3, mass_kg: f64) -> Vec3 {
        tr.acc_w - self.kp.component_mul(&tr.e_p) - self.kd.component_mul(&tr.e_v) - f_hat_w / mass_kg
    }

    /// `τ_b = I_b (Q τ̃ + Q̇ η̇) + ω × I_b ω` with `τ̃ = η̈_{b,d} − K_η e_η − K_ė ė_η`
    /// (docs/control.md §4.2, eqs. (4.7)–(4.8)).
    fn torque_b(&self, t: &RpyTracking, inertia: &Mat3, omega_b: &Vec3) -> Vec3 {
        let tau_tilde = t.eta_d_ddot - self.k_eta.component_mul(&t.e_eta) - self.k_eta_dot.component_mul(&t.e_eta_dot);
        inertia * (t.q * tau_tilde + rpy::q_dot(&t.eta, &t.eta_dot) * t.eta_dot) + omega_b.cross(&(inertia * omega_b))
    }
}

#[cfg(test)]
mod tests {
    use crate::control::rpy_law::plant::{first_tick, EtaPlant};
    use crate::control::ControllerGains;

    #[test]
    fn feedback_linearisation_yields_the_commanded_eta_acceleration() {
        let g = ControllerGains::default();
        let (out, EtaPlant { eta, eta_ddot, .. }) = first_tick(
            &g.hierarchical,
            [[0.3, -0.2, 0.1], [0.1, 0.2, -0.1], [0.2, -0.1, 0.4], [0.3, -0.5, 0.2]],
        );
        // Plant in η coordinates: M η̈ = Qᵀ τ_b − C η̇ must give η̈ = τ̃ (first tick: η̇_d = η̈_d = 0
        // for roll and pitch, planner yaw rate/acc 0).
        let tau_tilde = -g.hierarchical.k_eta.component_mul(&out.errors.attitude)
            - g.hierarchical.k_eta_dot.component_mul(&out.errors.rate);
        assert!((eta_ddot - tau_tilde).norm() < 1e-9, "{eta_ddot} vs {tau_tilde}");
        assert!((out.errors.attitude - (eta - out.eta_desired)).norm() < 1e-12);
    }
}
