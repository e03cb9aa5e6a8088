//! Rotor thrust and drag torque, and the first-order motor lag (docs/model.md §4, eqs. (4.1)–(4.5)).
//!
//! `T_i = c_T ω_i² k_i` along −z_b, where k_i is the ground/ceiling factor, and drag torque
//! `Q_i = c_Q ω_i²` whose reaction on the body is `s_i Q_i e3`. Motor speed follows
//! `ω̇ = (ω_cmd − ω)/τ` with τ = τ_up when speeding up and τ_down when slowing down; the
//! plant uses the exact solution `ω(t) = ω_cmd + (ω_0 − ω_cmd) e^{−t/τ}` over each step, so the
//! RK4 stages see the true motor speed at their time.

use nalgebra::Vector3;

use crate::params::{RotorConstants, RotorGeometry};

/// Motor speeds and their values at the RK4 stage times of the current step.
#[derive(Debug, Clone)]
pub struct MotorBank {
    speeds: Vec<f64>,
    at_half: Vec<f64>,
    at_end: Vec<f64>,
    decay: Decay,
}

/// Cached `e^{−h/τ}` for the current step length.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Decay {
    dt_s: f64,
    up_half: f64,
    up_full: f64,
    down_half: f64,
    down_full: f64,
}

impl Decay {
    fn new(c: &RotorConstants, dt_s: f64) -> Self {
        let e = |tau: f64, h: f64| if tau > 0.0 { (-h / tau).exp() } else { 0.0 };
        Self {
            dt_s,
            up_half: e(c.tau_up_s, 0.5 * dt_s),
            up_full: e(c.tau_up_s, dt_s),
            down_half: e(c.tau_down_s, 0.5 * dt_s),
            down_full: e(c.tau_down_s, dt_s),
        }
    }
}

impl MotorBank {
    /// `n` motors at rest.
    pub fn new(n: usize, c: &RotorConstants) -> Self {
        Self {
            speeds: vec![0.0; n],
            at_half: vec![0.0; n],
            at_end: vec![0.0; n],
            decay: Decay::new(c, 1e-3),
        }
    }

    /// Current motor speeds [rad/s].
    pub fn speeds(&self) -> &[f64] {
        &self.speeds
    }

    /// Motor speeds at mid-step [rad/s], valid after [`Self::plan`].
    pub fn at_half(&self) -> &[f64] {
        &self.at_half
    }

    /// Motor speeds at the end of the step [rad/s], valid after [`Self::plan`].
    pub fn at_end(&self) -> &[f64] {
        &self.at_end
    }

    /// Computes the speeds at `dt/2` and `dt` for commands `cmd` [rad/s], already clamped to
    /// the motor limits and finite.
    pub fn plan(&mut self, cmd: &[f64], c: &RotorConstants, dt_s: f64) {
        if self.decay.dt_s != dt_s {
            self.decay = Decay::new(c, dt_s);
        }
        let d = self.decay;
        for (i, (&w0, &wc)) in self.speeds.iter().zip(cmd).enumerate() {
            let (half, full) = if wc >= w0 {
                (d.up_half, d.up_full)
            } else {
                (d.down_half, d.down_full)
            };
            self.at_half[i] = wc + (w0 - wc) * half;
            self.at_end[i] = wc + (w0 - wc) * full;
        }
    }

    /// Sets the current speeds directly [rad/s] (already clamped).
    pub fn set(&mut self, omega_rad_s: &[f64]) {
        for (s, w) in self.speeds.iter_mut().zip(omega_rad_s) {
            *s = *w;
        }
    }

    /// Ends the step: the end-of-step speeds become the current ones.
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.speeds, &mut self.at_end);
    }
}

/// Body force [N] and torque [N·m] of all rotors at speeds `omega` [rad/s] with thrust factors
/// `factor` [-], from each hub position: `Σ r_i × (−T_i e3) + s_i Q_i e3`.
pub fn rotor_wrench_b(
    rotors: &[RotorGeometry],
    c: &RotorConstants,
    omega: &[f64],
    factor: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let mut thrust = 0.0;
    let mut torque = Vector3::zeros();
    for ((r, &w), &k) in rotors.iter().zip(omega).zip(factor) {
        let w2 = w * w;
        let t = c.c_t * w2 * k;
        let f = Vector3::new(0.0, 0.0, -t);
        torque += r.hub_b.cross(&f);
        torque.z += r.reaction_sign * c.c_q * w2;
        thrust += t;
    }
    (Vector3::new(0.0, 0.0, -thrust), torque)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constants(tau_up: f64, tau_down: f64) -> RotorConstants {
        RotorConstants {
            radius_m: 0.1,
            c_t: 1e-5,
            c_q: 1e-7,
            omega_min_rad_s: 0.0,
            omega_max_rad_s: 1000.0,
            tau_up_s: tau_up,
            tau_down_s: tau_down,
        }
    }

    #[test]
    fn lag_is_exact_first_order_with_separate_constants() {
        let c = constants(0.01, 0.03);
        let mut m = MotorBank::new(1, &c);
        m.plan(&[500.0], &c, 1e-3);
        assert!((m.at_end()[0] - 500.0 * (1.0 - (-0.1f64).exp())).abs() < 1e-9);
        for _ in 0..1000 {
            m.plan(&[500.0], &c, 1e-3);
            m.commit();
        }
        assert!((m.speeds()[0] - 500.0).abs() < 1e-6);
        m.plan(&[0.0], &c, 1e-3);
        assert!((m.at_end()[0] - 500.0 * (-1e-3f64 / 0.03).exp()).abs() < 1e-9);
    }

    #[test]
    fn zero_time_constant_is_instant() {
        let c = constants(0.0, 0.0);
        let mut m = MotorBank::new(2, &c);
        m.plan(&[300.0, 10.0], &c, 1e-3);
        assert_eq!(m.at_half(), &[300.0, 10.0]);
    }

    #[test]
    fn wrench_of_single_rotor() {
        let c = constants(0.0, 0.0);
        let r = [RotorGeometry {
            hub_b: Vector3::new(0.2, 0.0, 0.0),
            reaction_sign: -1.0,
        }];
        let (f, t) = rotor_wrench_b(&r, &c, &[100.0], &[1.0]);
        assert!((f.z + 0.1).abs() < 1e-12);
        // A rotor ahead of the CoM pitches the nose up: positive τy in FRD.
        assert!((t.y - 0.02).abs() < 1e-12);
        assert!((t.z + 1e-3).abs() < 1e-15);
    }
}
