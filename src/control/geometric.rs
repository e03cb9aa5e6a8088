//! Geometric tracking controller on SE(3) (T. Lee, M. Leok, N. H. McClamroch, CDC 2010;
//! docs/control.md §5, eqs. (5.1)–(5.10), with the homework's position-feedback sign corrected,
//! docs/homework.md §3, E2):
//!
//! ```text
//! A   = −K_p e_p − K_v ė_p − m g e3 + m p̈_{b,d}  [− f̂_e]                       (5.1)
//! u_T = −Aᵀ R_b e3  (at least 0.12 u_T,max while R_b e3 is over 60° from z_{b,d})   (5.2)
//! z_{b,d} = −A / ‖A‖                                                              (5.3)
//! R_{b,d} = [y_{b,d} × z_{b,d}, y_{b,d}, z_{b,d}],  y_{b,d} ∥ z_{b,d} × x_c          (5.4)
//! e_R = ½ vee( R_{b,d}ᵀ R_b − R_bᵀ R_{b,d} )                                      (5.7)
//! e_ω = ω_b − R_bᵀ R_{b,d} ω_{b,d}                                                (5.8)
//! τ_b = −K_R e_R − K_ω e_ω + ω_b × I_b ω_b
//!       − I_b ( S(ω_b) R_bᵀ R_{b,d} ω_{b,d} − R_bᵀ R_{b,d} ω̇_{b,d} )  [− τ̂_e^b]  (5.9)
//! ```
//!
//! with `x_c ∥ y_ψ × z_{b,d}`, `y_ψ = [−sin ψ_d, cos ψ_d, 0]ᵀ` (5.4a): the direction normal to
//! z_{b,d} whose horizontal projection points along ψ_d, so the heading (ZYX yaw) of R_{b,d} is
//! ψ_d at any tilt, as PX4 builds its attitude setpoint; ω_{b,d} and ω̇_{b,d} by
//! [`DesiredRateMode`] (docs/control.md §5.3, eqs. (5.5)–(5.6)).

use serde::{Deserialize, Serialize};

use crate::allocation::Wrench;
use crate::math::{e3, euler_zyx, hat, vee, Mat3, Vec3, GRAVITY_M_S2};

use super::filters::DirtyDerivative;
use super::gains::{GeometricGains, VehicleModel};
use super::reference::LawInput;
use super::{ControlFlags, ControlOutput, TrackingErrors, VehicleState};

/// Below this `‖z_{b,d} × x_c‖` the previous `y_{b,d}` is kept (heading undefined) [-].
const CROSS_MIN: f64 = 1e-6;
/// While the thrust axis is further than this from the desired one [rad]...
const RECOVERY_TILT_ERROR_RAD: f64 = std::f64::consts::FRAC_PI_3;
/// ...the thrust keeps at least this share of its maximum (PX4's `MPC_THR_MIN`, 0.12): the
/// projection (5.2) would ask none, and rotors at rest give no torque to turn back with.
const RECOVERY_THRUST_FRACTION: f64 = 0.12;

/// How ω_{b,d} and ω̇_{b,d} are obtained (docs/control.md §5.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DesiredRateMode {
    /// `ω_{b,d} = vee(½(X − Xᵀ)) / Ts`, `X = R_{b,d}[k−1]ᵀ R_{b,d}[k]`; ω̇_{b,d} by the filtered
    /// derivative (the course template's choice).
    #[default]
    Numerical,
    /// RotorPy's simplification: `ω_{b,d} = [0, 0, ψ̇_d]`, `ω̇_{b,d} = 0`.
    YawRateOnly,
}

/// State of the geometric law between ticks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeometricLaw {
    ts_s: f64,
    tau_s: f64,
    mode: DesiredRateMode,
    previous_r_d: Option<Mat3>,
    previous_z_d: Vec3,
    previous_y_d: Vec3,
    omega_d_dot: DirtyDerivative,
}

impl GeometricLaw {
    /// Law sampled every `ts_s` [s] with derivative filter time constant `tau_s` [s].
    pub fn new(ts_s: f64, tau_s: f64, mode: DesiredRateMode) -> Self {
        Self {
            ts_s,
            tau_s,
            mode,
            previous_r_d: None,
            previous_z_d: e3(),
            previous_y_d: Vec3::new(0.0, 1.0, 0.0),
            omega_d_dot: DirtyDerivative::new(tau_s, ts_s),
        }
    }

