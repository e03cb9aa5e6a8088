//! The envelope of a Monte Carlo campaign and seeded draws inside it.
//!
//! One draw is an initial state relative to a hover-at-origin setpoint (heading 0) and a
//! constant external wrench:
//!
//! ```text
//! R_0   = Rot(a, ϑ) Rot(e3, ψ)     a uniform on the horizontal unit circle, ϑ ~ U[0, ϑ_max],
//!                                  ψ ~ U[−π, π): body z is tilted exactly ϑ from the vertical
//! ω_0   = ρ_ω u_ω                  u uniform on the unit sphere, ρ_ω ~ U[0, ω_max]   (body FRD)
//! v_0   = ρ_v u_v,  p_0 = ρ_p u_p  (world NED), same construction
//! f_e   = ρ_f u_f                  (world NED), ρ_f ~ U[0, f_max]
//! τ_e,i ~ U[−τ_max,i, τ_max,i]     per body axis (FRD): the axes' authorities differ
//! ```
//!
//! Magnitudes are uniform in their range (not volume-uniform), so the edges of the envelope are
//! sampled as often as its centre. A unit direction on the sphere is `(√(1−z²) cos φ,
//! √(1−z²) sin φ, z)` with `z ~ U[−1, 1]`, `φ ~ U[0, 2π)` (Archimedes' hat-box theorem).

use rand_chacha::rand_core::Rng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use thiserror::Error;

use crate::math::{e3, UnitQuat, Vec3};
use crate::sweep::design::unit;

/// An envelope that cannot be sampled.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("envelope: {field}: {reason}")]
pub struct EnvelopeError {
    /// Envelope field (command-line option name without dashes).
    pub field: &'static str,
    /// What is wrong.
    pub reason: String,
}

/// Ranges of the random initial state and disturbance. Every bound is a magnitude ≥ 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Envelope {
    /// Largest initial tilt of body z from the vertical [rad] (heading is always any).
    pub max_tilt_rad: f64,
    /// Largest initial body-rate magnitude ‖ω_0‖ [rad/s].
    pub max_rate_rad_s: f64,
    /// Largest initial speed ‖v_0‖ [m/s].
    pub max_speed_m_s: f64,
    /// Largest initial distance from the setpoint ‖p_0‖ [m].
    pub max_offset_m: f64,
    /// Largest constant external force ‖f_e‖, world NED [N].
    pub max_force_n: f64,
    /// Largest constant external torque per body axis |τ_e,i|, FRD [N·m].
    pub max_torque_n_m: [f64; 3],
}

impl Envelope {
    /// The envelope of the hover state alone: every draw starts at rest on the setpoint, without
    /// disturbance, at a random heading.
    pub const HOVER: Self = Self {
        max_tilt_rad: 0.0,
        max_rate_rad_s: 0.0,
        max_speed_m_s: 0.0,
        max_offset_m: 0.0,
        max_force_n: 0.0,
        max_torque_n_m: [0.0; 3],
    };

    /// Checks every bound: finite, ≥ 0, and a tilt below π (a tilt of π has no unique axis).
    pub fn validate(&self) -> Result<(), EnvelopeError> {
        let bad = |field: &'static str, v: f64| EnvelopeError {
            field,
            reason: format!("must be a finite number ≥ 0, got {v}"),
        };
        for (field, v) in [
            ("max-tilt", self.max_tilt_rad),
            ("max-rate", self.max_rate_rad_s),
            ("max-speed", self.max_speed_m_s),
            ("max-offset", self.max_offset_m),
            ("max-force", self.max_force_n),
        ]
        .into_iter()
        .chain(self.max_torque_n_m.iter().map(|t| ("max-torque", *t)))
        {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(field, v));
            }
        }
        if self.max_tilt_rad >= std::f64::consts::PI {
            return Err(EnvelopeError {
                field: "max-tilt",
                reason: format!("must be below 180°, got {}°", self.max_tilt_rad.to_degrees()),
            });
        }
        Ok(())
    }
}

/// One random initial state and disturbance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Draw {
    /// Initial position, world NED [m].
    pub pos_w: Vec3,
    /// Initial velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Initial attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
    /// Initial body rates, FRD [rad/s].
    pub omega_b: Vec3,
    /// Constant external force, world NED [N].
    pub force_w: Vec3,
    /// Constant external torque, body FRD [N·m].
    pub torque_b: Vec3,
    /// Seed of the plant's sensor noise (zero noise on the presets) [-].
    pub noise_seed: u64,
}

impl Draw {
    /// Tilt of body z from the vertical [rad].
    pub fn tilt_rad(&self) -> f64 {
        (self.q_wb * e3()).z.clamp(-1.0, 1.0).acos()
    }
}

/// A number uniform in [lo, hi).
fn uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * unit(rng)
}

