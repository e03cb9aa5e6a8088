//! Gains and limits of the three controllers, with units, and their defaults.
//!
//! The defaults are the homework's (docs/control.md §7), tuned for the homework vehicle
//! `fsr_quad`: m = 1.5 kg,
//! I_b = diag(1.2416, 1.2416, 2.4832) kg·m². For another airframe [`ControllerGains::for_vehicle`]
//! keeps the natural frequencies and damping ratios of that tuning: gains in force units scale
//! with the mass, gains in torque units with the inertia of each axis (`K_R = I_b ω_n²`,
//! `K_ω = 2 ζ I_b ω_n`, docs/control.md §7, eqs. (7.1)–(7.2)). On `fsr_quad` they are exactly
//! the homework's.

use serde::{Deserialize, Serialize};

use crate::math::Vec3;

/// Mass of the vehicle the homework gains were tuned for [kg].
pub const REFERENCE_MASS_KG: f64 = 1.5;
/// Principal inertia of the vehicle the homework gains were tuned for [kg·m²].
pub const REFERENCE_INERTIA_KG_M2: [f64; 3] = [1.2416, 1.2416, 2.4832];

/// What the controller believes about the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleModel {
    /// Nominal mass m [kg].
    pub mass_kg: f64,
    /// Nominal principal inertia I_b [kg·m²].
    pub inertia_kg_m2: Vec3,
    /// Largest collective thrust of the rotors [N].
    pub thrust_max_n: f64,
}

#[cfg(test)]
impl VehicleModel {
    /// The homework vehicle `fsr_quad` (reference mass and inertia) with full thrust
    /// `thrust_max_n` [N].
    pub(crate) fn homework(thrust_max_n: f64) -> Self {
        Self {
            mass_kg: REFERENCE_MASS_KG,
            inertia_kg_m2: Vec3::from(REFERENCE_INERTIA_KG_M2),
            thrust_max_n,
        }
    }
}

/// Geometric controller gains (docs/control.md §5, §7), force and torque units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometricGains {
    /// K_p, position stiffness per axis [N/m].
    pub kp: Vec3,
    /// K_v, velocity damping per axis [N·s/m].
    pub kv: Vec3,
    /// K_R, attitude stiffness per body axis [N·m/rad].
    pub kr: Vec3,
    /// K_ω, angular-rate damping per body axis [N·m·s/rad].
    pub komega: Vec3,
}

/// Hierarchical controller gains (docs/control.md §4, §7), per unit mass and per unit inertia
/// (feedback linearisation makes them vehicle-independent).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HierarchicalGains {
    /// K_P, position stiffness per unit mass [1/s²].
    pub kp: Vec3,
    /// K_D, velocity damping per unit mass [1/s].
    pub kd: Vec3,
    /// K_η, attitude stiffness per unit inertia [1/s²].
    pub k_eta: Vec3,
    /// K_ė, attitude-rate damping per unit inertia [1/s].
    pub k_eta_dot: Vec3,
}

/// Passivity-based controller gains (docs/control.md §6, §7).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassivityGains {
    /// σ, coupling between e_η and ė_η [1/s].
    pub sigma: f64,
    /// D_a, angular damping per η axis [N·m·s/rad].
    pub d_a: Vec3,
    /// K_a, angular stiffness per η axis [N·m/rad].
    pub k_a: Vec3,
    /// D_o, linear damping per axis [N·s/m].
    pub d_o: Vec3,
    /// K_o, linear stiffness per axis [N/m].
    pub k_o: Vec3,
}

/// Guards shared by the laws (docs/control.md §8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlLimits {
    /// Largest tilt of the commanded thrust direction [rad].
    pub tilt_max_rad: f64,
    /// ε_z: the commanded acceleration keeps at least this much upward thrust [m/s²].
    pub eps_z_m_s2: f64,
    /// ε_A: below this ‖A‖ the geometric law keeps the previous thrust direction [N].
    pub eps_a_n: f64,
    /// RPY laws hold their last output when |cos θ| falls below this [-].
    pub cos_theta_min: f64,
    /// Time constant τ_f of the filtered derivatives [s].
    pub derivative_tau_s: f64,
}

impl Default for ControlLimits {
    /// Tilt ≤ 40°, ε_z = 0.5 m/s², ε_A = 1e-3 N, |cos θ| ≥ 0.05 (θ within ±87°), τ_f = 20 ms.
    fn default() -> Self {
        Self {
            tilt_max_rad: 40f64.to_radians(),
            eps_z_m_s2: 0.5,
            eps_a_n: 1e-3,
            cos_theta_min: 0.05,
            derivative_tau_s: 0.02,
        }
    }
}

/// Gains of every law; the active one is chosen elsewhere, so a switch is bumpless in gains.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerGains {
    /// Geometric law.
    pub geometric: GeometricGains,
    /// Hierarchical law.
    pub hierarchical: HierarchicalGains,
    /// Passivity-based law.
    pub passivity: PassivityGains,
    /// Guards.
    pub limits: ControlLimits,
}

