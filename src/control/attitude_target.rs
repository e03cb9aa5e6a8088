//! Direct attitude or body-rate control for offboard SET_ATTITUDE_TARGET (mavlink.md §6):
//! the attitude part of the geometric law (control.md §5, eqs. (9), (10), (14)) with a given
//! `R_{b,d}` and `ω_{b,d}` (ω̇_{b,d} = 0), or a body-rate loop
//! `τ_b = −K_ω (ω_b − ω_{b,d}) + ω_b × I_b ω_b` when only rates are given. Thrust is commanded
//! directly as a fraction of the rotors' maximum.

use crate::allocation::Wrench;
use crate::math::{euler_zyx, hat, vee, Mat3, UnitQuat, Vec3};

use super::gains::{GeometricGains, VehicleModel};
use super::{ControlFlags, ControlOutput, TrackingErrors, VehicleState};

/// An attitude or rate target with collective thrust.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeTarget {
    /// Desired attitude body → world; `None` for rate-only control.
    pub q_wb: Option<UnitQuat>,
    /// Desired body rates [rad/s]; `None` = zero.
    pub omega_b: Option<Vec3>,
    /// Collective thrust as a fraction of the maximum [0, 1].
    pub thrust_fraction: f64,
}

impl AttitudeTarget {
    /// True when every value that is set is finite.
    pub fn is_finite(&self) -> bool {
        self.thrust_fraction.is_finite()
            && self.q_wb.is_none_or(|q| q.coords.iter().all(|c| c.is_finite()))
            && self.omega_b.is_none_or(|w| w.iter().all(|c| c.is_finite()))
    }
}

/// The wrench that tracks `target` from state `x` with the geometric attitude gains.
pub fn track_attitude(
    model: &VehicleModel,
    gains: &GeometricGains,
    x: &VehicleState,
    target: &AttitudeTarget,
) -> ControlOutput {
    let mut flags = ControlFlags::default();
    let raw = target.thrust_fraction * model.thrust_max_n;
    let thrust_n = raw.clamp(0.0, model.thrust_max_n);
    flags.thrust_clamped = thrust_n != raw;
    let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
    let w = &x.omega_b;
    let omega_d = target.omega_b.unwrap_or_default();
    let (torque_b, r_d, e_r, e_omega) = match target.q_wb {
        Some(q) => {
            let r_d = q.to_rotation_matrix().into_inner();
            let r = &x.r_wb;
            let rt_rd = r.transpose() * r_d;
            let e_r = 0.5 * vee(&(r_d.transpose() * r - r.transpose() * r_d));
            let e_omega = w - rt_rd * omega_d;
            let torque = -gains.kr.component_mul(&e_r) - gains.komega.component_mul(&e_omega) + w.cross(&(inertia * w))
                - inertia * (hat(w) * rt_rd * omega_d);
            flags.large_attitude_error = 0.5 * (Mat3::identity() - r_d.transpose() * r).trace() >= 1.0;
            (torque, r_d, e_r, e_omega)
        }
        None => {
            let e_omega = w - omega_d;
            let torque = -gains.komega.component_mul(&e_omega) + w.cross(&(inertia * w));
            (torque, x.r_wb, Vec3::zeros(), e_omega)
        }
    };
    ControlOutput {
        wrench: Wrench { thrust_n, torque_b },
        r_wb_desired: r_d,
        eta_desired: euler_zyx(&r_d),
        errors: TrackingErrors {
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            attitude: e_r,
            rate: e_omega,
        },
        flags,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::ControllerGains;

    fn model() -> VehicleModel {
        VehicleModel {
            mass_kg: 1.5,
            inertia_kg_m2: Vec3::new(0.03, 0.03, 0.05),
            thrust_max_n: 28.0,
        }
    }

    fn level() -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    #[test]
    fn attitude_target_rolls_towards_it_and_thrust_is_a_fraction() {
        let g = ControllerGains::default().geometric;
        let t = AttitudeTarget {
            q_wb: Some(UnitQuat::from_euler_angles(0.2, 0.0, 0.0)),
            omega_b: None,
            thrust_fraction: 0.5,
        };
        let out = track_attitude(&model(), &g, &level(), &t);
        assert!(out.wrench.torque_b.x > 0.0 && out.wrench.torque_b.y.abs() < 1e-12);
        assert_eq!(out.wrench.thrust_n, 14.0);
        let over = track_attitude(
            &model(),
            &g,
            &level(),
            &AttitudeTarget {
                thrust_fraction: 1.5,
                ..t
            },
        );
        assert!(over.flags.thrust_clamped && over.wrench.thrust_n == 28.0);
    }

    #[test]
    fn rate_target_damps_towards_the_rate() {
        let g = ControllerGains::default().geometric;
        let t = AttitudeTarget {
            q_wb: None,
            omega_b: Some(Vec3::new(0.0, 0.0, 1.0)),
            thrust_fraction: 0.5,
        };
        let out = track_attitude(&model(), &g, &level(), &t);
        assert!((out.wrench.torque_b.z - g.komega.z).abs() < 1e-12);
        assert!(!AttitudeTarget {
            thrust_fraction: f64::NAN,
            ..t
        }
        .is_finite());
    }
}
