//! Momentum-based estimator of order r of the external wrench (Ruggiero et al.;
//! docs/estimator.md §1–§5).
//!
//! Generalized momentum `q = [m ṗ_b ; M(η) η̇]`, `q̇ = β + w` with
//! `β = [m g e3 − u_T R_b(η) e3 ; Cᵀ(η, η̇) η̇ + Qᵀ τ_b]` (docs/estimator.md §1, eqs. (1.1)–(1.3)).
//! Forward-Euler (Jacobi) update at Ts (docs/estimator.md §4), using only previous-tick values
//! inside the chain:
//!
//! ```text
//! γ_1[k] = γ_1[k−1] + K_1 ( q_k − q_{k−1} − Ts (ŵ_{k−1} + β_{k−1}) )          (4.3)
//! γ_i[k] = γ_i[k−1] + K_i Ts ( γ_{i−1}[k−1] − ŵ_{k−1} ),   i = 2 … r           (4.4)
//! ŵ_k = γ_r[k]                                                                 (4.5)
//! ```
//!
//! The force is in world NED, the torque in η coordinates (`τ̂_e^b = Q⁻ᵀ τ̂_e` in body FRD), and
//! the mass estimate is `m_r = m_e + f̂_ez / g` (docs/estimator.md §5, eqs. (5.1)–(5.3)). The
//! thrust and torque fed in must be the *applied* ones (`G_q ω²` after saturation,
//! docs/allocation.md §4).

use nalgebra::Vector6;
use thiserror::Error;

use crate::math::{e3, Mat3, Vec3, GRAVITY_M_S2};
use crate::rpy;

use super::WrenchEstimate;

/// |cos θ| below which the body torque falls back to the η-space torque (RPY singularity).
const COS_THETA_MIN: f64 = 1e-3;

/// An estimator that cannot be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ObserverError {
    /// No gains, or a gain that is not a positive finite number.
    #[error("estimator gains must be 1 to 20 positive numbers, got {0:?}")]
    Gains(Vec<f64>),
    /// Sample time not a positive finite number.
    #[error("sample time {0} s must be a positive number")]
    SampleTime(f64),
    /// Nominal mass or inertia not positive.
    #[error("nominal mass and inertia must be positive")]
    MassProperties,
}

/// Measurements and applied inputs of one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObserverInput {
    /// Linear velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Roll, pitch, yaw (ZYX) [rad].
    pub eta: Vec3,
    /// Euler-angle rates [rad/s].
    pub eta_dot: Vec3,
    /// Applied collective thrust [N].
    pub thrust_n: f64,
    /// Applied body torque, FRD [N·m].
    pub torque_b: Vec3,
}

/// Momentum-based wrench estimator of order r = number of gains.
#[derive(Debug, Clone, PartialEq)]
pub struct WrenchObserver {
    mass_kg: f64,
    inertia: Mat3,
    ts_s: f64,
    gains: Vec<f64>,
    gamma: Vec<Vector6<f64>>,
    previous_q: Option<Vector6<f64>>,
    previous_beta: Option<Vector6<f64>>,
    pending: Option<(Vec3, Vec3)>,
    last: WrenchEstimate,
    held: bool,
}

impl WrenchObserver {
    /// Estimator with nominal mass `mass_kg` [kg], principal inertia `inertia_kg_m2` [kg·m²],
    /// gains K_1 … K_r [1/s] and sample time `ts_s` [s].
    pub fn new(mass_kg: f64, inertia_kg_m2: Vec3, gains: Vec<f64>, ts_s: f64) -> Result<Self, ObserverError> {
        if gains.is_empty() || gains.len() > super::MAX_ORDER || gains.iter().any(|k| !(k.is_finite() && *k > 0.0)) {
            return Err(ObserverError::Gains(gains));
        }
        if !(ts_s.is_finite() && ts_s > 0.0) {
            return Err(ObserverError::SampleTime(ts_s));
        }
        if !(mass_kg > 0.0 && inertia_kg_m2.iter().all(|i| *i > 0.0)) {
            return Err(ObserverError::MassProperties);
        }
        let r = gains.len();
        Ok(Self {
            mass_kg,
            inertia: Mat3::from_diagonal(&inertia_kg_m2),
            ts_s,
            gains,
            gamma: vec![Vector6::zeros(); r],
            previous_q: None,
            previous_beta: None,
            pending: None,
            last: WrenchEstimate::zero(mass_kg),
            held: false,
        })
    }

    /// Order r.
    pub fn order(&self) -> usize {
        self.gains.len()
    }

    /// Latest estimate.
    pub fn estimate(&self) -> WrenchEstimate {
        self.last
    }

    /// True when the last observation's input was not finite and the previous estimate was held.
    pub fn held(&self) -> bool {
        self.held
    }