impl Default for ControllerGains {
    /// The homework's gains for `fsr_quad`.
    fn default() -> Self {
        Self {
            geometric: GeometricGains {
                kp: Vec3::new(20.0, 20.0, 25.0),
                kv: Vec3::repeat(10.0),
                kr: Vec3::new(180.0, 180.0, 200.0),
                komega: Vec3::repeat(30.0),
            },
            hierarchical: HierarchicalGains {
                kp: Vec3::repeat(4.0),
                kd: Vec3::repeat(4.0),
                k_eta: Vec3::repeat(100.0),
                k_eta_dot: Vec3::repeat(20.0),
            },
            passivity: PassivityGains {
                sigma: 5.0,
                d_a: Vec3::repeat(20.0),
                k_a: Vec3::repeat(100.0),
                d_o: Vec3::repeat(6.0),
                k_o: Vec3::repeat(6.0),
            },
            limits: ControlLimits::default(),
        }
    }
}

impl ControllerGains {
    /// The homework tuning carried over to `vehicle`: same natural frequencies and damping.
    pub fn for_vehicle(vehicle: &VehicleModel) -> Self {
        let base = Self::default();
        let m = vehicle.mass_kg / REFERENCE_MASS_KG;
        let i = vehicle
            .inertia_kg_m2
            .component_div(&Vec3::from(REFERENCE_INERTIA_KG_M2));
        Self {
            geometric: GeometricGains {
                kp: base.geometric.kp * m,
                kv: base.geometric.kv * m,
                kr: base.geometric.kr.component_mul(&i),
                komega: base.geometric.komega.component_mul(&i),
            },
            hierarchical: base.hierarchical,
            passivity: PassivityGains {
                d_a: base.passivity.d_a.component_mul(&i),
                k_a: base.passivity.k_a.component_mul(&i),
                d_o: base.passivity.d_o * m,
                k_o: base.passivity.k_o * m,
                ..base.passivity
            },
            limits: base.limits,
        }
    }

    /// Every gain and limit positive and finite; otherwise the name of the first bad one.
    pub fn validate(&self) -> Result<(), String> {
        let g = &self.geometric;
        let h = &self.hierarchical;
        let p = &self.passivity;
        let l = &self.limits;
        let vectors = [
            ("geometric", ["kp", "kv", "kr", "komega"], [g.kp, g.kv, g.kr, g.komega]),
            (
                "hierarchical",
                ["kp", "kd", "k_eta", "k_eta_dot"],
                [h.kp, h.kd, h.k_eta, h.k_eta_dot],
            ),
            ("passivity", ["d_a", "k_a", "d_o", "k_o"], [p.d_a, p.k_a, p.d_o, p.k_o]),
        ];
        let positive = |x: &f64| x.is_finite() && *x > 0.0;
        for (law, names, values) in vectors {
            for (name, v) in names.into_iter().zip(values) {
                if !v.iter().all(positive) {
                    return Err(format!(
                        "{law}.{name}: every component must be a positive number, got {v:?}"
                    ));
                }
            }
        }
        let scalars = [
            ("passivity.sigma", p.sigma),
            ("limits.eps_z_m_s2", l.eps_z_m_s2),
            ("limits.eps_a_n", l.eps_a_n),
            ("limits.cos_theta_min", l.cos_theta_min),
            ("limits.derivative_tau_s", l.derivative_tau_s),
        ];
        if let Some((name, x)) = scalars.into_iter().find(|(_, x)| !positive(x)) {
            return Err(format!("{name}: must be a positive number, got {x}"));
        }
        if !(l.tilt_max_rad > 0.0 && l.tilt_max_rad < 80f64.to_radians()) {
            return Err(format!(
                "limits.tilt_max_rad: must be in (0, 80°), got {}",
                l.tilt_max_rad
            ));
        }
        if l.cos_theta_min >= 1.0 {
            return Err("limits.cos_theta_min: must be below 1".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn homework_vehicle_gets_the_homework_gains_and_others_keep_frequencies() {
        let fsr = VehicleModel::homework(28.0);
        assert_eq!(ControllerGains::for_vehicle(&fsr), ControllerGains::default());
        let iris = VehicleModel {
            mass_kg: 1.5,
            inertia_kg_m2: Vec3::new(0.029125, 0.029125, 0.055225),
            thrust_max_n: 28.0,
        };
        let g = ControllerGains::for_vehicle(&iris);
        // Roll: ω_n = √(K_R / I) = 12.04 rad/s on both.
        let wn = |kr: f64, i: f64| (kr / i).sqrt();
        assert!((wn(g.geometric.kr.x, 0.029125) - wn(180.0, 1.2416)).abs() < 1e-12);
        assert_eq!(g.geometric.kp, Vec3::new(20.0, 20.0, 25.0));
        assert!(g.validate().is_ok());
    }

    #[test]
    fn validation_names_the_bad_gain() {
        let mut g = ControllerGains::default();
        g.passivity.k_a.y = -1.0;
        assert!(g.validate().unwrap_err().starts_with("passivity.k_a"));
        let mut g = ControllerGains::default();
        g.limits.tilt_max_rad = 2.0;
        assert!(g.validate().unwrap_err().starts_with("limits.tilt_max_rad"));
    }
}
