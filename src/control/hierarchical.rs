//! Hierarchical controller in RPY coordinates (course material; control.md §4): an outer
//! position loop producing μ_d, then u_T, φ_d, θ_d (§4.1, erratum E1), and an inner attitude
//! loop by feedback linearisation (§4.2):
//!
//! ```text
//! μ_d = p̈_{b,d} − K_P e_p − K_D ė_p  [− f̂_e / m]
//! τ̃   = η̈_{b,d} − K_η e_η − K_ė ė_η
//! τ_b = I_b Q τ̃ + ω × I_b ω + I_b Q̇ η̇_b  [− Q⁻ᵀ τ̂_e]
//! closed loop:  ë_η + K_ė ė_η + K_η e_η = M⁻¹ (τ_e − τ̂_e)
//! ```
//!
//! `I_b Q τ̃ = Q⁻ᵀ M τ̃` and the middle terms are `Q⁻ᵀ C η̇` (§2.2), so neither M⁻¹ nor C is formed.

use crate::math::{Mat3, Vec3};
use crate::rpy;

use super::gains::{ControlLimits, HierarchicalGains, VehicleModel};
use super::reference::{HeadingReference, TranslationReference};
use super::rpy_reference::RpyReference;
use super::{ControlFlags, ControlOutput, ExternalWrench};

/// State of the hierarchical law between ticks (the desired-angle derivative filters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HierarchicalLaw {
    reference: RpyReference,
}

impl HierarchicalLaw {
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
        gains: &HierarchicalGains,
        limits: &ControlLimits,
        x: &super::VehicleState,
        tr: &TranslationReference,
        heading: &HeadingReference,
        ext: Option<&ExternalWrench>,
        flags: &mut ControlFlags,
    ) -> Option<ControlOutput> {
        let f_hat = ext.map_or(Vec3::zeros(), |w| w.force_w);
        let mu = tr.acc_w - gains.kp.component_mul(&tr.e_p) - gains.kd.component_mul(&tr.e_v) - f_hat / model.mass_kg;
        let t = self.reference.track(mu, heading, model, limits, x, flags)?;
        let tau_tilde =
            t.eta_d_ddot - gains.k_eta.component_mul(&t.e_eta) - gains.k_eta_dot.component_mul(&t.e_eta_dot);
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let w = &x.omega_b;
        let tau_hat = ext.map_or(Vec3::zeros(), |e| e.torque_b);
        let torque_b = inertia * (t.q * tau_tilde + rpy::q_dot(&t.eta, &t.eta_dot) * t.eta_dot)
            + w.cross(&(inertia * w))
            - tau_hat;
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
    fn feedback_linearisation_yields_the_commanded_eta_acceleration() {
        let model = VehicleModel {
            mass_kg: 1.5,
            inertia_kg_m2: Vec3::new(1.2416, 1.2416, 2.4832),
            thrust_max_n: 28.0,
        };
        let g = ControllerGains::default();
        let x = VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(0.3, -0.2, 0.1),
            vel_w: Vec3::new(0.1, 0.2, -0.1),
            r_wb: UnitQuat::from_euler_angles(0.2, -0.1, 0.4)
                .to_rotation_matrix()
                .into_inner(),
            omega_b: Vec3::new(0.3, -0.5, 0.2),
        };
        let sp = FlatSetpoint::hold(Vec3::zeros(), 0.0);
        let heading = HeadingHold::default().resolve(&x, &sp);
        let mut flags = ControlFlags::default();
        let out = HierarchicalLaw::new(1e-3, 0.02)
            .update(
                &model,
                &g.hierarchical,
                &g.limits,
                &x,
                &translation(&x, &sp),
                &heading,
                None,
                &mut flags,
            )
            .unwrap();
        // Plant in η coordinates: M η̈ = Qᵀ τ_b − C η̇ must give η̈ = τ̃ (first tick: η̇_d = η̈_d = 0
        // for roll and pitch, planner yaw rate/acc 0).
        let eta = crate::math::euler_zyx(&x.r_wb);
        let eta_dot = rpy::q_inverse(&eta, 1e-3).unwrap() * x.omega_b;
        let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
        let m = rpy::mass_matrix(&eta, &inertia);
        let c = rpy::coriolis(&eta, &eta_dot, &inertia);
        let eta_ddot = m.try_inverse().unwrap() * (rpy::q_matrix(&eta).transpose() * out.wrench.torque_b - c * eta_dot);
        let tau_tilde = -g.hierarchical.k_eta.component_mul(&out.errors.attitude)
            - g.hierarchical.k_eta_dot.component_mul(&out.errors.rate);
        assert!((eta_ddot - tau_tilde).norm() < 1e-9, "{eta_ddot} vs {tau_tilde}");
        assert!((out.errors.attitude - (eta - out.eta_desired)).norm() < 1e-12);
    }
}
