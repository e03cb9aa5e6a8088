//! Scripted external wrench and aerodynamic drag.
//!
//! A [`Disturbance`] adds a force in world coordinates (NED) [N] and a torque in body
//! coordinates (FRD) [N·m] that is constant, switched on at a time, or sinusoidal. The plant
//! sums every configured component; the flight controller's estimator should recover the sum.

use nalgebra::Vector3;

/// How a disturbance varies in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DisturbanceKind {
    /// Always on.
    Constant,
    /// Zero before `start_s`, full value from `start_s` [s] on.
    Step {
        /// Switch-on time [s].
        start_s: f64,
    },
    /// Value × sin(2π f t + phase).
    Sinusoid {
        /// Frequency f [Hz].
        frequency_hz: f64,
        /// Phase [rad].
        phase_rad: f64,
    },
}

/// One component of the scripted external wrench.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disturbance {
    /// Time profile.
    pub kind: DisturbanceKind,
    /// Force (amplitude for a sinusoid) in world NED [N].
    pub force_w: Vector3<f64>,
    /// Torque (amplitude for a sinusoid) in body FRD [N·m].
    pub torque_b: Vector3<f64>,
}

impl Disturbance {
    /// Scale of the component at time `t_s` [s].
    fn scale(&self, t_s: f64) -> f64 {
        match self.kind {
            DisturbanceKind::Constant => 1.0,
            DisturbanceKind::Step { start_s } => {
                if t_s >= start_s {
                    1.0
                } else {
                    0.0
                }
            }
            DisturbanceKind::Sinusoid {
                frequency_hz,
                phase_rad,
            } => (std::f64::consts::TAU * frequency_hz * t_s + phase_rad).sin(),
        }
    }
}

/// Sum of the components at `t_s` [s]: (force in world NED [N], torque in body FRD [N·m]).
pub fn external_wrench(components: &[Disturbance], t_s: f64) -> (Vector3<f64>, Vector3<f64>) {
    components
        .iter()
        .fold((Vector3::zeros(), Vector3::zeros()), |(f, t), d| {
            let s = d.scale(t_s);
            (f + d.force_w * s, t + d.torque_b * s)
        })
}

/// Drag on the body moving at `v_air_w` relative to the air (world NED [m/s]):
/// f = −R (D_1 v_b + D_2 |v_b| ⊙ v_b) with v_b = Rᵀ v_air, D_1 = diag(`linear_b`) [N·s/m] and
/// D_2 = diag(`quadratic_b`) [N·s²/m²] along the body axes (docs/model.md §5.1, eqs. (5.1)–(5.2));
/// returns the force in world NED [N].
pub fn drag_w(
    linear_b: &Vector3<f64>,
    quadratic_b: &Vector3<f64>,
    r_wb: &nalgebra::Matrix3<f64>,
    v_air_w: &Vector3<f64>,
) -> Vector3<f64> {
    let v_b = r_wb.transpose() * v_air_w;
    let quad_b = quadratic_b.component_mul(&v_b.abs()).component_mul(&v_b);
    -(r_wb * (linear_b.component_mul(&v_b) + quad_b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_sum() {
        let c = Disturbance {
            kind: DisturbanceKind::Constant,
            force_w: Vector3::new(0.5, 0.5, 0.0),
            torque_b: Vector3::zeros(),
        };
        let s = Disturbance {
            kind: DisturbanceKind::Step { start_s: 2.0 },
            force_w: Vector3::zeros(),
            torque_b: Vector3::new(0.0, 0.0, 0.2),
        };
        let w = Disturbance {
            kind: DisturbanceKind::Sinusoid {
                frequency_hz: 1.0,
                phase_rad: 0.0,
            },
            force_w: Vector3::new(0.0, 0.0, 1.0),
            torque_b: Vector3::zeros(),
        };
        let list = [c, s, w];
        let (f, t) = external_wrench(&list, 1.0);
        assert!((f - Vector3::new(0.5, 0.5, 0.0)).norm() < 1e-12);
        assert_eq!(t, Vector3::zeros());
        let (f, t) = external_wrench(&list, 2.25);
        assert!((f.z - 1.0).abs() < 1e-12);
        assert_eq!(t.z, 0.2);
    }

    #[test]
    fn drag_opposes_velocity() {
        let r = nalgebra::Rotation3::from_euler_angles(0.1, -0.2, 0.7).into_inner();
        let v = Vector3::new(1.0, -2.0, 0.5);
        let zero = Vector3::zeros();
        let f = drag_w(&Vector3::new(0.3, 0.3, 0.3), &zero, &r, &v);
        assert!((f + 0.3 * v).norm() < 1e-12);
        let f = drag_w(&Vector3::new(0.1, 0.2, 0.4), &zero, &r, &v);
        assert!(f.dot(&v) < 0.0);
        // Quadratic drag with equal coefficients along axis-aligned motion: c |v| v.
        let level = nalgebra::Matrix3::identity();
        let f = drag_w(&zero, &Vector3::repeat(0.02), &level, &Vector3::new(0.0, -5.0, 0.0));
        assert!((f - Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-12);
    }
}