/// A unit vector uniform on the sphere (hat-box construction, module docs).
fn direction(rng: &mut ChaCha8Rng) -> Vec3 {
    let z = uniform(rng, -1.0, 1.0);
    let phi = uniform(rng, 0.0, std::f64::consts::TAU);
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// A vector with uniform direction and magnitude uniform in [0, max].
fn ball(rng: &mut ChaCha8Rng, max: f64) -> Vec3 {
    let d = direction(rng);
    d * uniform(rng, 0.0, max)
}

/// One draw inside `env` (module docs for the distributions). Consumes a fixed number of
/// values from `rng`, so draw k of a seed does not depend on the envelope's bounds.
pub fn draw(env: &Envelope, rng: &mut ChaCha8Rng) -> Draw {
    let axis_angle = uniform(rng, 0.0, std::f64::consts::TAU);
    let tilt = uniform(rng, 0.0, env.max_tilt_rad);
    let yaw = uniform(rng, -std::f64::consts::PI, std::f64::consts::PI);
    let axis = nalgebra::Unit::new_unchecked(Vec3::new(axis_angle.cos(), axis_angle.sin(), 0.0));
    let q_wb = UnitQuat::from_axis_angle(&axis, tilt) * UnitQuat::from_axis_angle(&nalgebra::Vector3::z_axis(), yaw);
    let omega_b = ball(rng, env.max_rate_rad_s);
    let vel_w = ball(rng, env.max_speed_m_s);
    let pos_w = ball(rng, env.max_offset_m);
    let force_w = ball(rng, env.max_force_n);
    let t = env.max_torque_n_m;
    let torque_b = Vec3::new(
        uniform(rng, -t[0], t[0]),
        uniform(rng, -t[1], t[1]),
        uniform(rng, -t[2], t[2]),
    );
    Draw {
        pos_w,
        vel_w,
        q_wb,
        omega_b,
        force_w,
        torque_b,
        noise_seed: rng.next_u64(),
    }
}

/// `runs` draws from a ChaCha8 stream seeded with `seed`, in order: the same seed gives the
/// same draws, and the first k draws of a longer campaign are those of a shorter one.
pub fn draws(env: &Envelope, seed: u64, runs: usize) -> Vec<Draw> {
    use rand_chacha::rand_core::SeedableRng;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..runs).map(|_| draw(env, &mut rng)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env() -> Envelope {
        Envelope {
            max_tilt_rad: 60f64.to_radians(),
            max_rate_rad_s: 3.0,
            max_speed_m_s: 3.0,
            max_offset_m: 1.0,
            max_force_n: 2.9,
            max_torque_n_m: [0.4, 0.3, 0.15],
        }
    }

    #[test]
    fn every_draw_lies_inside_the_envelope() {
        let e = env();
        let ds = draws(&e, 7, 5000);
        for d in &ds {
            assert!(d.tilt_rad() <= e.max_tilt_rad + 1e-12, "{}", d.tilt_rad());
            assert!(d.omega_b.norm() <= e.max_rate_rad_s + 1e-12);
            assert!(d.vel_w.norm() <= e.max_speed_m_s + 1e-12);
            assert!(d.pos_w.norm() <= e.max_offset_m + 1e-12);
            assert!(d.force_w.norm() <= e.max_force_n + 1e-12);
            for i in 0..3 {
                assert!(d.torque_b[i].abs() <= e.max_torque_n_m[i]);
            }
            assert!((d.q_wb.norm() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn draws_fill_the_envelope() {
        // Uniform magnitudes reach the edges; headings cover the full circle.
        let e = env();
        let ds = draws(&e, 1, 5000);
        let max = |f: &dyn Fn(&Draw) -> f64| ds.iter().map(f).fold(0.0, f64::max);
        assert!(max(&|d| d.tilt_rad()) > 0.99 * e.max_tilt_rad);
        assert!(max(&|d| d.omega_b.norm()) > 0.99 * e.max_rate_rad_s);
        assert!(max(&|d| d.force_w.norm()) > 0.99 * e.max_force_n);
        assert!(max(&|d| d.torque_b.z.abs()) > 0.99 * e.max_torque_n_m[2]);
        let yaws: Vec<f64> = ds
            .iter()
            .map(|d| crate::math::euler_zyx(&d.q_wb.to_rotation_matrix().into_inner()).z)
            .collect();
        assert!(yaws.iter().any(|y| *y > 3.0) && yaws.iter().any(|y| *y < -3.0));
        // Directions are centred: the mean of many unit vectors is near zero.
        let mean = ds.iter().map(|d| d.vel_w / d.vel_w.norm()).sum::<Vec3>() / ds.len() as f64;
        assert!(mean.norm() < 0.05, "{mean}");
    }

    #[test]
    fn the_same_seed_gives_the_same_draws() {
        let e = env();
        assert_eq!(draws(&e, 42, 50), draws(&e, 42, 50));
        assert_ne!(draws(&e, 42, 50), draws(&e, 43, 50));
        // Prefix property: a short campaign is the start of a long one.
        assert_eq!(draws(&e, 42, 10)[..], draws(&e, 42, 50)[..10]);
    }

    #[test]
    fn a_zero_envelope_draws_the_hover_state_at_any_heading() {
        for d in draws(&Envelope::HOVER, 3, 20) {
            assert_eq!(d.tilt_rad(), 0.0);
            assert_eq!(d.pos_w + d.vel_w + d.omega_b + d.force_w + d.torque_b, Vec3::zeros());
        }
    }

    #[test]
    fn bad_bounds_are_refused_by_name() {
        let mut e = env();
        e.max_rate_rad_s = f64::NAN;
        assert_eq!(e.validate().map_err(|e| e.field), Err("max-rate"));
        let mut e = env();
        e.max_torque_n_m[1] = -0.1;
        assert_eq!(e.validate().map_err(|e| e.field), Err("max-torque"));
        let mut e = env();
        e.max_tilt_rad = 200f64.to_radians();
        assert_eq!(e.validate().map_err(|e| e.field), Err("max-tilt"));
        assert!(env().validate().is_ok());
    }
}
