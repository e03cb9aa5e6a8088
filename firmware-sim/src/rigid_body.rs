//! 6-DoF rigid body in NED world / FRD body, integrated with fixed-step RK4
//! (docs/model.md §2, eqs. (2.1)–(2.5)).
//!
//! ```text
//! ṗ = v,   m v̇ = m g e3 + f_w,   q̇ = ½ q ⊗ (0, ω),   I ω̇ = −ω × I ω + τ_b
//! ```
//! where `f_w` collects rotor thrust (rotated to world), external force and drag. The quaternion
//! is integrated as a plain 4-vector and renormalised after every step.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::GRAVITY_M_S2;

/// Kinematic state of the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBodyState {
    /// Position in world NED [m].
    pub pos_w: Vector3<f64>,
    /// Velocity in world NED [m/s].
    pub vel_w: Vector3<f64>,
    /// Attitude: maps body FRD vectors to world NED.
    pub q_wb: UnitQuaternion<f64>,
    /// Angular velocity in body FRD [rad/s].
    pub omega_b: Vector3<f64>,
}

/// Forces and torques acting during one RK4 stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageLoads {
    /// Force in world NED, gravity excluded [N].
    pub force_w: Vector3<f64>,
    /// Torque in body FRD [N·m].
    pub torque_b: Vector3<f64>,
}

/// Mass properties.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Mass [kg].
    pub mass_kg: f64,
    /// Principal inertia [kg·m²].
    pub inertia_kg_m2: Vector3<f64>,
}

/// Working state of RK4: the quaternion is not kept unit inside a step.
#[derive(Debug, Clone, Copy)]
struct Raw {
    pos: Vector3<f64>,
    vel: Vector3<f64>,
    quat: Quaternion<f64>,
    omega: Vector3<f64>,
}

impl Raw {
    fn plus(&self, d: &Raw, h: f64) -> Raw {
        Raw {
            pos: self.pos + d.pos * h,
            vel: self.vel + d.vel * h,
            quat: self.quat + d.quat * h,
            omega: self.omega + d.omega * h,
        }
    }

    /// Attitude of a stage: the normalised quaternion (RK4 stages drift off the unit sphere).
    fn attitude(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::new_normalize(self.quat)
    }
}

impl MassProperties {
    fn derivative(&self, s: &Raw, loads: &StageLoads) -> Raw {
        let i = &self.inertia_kg_m2;
        let w = s.omega;
        let iw = i.component_mul(&w);
        let omega_dot = (loads.torque_b - w.cross(&iw)).component_div(i);
        let quat_dot = s.quat * Quaternion::from_imag(w) * 0.5;
        let vel_dot = Vector3::new(0.0, 0.0, GRAVITY_M_S2) + loads.force_w / self.mass_kg;
        Raw {
            pos: s.vel,
            vel: vel_dot,
            quat: quat_dot,
            omega: omega_dot,
        }
    }

    /// One classical RK4 step of length `dt_s` [s]. `loads(stage, state)` gives the loads at
    /// stage 0 (t), 1 and 2 (t + dt/2) and 3 (t + dt) for the stage's state.
    pub fn rk4_step(
        &self,
        s: &RigidBodyState,
        dt_s: f64,
        mut loads: impl FnMut(usize, &RigidBodyState) -> StageLoads,
    ) -> RigidBodyState {
        let x0 = Raw {
            pos: s.pos_w,
            vel: s.vel_w,
            quat: *s.q_wb.quaternion(),
            omega: s.omega_b,
        };
        let mut eval = |stage: usize, x: &Raw| {
            let view = RigidBodyState {
                pos_w: x.pos,
                vel_w: x.vel,
                q_wb: x.attitude(),
                omega_b: x.omega,
            };
            self.derivative(x, &loads(stage, &view))
        };
        let k1 = eval(0, &x0);
        let k2 = eval(1, &x0.plus(&k1, 0.5 * dt_s));
        let k3 = eval(2, &x0.plus(&k2, 0.5 * dt_s));
        let k4 = eval(3, &x0.plus(&k3, dt_s));
        let h6 = dt_s / 6.0;
        let x1 = Raw {
            pos: x0.pos + (k1.pos + (k2.pos + k3.pos) * 2.0 + k4.pos) * h6,
            vel: x0.vel + (k1.vel + (k2.vel + k3.vel) * 2.0 + k4.vel) * h6,
            quat: x0.quat + (k1.quat + (k2.quat + k3.quat) * 2.0 + k4.quat) * h6,
            omega: x0.omega + (k1.omega + (k2.omega + k3.omega) * 2.0 + k4.omega) * h6,
        };
        RigidBodyState {
            pos_w: x1.pos,
            vel_w: x1.vel,
            q_wb: x1.attitude(),
            omega_b: x1.omega,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn free(_: usize, _: &RigidBodyState) -> StageLoads {
        StageLoads {
            force_w: Vector3::zeros(),
            torque_b: Vector3::zeros(),
        }
    }

    /// A body of 1 kg and diagonal inertia `inertia` [kg·m²] at the origin, at rest in
    /// translation, with attitude `q_wb` and body rates `omega_b` [rad/s].
    fn body(inertia: [f64; 3], q_wb: UnitQuaternion<f64>, omega_b: Vector3<f64>) -> (MassProperties, RigidBodyState) {
        let mp = MassProperties {
            mass_kg: 1.0,
            inertia_kg_m2: Vector3::from(inertia),
        };
        let s = RigidBodyState {
            pos_w: Vector3::zeros(),
            vel_w: Vector3::zeros(),
            q_wb,
            omega_b,
        };
        (mp, s)
    }

    #[test]
    fn free_fall_is_exact() {
        let (mp, mut s) = body([1.0; 3], UnitQuaternion::identity(), Vector3::zeros());
        for _ in 0..1000 {
            s = mp.rk4_step(&s, 1e-3, free);
        }
        assert!((s.pos_w.z - 0.5 * GRAVITY_M_S2).abs() < 1e-9);
        assert!((s.vel_w.z - GRAVITY_M_S2).abs() < 1e-9);
    }

    #[test]
    fn torque_free_rotation_keeps_angular_momentum_and_energy() {
        let q_wb = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.0);
        let (mp, mut s) = body([0.03, 0.04, 0.06], q_wb, Vector3::new(2.0, 0.1, 1.5));
        let momentum_w = |s: &RigidBodyState| s.q_wb * mp.inertia_kg_m2.component_mul(&s.omega_b);
        let energy = |s: &RigidBodyState| 0.5 * s.omega_b.dot(&mp.inertia_kg_m2.component_mul(&s.omega_b));
        let (h0, e0) = (momentum_w(&s), energy(&s));
        for _ in 0..10_000 {
            s = mp.rk4_step(&s, 1e-3, free);
        }
        assert!(
            (momentum_w(&s) - h0).norm() / h0.norm() < 1e-9,
            "{}",
            (momentum_w(&s) - h0).norm()
        );
        assert!((energy(&s) - e0).abs() / e0 < 1e-9);
        assert!((s.q_wb.quaternion().norm() - 1.0).abs() < 1e-15);
    }
}
