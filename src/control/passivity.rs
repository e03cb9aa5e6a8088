//! Passivity-based controller in RPY coordinates without feedback linearisation
//! (F. Ruggiero et al., ICRA 2014 / RAS 2015; control.md §6, eq. (16) corrected, erratum E3):
//!
//! ```text
//! μ_d  = p̈_{b,d} − (1/m)( D_o ė_p + K_o e_p + f̂_e )                          §6.1
//! η̇_r = η̇_{b,d} − σ e_η                                                     (15)
//! η̈_r = η̈_{b,d} − σ ė_η                                                     (16, E3)
//! ν_η = ė_η + σ e_η                                                          (19)
//! τ_b = Q⁻ᵀ ( M η̈_r + C η̇_r − τ̂_e − D_a ν_η − K_a e_η )
//! closed loop:  M ν̇_η + (C + D_a) ν_η + K_a e_η = τ_e − τ̂_e
//! ```
//!
//! C is the skew-consistent Coriolis matrix of §2.2 (erratum E4), for which the passivity
//! argument holds. `Q⁻ᵀ τ̂_e = τ̂_e^b`, so the compensation is subtracted in body coordinates.

use crate::math::{Mat3, Vec3};
use crate::rpy;

use super::gains::{ControlLimits, PassivityGains, VehicleModel};
use super::reference::{HeadingReference, TranslationReference};
use super::rpy_reference::RpyReference;
use super::{ControlFlags, ControlOutput, ExternalWrench};

/// State of the passivity-based law between ticks (the desired-angle derivative filters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassivityLaw {
    reference: RpyReference,
}

impl PassivityLaw {
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

    /// One tick; `None` at the RPY singularity (`flags.rpy_singular` set).
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        model: &VehicleModel,
        gains: &PassivityGains,
        limits: &ControlLimits,
        x: &super::VehicleState,
        tr: &TranslationReference,
        heading: &HeadingReference,
        ext: Option<&ExternalWrench>,
        flags: &mut ControlFlags,
    ) -> Option<ControlOutput> {
        let f_hat = ext.map_or(Vec3::zeros(), |w| w.force_w);
        let mu =
            tr.acc_w - (gains.d_o.component_mul(&tr.e_v) + gains.k_o.component_mul(&tr.e_p) + f_hat) / model.mass_kg;
        let t = self.reference.track(mu, heading, model, limits, x, flags)?;
        let sigma = gains.sigma;
        let eta_r_dot = t.eta_d_dot - sigma * t.e_eta;
        let eta_r_ddot = t.eta_d_ddot - sigma * t.e_eta_dot;
        let nu = t.e_eta_dot + sigma * t.e_eta;
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let m = rpy::mass_matrix(&t.eta, &inertia);
        let c = rpy::coriolis(&t.eta, &t.eta_dot, &inertia);
        let tau_eta = m * eta_r_ddot + c * eta_r_dot - gains.d_a.component_mul(&nu) - gains.k_a.component_mul(&t.e_eta);
        let tau_hat = ext.map_or(Vec3::zeros(), |e| e.torque_b);
        let torque_b = t.q_inv.transpose() * tau_eta - tau_hat;
        Some(t.output(torque_b, tr, *flags))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::reference::{translation, HeadingHold};
    use crate::control::{ControllerGains, FlatSetpoint, VehicleState};
    use crate::math::UnitQuat;

    #[test]
    fn closed_loop_is_the_mass_spring_damper_in_nu() {
        let model = VehicleModel {
            mass_kg: 1.5,
            inertia_kg_m2: Vec3::new(1.2416, 1.2416, 2.4832),
            thrust_max_n: 28.0,
        };
        let g = ControllerGains::default();
        let x = VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(-0.2, 0.4, 0.3),
            vel_w: Vec3::new(0.0, -0.3, 0.1),
            r_wb: UnitQuat::from_euler_angles(-0.15, 0.25, -0.6)
                .to_rotation_matrix()
                .into_inner(),
            omega_b: Vec3::new(-0.4, 0.2, 0.6),
        };
        let sp = FlatSetpoint::hold(Vec3::zeros(), 0.0);
        let heading = HeadingHold::default().resolve(&x, &sp);
        let mut flags = ControlFlags::default();
        let out = PassivityLaw::new(1e-3, 0.02)
            .update(
                &model,
                &g.passivity,
                &g.limits,
                &x,
                &translation(&x, &sp),
                &heading,
                None,
                &mut flags,
            )
            .unwrap();
        // M ν̇ + (C + D_a) ν + K_a e = 0 with ν̇ = ë + σ ė and ë = η̈ (first tick: η̈_d = 0).
        let eta = crate::math::euler_zyx(&x.r_wb);
        let eta_dot = rpy::q_inverse(&eta, 1e-3).unwrap() * x.omega_b;
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let m = rpy::mass_matrix(&eta, &inertia);
        let c = rpy::coriolis(&eta, &eta_dot, &inertia);
        let eta_ddot = m.try_inverse().unwrap() * (rpy::q_matrix(&eta).transpose() * out.wrench.torque_b - c * eta_dot);
        let (e, e_dot, sigma) = (out.errors.attitude, out.errors.rate, g.passivity.sigma);
        let nu = e_dot + sigma * e;
        let nu_dot = eta_ddot + sigma * e_dot;
        let residual = m * nu_dot + c * nu + g.passivity.d_a.component_mul(&nu) + g.passivity.k_a.component_mul(&e);
        assert!(residual.norm() < 1e-9, "{residual}");
    }
}
