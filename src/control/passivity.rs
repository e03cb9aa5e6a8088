//! Passivity-based controller in RPY coordinates without feedback linearisation
//! (F. Ruggiero et al., ICRA 2014 / RAS 2015; docs/control.md §6, eqs. (6.1)–(6.8), with the
//! homework's reference acceleration corrected, docs/homework.md §3, E3); the loops are
//! [`RpyGains`] of [`PassivityGains`], run by [`RpyLaw`](super::rpy_law::RpyLaw):
//!
//! ```text
//! μ_d  = p̈_{b,d} − (1/m)( D_o ė_p + K_o e_p + f̂_e )                          (6.1)
//! η̇_r = η̇_{b,d} − σ e_η                                                     (6.3)
//! η̈_r = η̈_{b,d} − σ ė_η                                                     (6.4)
//! ν_η = ė_η + σ e_η                                                          (6.5)
//! τ_b = Q⁻ᵀ ( M η̈_r + C η̇_r − τ̂_e − D_a ν_η − K_a e_η )                     (6.6)
//! closed loop:  M ν̇_η + (C + D_a) ν_η + K_a e_η = τ_e − τ̂_e                 (6.7)
//! ```
//!
//! C is the skew-consistent Coriolis matrix of docs/model.md §3, eq. (3.9) (docs/homework.md §3,
//! E4), for which the passivity argument holds. `Q⁻ᵀ τ̂_e = τ̂_e^b`, so the compensation is
//! subtracted in body coordinates.

use crate::math::{Mat3, Vec3};
use crate::rpy;

use super::gains::PassivityGains;
use super::reference::TranslationReference;
use super::rpy_law::RpyGains;
use super::rpy_reference::RpyTracking;

impl RpyGains for PassivityGains {
    /// `μ_d = p̈_{b,d} − (D_o ė_p + K_o e_p + f̂_e) / m` (docs/control.md §6.1, eq. (6.1)).
    fn mu(&self, tr: &TranslationReference, f_hat_w: &Vec3, mass_kg: f64) -> Vec3 {
        tr.acc_w - (self.d_o.component_mul(&tr.e_v) + self.k_o.component_mul(&tr.e_p) + f_hat_w) / mass_kg
    }

    /// `τ_b = Q⁻ᵀ (M η̈_r + C η̇_r − D_a ν_η − K_a e_η)` (docs/control.md §6.2, eqs. (6.3)–(6.6)).
    fn torque_b(&self, t: &RpyTracking, inertia: &Mat3, _omega_b: &Vec3) -> Vec3 {
        let sigma = self.sigma;
        let eta_r_dot = t.eta_d_dot - sigma * t.e_eta;
        let eta_r_ddot = t.eta_d_ddot - sigma * t.e_eta_dot;
        let nu = t.e_eta_dot + sigma * t.e_eta;
        let m = rpy::mass_matrix(&t.eta, inertia);
        let c = rpy::coriolis(&t.eta, &t.eta_dot, inertia);
        let tau_eta = m * eta_r_ddot + c * eta_r_dot - self.d_a.component_mul(&nu) - self.k_a.component_mul(&t.e_eta);
        t.q_inv.transpose() * tau_eta
    }
}

#[cfg(test)]
mod tests {
    use crate::control::rpy_law::plant::{first_tick, EtaPlant};
    use crate::control::ControllerGains;

    #[test]
    fn closed_loop_is_the_mass_spring_damper_in_nu() {
        let g = ControllerGains::default();
        let (out, EtaPlant { m, c, eta_ddot, .. }) = first_tick(
            &g.passivity,
            [
                [-0.2, 0.4, 0.3],
                [0.0, -0.3, 0.1],
                [-0.15, 0.25, -0.6],
                [-0.4, 0.2, 0.6],
            ],
        );
        // M ν̇ + (C + D_a) ν + K_a e = 0 with ν̇ = ë + σ ė and ë = η̈ (first tick: η̈_d = 0).
        let (e, e_dot, sigma) = (out.errors.attitude, out.errors.rate, g.passivity.sigma);
        let nu = e_dot + sigma * e;
        let nu_dot = eta_ddot + sigma * e_dot;
        let residual = m * nu_dot + c * nu + g.passivity.d_a.component_mul(&nu) + g.passivity.k_a.component_mul(&e);
        assert!(residual.norm() < 1e-9, "{residual}");
    }
}
