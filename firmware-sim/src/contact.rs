//! Ground and ceiling contact: the vehicle rests on the ground without sinking or bouncing and
//! takes off as soon as its thrust exceeds its weight.
//!
//! The landing gear is rigid and the contact perfectly inelastic with sticking friction: once
//! the centre of mass is at or below `gear_height` above the ground while not climbing, the
//! vehicle is placed on the ground, level at its current heading, at rest. A step whose
//! integration moves it up (thrust above weight) leaves it untouched, so take-off needs no
//! special case. The ceiling stops upward motion when a rotor hub reaches it.

use nalgebra::{UnitQuaternion, Vector3};

use crate::rigid_body::RigidBodyState;

/// Contact geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Ground plane as a NED z coordinate [m].
    pub ground_z_m: f64,
    /// Height of the centre of mass above the ground when resting level [m].
    pub gear_height_m: f64,
    /// Ceiling plane as a NED z coordinate [m], if any.
    pub ceiling_z_m: Option<f64>,
}

impl Contact {
    /// NED z of the centre of mass when resting on the ground [m].
    pub fn resting_z_m(&self) -> f64 {
        self.ground_z_m - self.gear_height_m
    }

    /// Applies ground contact to the state after a step; returns true when resting on the ground.
    pub fn resolve_ground(&self, s: &mut RigidBodyState) -> bool {
        let z_rest = self.resting_z_m();
        if s.pos_w.z < z_rest || s.vel_w.z < 0.0 {
            return false;
        }
        s.pos_w.z = z_rest;
        s.vel_w = Vector3::zeros();
        s.omega_b = Vector3::zeros();
        let (_, _, yaw) = s.q_wb.euler_angles();
        s.q_wb = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        true
    }

    /// Stops upward motion when the highest hub (NED z `top_z_m` [m]) touches the ceiling;
    /// returns true while touching.
    pub fn resolve_ceiling(&self, s: &mut RigidBodyState, top_z_m: f64) -> bool {
        let Some(ceiling) = self.ceiling_z_m else { return false };
        if top_z_m > ceiling || s.vel_w.z > 0.0 {
            return false;
        }
        s.pos_w.z += ceiling - top_z_m;
        s.vel_w.z = 0.0;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(z: f64, vz: f64) -> RigidBodyState {
        RigidBodyState {
            pos_w: Vector3::new(1.0, 2.0, z),
            vel_w: Vector3::new(0.3, 0.0, vz),
            q_wb: UnitQuaternion::from_euler_angles(0.1, 0.05, 0.7),
            omega_b: Vector3::new(0.1, 0.2, 0.3),
        }
    }

    #[test]
    fn landing_stops_and_levels_keeping_heading() {
        let c = Contact {
            ground_z_m: 0.0,
            gear_height_m: 0.1,
            ceiling_z_m: None,
        };
        let mut s = state(-0.09, 0.5);
        assert!(c.resolve_ground(&mut s));
        assert_eq!(s.pos_w.z, -0.1);
        assert_eq!(s.vel_w, Vector3::zeros());
        let (r, p, y) = s.q_wb.euler_angles();
        assert!(r.abs() < 1e-12 && p.abs() < 1e-12 && (y - 0.7).abs() < 1e-12);
    }

    #[test]
    fn climbing_or_airborne_is_untouched() {
        let c = Contact {
            ground_z_m: 0.0,
            gear_height_m: 0.1,
            ceiling_z_m: None,
        };
        let mut s = state(-0.0999, -0.01);
        let before = s;
        assert!(!c.resolve_ground(&mut s));
        assert_eq!(s, before);
        let mut s = state(-2.0, 1.0);
        assert!(!c.resolve_ground(&mut s));
    }

    #[test]
    fn ceiling_stops_upward_motion() {
        let c = Contact {
            ground_z_m: 0.0,
            gear_height_m: 0.1,
            ceiling_z_m: Some(-3.0),
        };
        let mut s = state(-2.9, -1.0);
        assert!(c.resolve_ceiling(&mut s, -3.05));
        assert!((s.pos_w.z + 2.85).abs() < 1e-12);
        assert_eq!(s.vel_w.z, 0.0);
    }
}