    /// Forgets everything: the next update restarts from ŵ = 0 with a new q(0).
    pub fn reset(&mut self) {
        self.gamma.iter_mut().for_each(|g| *g = Vector6::zeros());
        self.previous_q = None;
        self.previous_beta = None;
        self.pending = None;
        self.last = WrenchEstimate::zero(self.mass_kg);
        self.held = false;
    }

    /// One tick of docs/estimator.md §4 with this tick's measurements and applied inputs:
    /// [`observe`](Self::observe)
    /// then [`apply`](Self::apply). Used when the applied inputs of tick k are known together with
    /// its measurements (offline logs).
    pub fn update(&mut self, x: &ObserverInput) -> WrenchEstimate {
        let est = self.observe(&x.vel_w, &x.eta, &x.eta_dot);
        self.apply(x.thrust_n, &x.torque_b);
        est
    }

    /// First half of a closed-loop tick: ŵ_k from this tick's momentum q_k and the previous
    /// tick's β_{k−1} (docs/estimator.md §6), before the controller runs. Non-finite input holds
    /// the previous estimate.
    pub fn observe(&mut self, vel_w: &Vec3, eta: &Vec3, eta_dot: &Vec3) -> WrenchEstimate {
        let all_finite = |v: &Vec3| v.iter().all(|c| c.is_finite());
        let finite = all_finite(vel_w) && all_finite(eta) && all_finite(eta_dot);
        self.held = !finite;
        if !finite {
            self.pending = None;
            return self.last;
        }
        let q_k = stack(
            &(self.mass_kg * vel_w),
            &(rpy::mass_matrix(eta, &self.inertia) * eta_dot),
        );
        self.pending = Some((*eta, *eta_dot));
        let previous_q = self.previous_q.replace(q_k);
        if let (Some(q_prev), Some(beta_prev)) = (previous_q, self.previous_beta) {
            let w_prev = self.gamma[self.gamma.len() - 1];
            // Descending, so γ_{i−1} is still the previous tick's value when γ_i reads it.
            for i in (1..self.gamma.len()).rev() {
                let step = self.gains[i] * self.ts_s * (self.gamma[i - 1] - w_prev);
                self.gamma[i] += step;
            }
            self.gamma[0] += self.gains[0] * (q_k - q_prev - self.ts_s * (w_prev + beta_prev));
        }
        self.publish(eta)
    }

    /// Second half of a closed-loop tick: β_k from the state given to the last
    /// [`observe`](Self::observe) and the *applied* thrust `thrust_n` [N] and body torque
    /// `torque_b` [N·m] (docs/allocation.md §4), kept for tick k+1:
    /// `β = [m g e3 − u_T R_b(η) e3 ; Cᵀ(η, η̇) η̇ + Qᵀ τ_b]` (docs/estimator.md §4, eq. (4.2)).
    /// Ignored when the
    /// observation was held or the inputs are not finite (β_{k−1} is kept).
    pub fn apply(&mut self, thrust_n: f64, torque_b: &Vec3) {
        let Some((eta, eta_dot)) = self.pending.take() else {
            return;
        };
        if !(thrust_n.is_finite() && torque_b.iter().all(|v| v.is_finite())) {
            return;
        }
        let lin_b = self.mass_kg * GRAVITY_M_S2 * e3() - thrust_n * (rpy::rotation(&eta) * e3());
        let c = rpy::coriolis(&eta, &eta_dot, &self.inertia);
        let ang_b = c.transpose() * eta_dot + rpy::q_matrix(&eta).transpose() * torque_b;
        self.previous_beta = Some(stack(&lin_b, &ang_b));
    }

    fn publish(&mut self, eta: &Vec3) -> WrenchEstimate {
        let w = self.gamma[self.gamma.len() - 1];
        let force_w = Vec3::new(w[0], w[1], w[2]);
        let torque_eta = Vec3::new(w[3], w[4], w[5]);
        let torque_b = if eta.y.cos().abs() > COS_THETA_MIN {
            rpy::q_matrix(eta)
                .transpose()
                .try_inverse()
                .map_or(torque_eta, |m| m * torque_eta)
        } else {
            torque_eta
        };
        self.last = WrenchEstimate {
            force_w,
            torque_b,
            mass_kg: self.mass_kg + force_w.z / GRAVITY_M_S2,
        };
        self.last
    }
}