    /// Forgets the previous desired attitude and the derivative history.
    pub fn reset(&mut self) {
        *self = Self::new(self.ts_s, self.tau_s, self.mode);
    }

    /// One tick of docs/control.md §5, eqs. (5.1)–(5.10).
    pub fn update(&mut self, gains: &GeometricGains, input: &LawInput) -> ControlOutput {
        let (model, limits, tr, heading) = (input.model, input.limits, &input.translation, &input.heading);
        let m = model.mass_kg;
        let mut flags = ControlFlags::default();
        let mut a = -gains.kp.component_mul(&tr.e_p) - gains.kv.component_mul(&tr.e_v) - m * GRAVITY_M_S2 * e3()
            + m * tr.acc_w
            - input.force_hat_w();
        // Guards: keep an upward thrust component and the tilt limit (docs/control.md §5.1).
        if a.z > -m * limits.eps_z_m_s2 {
            a.z = -m * limits.eps_z_m_s2;
            flags.thrust_direction_held = true;
        }
        let horizontal = a.xy().norm();
        let allowed = limits.tilt_max_rad.tan() * a.z.abs();
        if horizontal > allowed {
            let s = allowed / horizontal;
            a.x *= s;
            a.y *= s;
            flags.tilt_limited = true;
        }
        let body_z = input.state.r_wb * e3();
        let raw_thrust = -a.dot(&body_z);
        let norm_a = a.norm();
        let z_d = if norm_a > limits.eps_a_n {
            -a / norm_a
        } else {
            flags.thrust_direction_held = true;
            self.previous_z_d
        };
        // Recovery: a thrust axis far from the desired one keeps torque authority (see
        // RECOVERY_THRUST_FRACTION); touch-downs and small errors are untouched.
        let floor = if body_z.dot(&z_d) < RECOVERY_TILT_ERROR_RAD.cos() {
            RECOVERY_THRUST_FRACTION * model.thrust_max_n
        } else {
            0.0
        };
        let thrust_n = raw_thrust.clamp(floor, model.thrust_max_n);
        flags.thrust_clamped = thrust_n != raw_thrust;
        // (5.4a): x_c normal to z_d with its horizontal projection along ψ_d.
        let y_psi = Vec3::new(-heading.yaw_rad.sin(), heading.yaw_rad.cos(), 0.0);
        let x_c = y_psi.cross(&z_d);
        let y_raw = z_d.cross(&x_c);
        let y_d = if y_raw.norm() > CROSS_MIN {
            y_raw.normalize()
        } else {
            self.previous_y_d
        };
        let r_d = Mat3::from_columns(&[y_d.cross(&z_d), y_d, z_d]);
        self.previous_z_d = z_d;
        self.previous_y_d = y_d;

        let (omega_d, omega_d_dot) = match self.mode {
            DesiredRateMode::Numerical => {
                let prev = self.previous_r_d.unwrap_or(r_d);
                let xm = prev.transpose() * r_d;
                let omega_d = vee(&(0.5 * (xm - xm.transpose()))) / self.ts_s;
                (omega_d, self.omega_d_dot.update(omega_d))
            }
            DesiredRateMode::YawRateOnly => (Vec3::new(0.0, 0.0, heading.yaw_rate_rad_s), Vec3::zeros()),
        };
        self.previous_r_d = Some(r_d);

        let desired = DesiredAttitude {
            r_d,
            omega_d,
            omega_d_dot,
        };
        attitude_tracking(gains, model, input.state, &desired, &input.torque_hat_b())
            .output(thrust_n, tr.e_p, tr.e_v, flags)
    }
}

/// A desired attitude with its rates (docs/control.md §5.2–§5.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesiredAttitude {
    /// `R_{b,d}`, body → world.
    pub r_d: Mat3,
    /// ω_{b,d}, desired body frame [rad/s].
    pub omega_d: Vec3,
    /// ω̇_{b,d}, desired body frame [rad/s²].
    pub omega_d_dot: Vec3,
}

