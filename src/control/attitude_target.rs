//! Direct attitude or body-rate control for offboard SET_ATTITUDE_TARGET (docs/mavlink.md §6,
//! docs/control.md §9): the attitude part of the geometric law
//! (docs/control.md §5.4, eqs. (5.7)–(5.9)) with a given
//! `R_{b,d}` and `ω_{b,d}` (ω̇_{b,d} = 0), or a body-rate loop
//! `τ_b = −K_ω (ω_b − ω_{b,d}) + ω_b × I_b ω_b` when only rates are given. Thrust is commanded
//! directly as a fraction of the rotors' maximum.

use crate::math::{Mat3, UnitQuat, Vec3};

use super::gains::{GeometricGains, VehicleModel};
use super::geometric::{attitude_tracking, AttitudeTracking, DesiredAttitude};
use super::{ControlFlags, ControlOutput, VehicleState};

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

/// The wrench that tracks `target` from state `x` with the geometric attitude gains: the
/// geometric attitude law ([`attitude_tracking`], ω̇_{b,d} = 0, no compensation) for an attitude
/// target, the body-rate loop `τ_b = −K_ω (ω_b − ω_{b,d}) + ω_b × I_b ω_b` for rates only.
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
    let omega_d = target.omega_b.unwrap_or_default();
    let tracking = match target.q_wb {
        Some(q) => {
            let desired = DesiredAttitude {
                r_d: q.to_rotation_matrix().into_inner(),
                omega_d,
                omega_d_dot: Vec3::zeros(),
            };
            attitude_tracking(gains, model, x, &desired, &Vec3::zeros())
        }
        None => {
            let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
            let w = &x.omega_b;
            let e_omega = w - omega_d;
            AttitudeTracking {
                r_d: x.r_wb,
                e_r: Vec3::zeros(),
                e_omega,
                torque_b: -gains.komega.component_mul(&e_omega) + w.cross(&(inertia * w)),
                large_error: false,
            }
        }
    };
    tracking.output(thrust_n, Vec3::zeros(), Vec3::zeros(), flags)
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
        VehicleState::at_rest(0.0, Vec3::zeros())
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
