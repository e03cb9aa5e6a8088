//! Hover controller: the small position + attitude law that flies the headless run until the
//! homework controllers exist (the "do-nothing implementation that documents the contract" of
//! architecture.md §7.1). Structure as control.md §5 (thrust along −z_b, `z_{b,d} = −A/‖A‖`,
//! `e_R = ½ vee(R_dᵀR − RᵀR_d)`), with gains per unit mass and inertia and no feed-forward of
//! desired angular rates.

use crate::allocation::Wrench;
use crate::math::{e3, vee, Mat3, Vec3, GRAVITY_M_S2};

use super::{FlatSetpoint, VehicleState};

/// Gains of the hover controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoverGains {
    /// Position stiffness per unit mass [1/s²].
    pub kp_per_s2: f64,
    /// Velocity damping per unit mass [1/s].
    pub kd_per_s: f64,
    /// Attitude stiffness per unit inertia [1/s²].
    pub k_att_per_s2: f64,
    /// Rate damping per unit inertia [1/s].
    pub k_rate_per_s: f64,
    /// Largest tilt commanded [rad].
    pub tilt_max_rad: f64,
}

impl Default for HoverGains {
    /// Position ω_n = 2 rad/s, ζ = 1; attitude ω_n = 12 rad/s, ζ = 1; tilt ≤ 35°.
    fn default() -> Self {
        Self {
            kp_per_s2: 4.0,
            kd_per_s: 4.0,
            k_att_per_s2: 144.0,
            k_rate_per_s: 24.0,
            tilt_max_rad: 35f64.to_radians(),
        }
    }
}

/// Hover controller for one vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoverController {
    /// Believed mass [kg].
    pub mass_kg: f64,
    /// Believed principal inertia [kg·m²].
    pub inertia_kg_m2: Vec3,
    /// Gains.
    pub gains: HoverGains,
}

impl HoverController {
    /// Thrust and torque that track `sp` from `x`.
    pub fn update(&self, x: &VehicleState, sp: &FlatSetpoint) -> Wrench {
        let g = &self.gains;
        let e_p = sp.pos_w.map_or(Vec3::zeros(), |p| x.pos_w - p);
        let e_v = x.vel_w - sp.vel_w.unwrap_or_default();
        let acc = sp.acc_w.unwrap_or_default() - g.kp_per_s2 * e_p - g.kd_per_s * e_v;
        // Force the rotors must supply: m v̇ = m g e3 + A  ⇒  A = m (v̇_d − g e3) (control.md §5).
        let mut a = self.mass_kg * (acc - GRAVITY_M_S2 * e3());
        a.z = a.z.min(-0.2 * self.mass_kg * GRAVITY_M_S2);
        let horizontal = a.xy().norm();
        let limit = g.tilt_max_rad.tan() * a.z.abs();
        if horizontal > limit {
            let s = limit / horizontal;
            a.x *= s;
            a.y *= s;
        }
        let r = &x.r_wb;
        let thrust_n = (-a.dot(&(r * e3()))).max(0.0);
        let z_d = -a / a.norm();
        let yaw = sp.yaw_rad.unwrap_or(0.0);
        let x_c = Vec3::new(yaw.cos(), yaw.sin(), 0.0);
        let y_d = z_d.cross(&x_c).normalize();
        let r_d = Mat3::from_columns(&[y_d.cross(&z_d), y_d, z_d]);
        let e_r = 0.5 * vee(&(r_d.transpose() * r - r.transpose() * r_d));
        let i = &self.inertia_kg_m2;
        let w = &x.omega_b;
        let torque_b = i.component_mul(&(-g.k_att_per_s2 * e_r - g.k_rate_per_s * w)) + w.cross(&i.component_mul(w));
        Wrench { thrust_n, torque_b }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ctrl() -> HoverController {
        HoverController {
            mass_kg: 1.5,
            inertia_kg_m2: Vec3::new(0.03, 0.03, 0.05),
            gains: HoverGains::default(),
        }
    }

    fn at(pos: Vec3) -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w: pos,
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    #[test]
    fn hover_needs_weight_and_no_torque() {
        let w = ctrl().update(&at(Vec3::zeros()), &FlatSetpoint::hold(Vec3::zeros(), 0.0));
        assert!((w.thrust_n - 1.5 * GRAVITY_M_S2).abs() < 1e-12);
        assert!(w.torque_b.norm() < 1e-12);
    }

    #[test]
    fn too_low_means_more_thrust_and_north_error_pitches_nose_down() {
        let c = ctrl();
        let low = c.update(&at(Vec3::new(0.0, 0.0, 1.0)), &FlatSetpoint::hold(Vec3::zeros(), 0.0));
        assert!(low.thrust_n > 1.5 * GRAVITY_M_S2);
        // Setpoint north of the vehicle: accelerate north, which in FRD is a negative pitch torque.
        let north = c.update(&at(Vec3::zeros()), &FlatSetpoint::hold(Vec3::new(1.0, 0.0, 0.0), 0.0));
        assert!(north.torque_b.y < 0.0);
        let east = c.update(&at(Vec3::zeros()), &FlatSetpoint::hold(Vec3::new(0.0, 1.0, 0.0), 0.0));
        assert!(east.torque_b.x > 0.0);
    }
}