/// Attitude errors and torque of one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeTracking {
    /// Desired attitude `R_{b,d}`.
    pub r_d: Mat3,
    /// Attitude error [rad].
    pub e_r: Vec3,
    /// Rate error [rad/s].
    pub e_omega: Vec3,
    /// Body torque τ_b, FRD [N·m].
    pub torque_b: Vec3,
    /// `Ψ = ½ tr(I − R_dᵀ R) ≥ 1`.
    pub large_error: bool,
}

impl AttitudeTracking {
    /// The output with thrust `thrust_n` [N], translational errors `e_p` [m], `e_v` [m/s] and
    /// `flags` (plus `large_attitude_error`); η_d are the ZYX angles of `R_{b,d}`.
    pub fn output(&self, thrust_n: f64, e_p: Vec3, e_v: Vec3, flags: ControlFlags) -> ControlOutput {
        ControlOutput {
            wrench: Wrench {
                thrust_n,
                torque_b: self.torque_b,
            },
            r_wb_desired: self.r_d,
            eta_desired: euler_zyx(&self.r_d),
            errors: TrackingErrors {
                pos_w: e_p,
                vel_w: e_v,
                attitude: self.e_r,
                rate: self.e_omega,
            },
            flags: ControlFlags {
                large_attitude_error: self.large_error,
                ..flags
            },
        }
    }
}