fn stack(a: &Vec3, b: &Vec3) -> Vector6<f64> {
    Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wrench_estimator::ChebyshevDesign;

    /// A vehicle held level by a thrust equal to the believed weight, pushed by `f_e` and
    /// `τ_e`, integrated exactly at Ts: the estimate must converge to (f_e, τ_e) and the mass
    /// to the true mass.
    fn converge(order: usize, wp: f64, seconds: f64) -> WrenchEstimate {
        let ts = 1e-3;
        let (m_nom, m_true) = (1.5, 1.7);
        let inertia = Vec3::new(1.2416, 1.2416, 2.4832);
        let gains = ChebyshevDesign {
            order,
            ripple_db: 3.0,
            passband_rad_s: wp,
        }
        .gains(ts)
        .unwrap();
        let mut obs = WrenchObserver::new(m_nom, inertia, gains, ts).unwrap();
        let f_e = Vec3::new(0.5, 0.5, 0.0);
        let tau_z = 0.2;
        let thrust = m_nom * GRAVITY_M_S2;
        let (mut vel, mut yaw_rate) = (Vec3::zeros(), 0.0);
        let mut est = obs.estimate();
        for _ in 0..(seconds / ts) as usize {
            let eta = Vec3::new(0.0, 0.0, 0.0);
            est = obs.update(&ObserverInput {
                vel_w: vel,
                eta,
                eta_dot: Vec3::new(0.0, 0.0, yaw_rate),
                thrust_n: thrust,
                torque_b: Vec3::zeros(),
            });
            // Exact dynamics of the true vehicle under constant inputs (level, yaw spinning up).
            vel += ts * ((m_true * GRAVITY_M_S2 - thrust) * e3() + f_e) / m_true;
            yaw_rate += ts * tau_z / inertia.z;
        }
        est
    }

    #[test]
    fn first_order_recovers_what_the_nominal_model_cannot_explain() {
        let est = converge(1, 2.0, 10.0);
        let mg_gap = 0.2 * GRAVITY_M_S2;
        // f̂ = f_e + (m_r − m_e)(g e3 − p̈): horizontally the nominal mass sees m_e/m_r of f_e.
        assert!((est.force_w.x - 0.5 * 1.5 / 1.7).abs() < 1e-3, "{:?}", est.force_w);
        assert!(
            (est.force_w.z - mg_gap * (1.0 - (1.7 * GRAVITY_M_S2 - 1.5 * GRAVITY_M_S2) / (1.7 * GRAVITY_M_S2))).abs()
                < 5e-3
        );
        // Level (η = 0, Q = I): the body torque is the η-space torque.
        assert!((est.torque_b.z - 0.2).abs() < 1e-6, "{:?}", est.torque_b);
    }

    #[test]
    fn high_order_forward_euler_is_stable() {
        // Order 13 at Wp = 10 (below the 16.5 rad/s bound): the in-sample update would diverge.
        let est = converge(13, 10.0, 40.0);
        assert!(est.torque_b.iter().all(|x| x.is_finite()));
        assert!((est.torque_b.z - 0.2).abs() < 2e-3, "{:?}", est.torque_b);
    }

    #[test]
    fn step_response_of_order_one_is_first_order() {
        let ts = 1e-3;
        let k1 = 5.0;
        let mut obs = WrenchObserver::new(1.0, Vec3::new(1.0, 1.0, 1.0), vec![k1], ts).unwrap();
        // Free-floating body with thrust = weight and a unit force along x from t = 0.
        let mut vel = Vec3::zeros();
        let mut est = obs.estimate();
        for _ in 0..200 {
            est = obs.update(&ObserverInput {
                vel_w: vel,
                eta: Vec3::zeros(),
                eta_dot: Vec3::zeros(),
                thrust_n: GRAVITY_M_S2,
                torque_b: Vec3::zeros(),
            });
            vel.x += ts * 1.0;
        }
        // Discrete pole 1 − K Ts: after n ticks 1 − (1 − K Ts)^(n−1).
        let expected = 1.0 - (1.0 - k1 * ts).powi(199);
        assert!(
            (est.force_w.x - expected).abs() < 1e-9,
            "{} vs {expected}",
            est.force_w.x
        );
    }

    #[test]
    fn bad_input_is_held_and_bad_gains_refused() {
        let mut obs = WrenchObserver::new(1.5, Vec3::new(1.0, 1.0, 2.0), vec![2.0], 1e-3).unwrap();
        let bad = ObserverInput {
            vel_w: Vec3::new(f64::NAN, 0.0, 0.0),
            eta: Vec3::zeros(),
            eta_dot: Vec3::zeros(),
            thrust_n: 1.0,
            torque_b: Vec3::zeros(),
        };
        obs.update(&bad);
        assert!(obs.held());
        assert!(WrenchObserver::new(1.5, Vec3::new(1.0, 1.0, 2.0), vec![], 1e-3).is_err());
        assert!(WrenchObserver::new(1.5, Vec3::new(1.0, 1.0, 2.0), vec![-1.0], 1e-3).is_err());
        assert!(WrenchObserver::new(1.5, Vec3::new(1.0, 1.0, 2.0), vec![1.0], 0.0).is_err());
    }
}