/// The attitude part of the geometric law (docs/control.md §5.4, eqs. (5.7)–(5.10)): e_R, e_ω
/// and τ_b from state `x` towards `desired`, minus the estimated body torque `tau_hat_b` [N·m]
/// (zero for no compensation); also serves offboard attitude targets.
pub fn attitude_tracking(
    gains: &GeometricGains,
    model: &VehicleModel,
    x: &VehicleState,
    desired: &DesiredAttitude,
    tau_hat_b: &Vec3,
) -> AttitudeTracking {
    let DesiredAttitude {
        r_d,
        omega_d,
        omega_d_dot,
    } = desired;
    let r = &x.r_wb;
    let rt_rd = r.transpose() * r_d;
    let e_r = 0.5 * vee(&(r_d.transpose() * r - r.transpose() * r_d));
    let e_omega = x.omega_b - rt_rd * omega_d;
    let inertia = Mat3::from_diagonal(&model.inertia_kg_m2);
    let w = &x.omega_b;
    let torque_b = -gains.kr.component_mul(&e_r) - gains.komega.component_mul(&e_omega) + w.cross(&(inertia * w))
        - inertia * (hat(w) * rt_rd * omega_d - rt_rd * omega_d_dot)
        - tau_hat_b;
    let psi = 0.5 * (Mat3::identity() - r_d.transpose() * r).trace();
    AttitudeTracking {
        r_d: *r_d,
        e_r,
        e_omega,
        torque_b,
        large_error: psi >= 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::reference::HeadingHold;
    use crate::control::{ControlLimits, ControllerGains, FlatSetpoint};
    use crate::math::UnitQuat;

    fn step(law: &mut GeometricLaw, x: &VehicleState, sp: &FlatSetpoint) -> ControlOutput {
        let g = ControllerGains::default();
        let model = VehicleModel::homework(60.0);
        law.update(
            &g.geometric,
            &LawInput::resolve(&model, &g.limits, x, sp, &mut HeadingHold::default(), None),
        )
    }

    fn level(pos_w: Vec3) -> VehicleState {
        VehicleState::at_rest(0.0, pos_w)
    }

    #[test]
    fn one_metre_low_adds_k_p_z_newtons() {
        // docs/control.md §5.5: e_z = 1 m ⇒ u_T = m g + K_p,z.
        let out = step(
            &mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical),
            &level(Vec3::new(0.0, 0.0, 1.0)),
            &FlatSetpoint::hold(Vec3::zeros(), 0.0),
        );
        assert!((out.wrench.thrust_n - (1.5 * GRAVITY_M_S2 + 25.0)).abs() < 1e-12);
        assert_eq!(out.r_wb_desired, Mat3::identity());
    }

    #[test]
    fn attitude_error_and_torque_follow_eqs_9_and_14() {
        let x = VehicleState::at_rest_turned(0.1, 0.0, 0.0);
        let out = step(
            &mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical),
            &x,
            &FlatSetpoint::hold(Vec3::zeros(), 0.0),
        );
        // Rolled right by 0.1 rad: e_R = (sin 0.1, 0, 0), τ_x = −K_R,x sin 0.1.
        assert!((out.errors.attitude.x - 0.1f64.sin()).abs() < 1e-12);
        assert!((out.wrench.torque_b.x + 180.0 * 0.1f64.sin()).abs() < 1e-9);
    }

    #[test]
    fn antipodal_quaternions_give_the_same_command() {
        let q = UnitQuat::from_euler_angles(2.0, -0.7, 1.0);
        let antipodal = UnitQuat::new_unchecked(-q.into_inner());
        let mut a = level(Vec3::zeros());
        a.r_wb = q.to_rotation_matrix().into_inner();
        let mut b = a;
        b.r_wb = antipodal.to_rotation_matrix().into_inner();
        let sp = FlatSetpoint::hold(Vec3::zeros(), 0.0);
        let oa = step(&mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical), &a, &sp);
        let ob = step(&mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical), &b, &sp);
        assert!((oa.wrench.torque_b - ob.wrench.torque_b).norm() < 1e-9);
        assert!(oa.flags.large_attitude_error);
    }

    #[test]
    fn numerical_desired_rate_recovers_a_yaw_ramp() {
        let mut law = GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical);
        let x = level(Vec3::zeros());
        let rate = 0.3;
        let mut out = None;
        for k in 0..400 {
            let yaw = rate * k as f64 * 1e-3;
            out = Some(step(&mut law, &x, &FlatSetpoint::hold(Vec3::zeros(), yaw)));
        }
        let out = out.unwrap();
        // e_ω = ω − Rᵀ R_d ω_d with ω = 0: −ω_d expressed in the body, ω_d ≈ (0, 0, 0.3).
        assert!((out.errors.rate.z + rate).abs() < 1e-3, "{}", out.errors.rate);
        let mut simple = GeometricLaw::new(1e-3, 0.02, DesiredRateMode::YawRateOnly);
        let sp = FlatSetpoint {
            yaw_rate_rad_s: Some(rate),
            ..FlatSetpoint::hold(Vec3::zeros(), 0.0)
        };
        assert!((step(&mut simple, &x, &sp).errors.rate.z + rate).abs() < 1e-15);
    }

    #[test]
    fn a_vehicle_rolled_far_from_its_desired_attitude_keeps_a_recovery_thrust() {
        let thrust_rolled = |roll_deg: f64| {
            let mut x = level(Vec3::zeros());
            x.r_wb = UnitQuat::from_euler_angles(roll_deg.to_radians(), 0.0, 0.0)
                .to_rotation_matrix()
                .into_inner();
            let law = &mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical);
            step(law, &x, &FlatSetpoint::hold(Vec3::zeros(), 0.0))
        };
        // Rolled 100°: the projection (5.2) asks no thrust, which would leave no torque.
        let out = thrust_rolled(100.0);
        let model = VehicleModel::homework(60.0);
        assert!((out.wrench.thrust_n - 0.12 * model.thrust_max_n).abs() < 1e-12);
        assert!(out.flags.thrust_clamped);
        // Rolled 30°: the projection as it is.
        let out = thrust_rolled(30.0);
        assert!((out.wrench.thrust_n - 1.5 * GRAVITY_M_S2 * 30f64.to_radians().cos()).abs() < 1e-9);
    }

    #[test]
    fn tilt_limit_and_upward_thrust_guards_act() {
        let out = step(
            &mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical),
            &level(Vec3::zeros()),
            &FlatSetpoint::hold(Vec3::new(100.0, 0.0, 0.0), 0.0),
        );
        assert!(out.flags.tilt_limited);
        let tilt = out.r_wb_desired[(2, 2)].acos();
        assert!((tilt - ControlLimits::default().tilt_max_rad).abs() < 1e-9);
        let dive = step(
            &mut GeometricLaw::new(1e-3, 0.02, DesiredRateMode::Numerical),
            &level(Vec3::zeros()),
            &FlatSetpoint::hold(Vec3::new(0.0, 0.0, 100.0), 0.0),
        );
        assert!(dive.flags.thrust_direction_held && dive.wrench.thrust_n > 0.0);
        assert_eq!(dive.r_wb_desired, Mat3::identity());
    }
}
