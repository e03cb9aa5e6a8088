//! Torque authority about a thrust level, and the default Monte Carlo envelope it scales.
//!
//! With the min-norm inverse A (docs/allocation.md §3, eq. (3.1)), a torque τ about body axis i alone at
//! collective thrust T asks for `ω² = A[:,0] T + A[:,1+i] τ`. The authority is the largest |τ|
//! that keeps every `ω_j²` in `[ω_min², ω_max²]` for both signs of τ:
//!
//! ```text
//! τ_max,i = min_j { (ω_max² − h_j)/a_j  if a_j > 0,   (h_j − ω_min²)/|a_j|  if a_j < 0 }
//!           over both signs of a,   h = A[:,0] T,  a = A[:,1+i]
//! ```

use crate::airframe::Airframe;
use crate::allocation::Allocator;
use crate::math::GRAVITY_M_S2;

use super::envelope::Envelope;

/// Default largest initial tilt [deg].
pub const DEFAULT_MAX_TILT_DEG: f64 = 60.0;
/// Default largest initial body-rate magnitude [rad/s].
pub const DEFAULT_MAX_RATE_RAD_S: f64 = 3.0;
/// Default largest initial speed [m/s].
pub const DEFAULT_MAX_SPEED_M_S: f64 = 3.0;
/// Default largest initial distance from the setpoint [m].
pub const DEFAULT_MAX_OFFSET_M: f64 = 1.0;
/// Default largest external force as a fraction of the believed weight m g [-]: 0.2 tilts the
/// hover by at most 11.3° (half the 40° tilt limit leaves room to manoeuvre) and asks for at
/// most 1.2 m g of thrust.
pub const DEFAULT_FORCE_FRACTION: f64 = 0.2;
/// Default largest external torque per axis as a fraction of that axis' authority at hover [-]:
/// the disturbance takes at most a fifth of what the rotors can do about each axis.
pub const DEFAULT_TORQUE_FRACTION: f64 = 0.2;

/// Largest torque about each body axis alone at collective thrust `thrust_n` [N], per axis
/// [N·m] (module docs). Zero on an axis when `thrust_n` itself does not fit the speed box.
pub fn torque_authority(airframe: &Airframe, allocator: &Allocator, thrust_n: f64) -> [f64; 3] {
    let a = allocator.inverse();
    let (lo, hi) = (airframe.omega_min_rad_s.powi(2), airframe.omega_max_rad_s.powi(2));
    let mut out = [0.0; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        let mut best = f64::INFINITY;
        for sign in [1.0, -1.0] {
            for j in 0..a.nrows() {
                let h = a[(j, 0)] * thrust_n;
                let aj = sign * a[(j, 1 + i)];
                if !(lo..=hi).contains(&h) {
                    best = 0.0;
                } else if aj > 0.0 {
                    best = best.min((hi - h) / aj);
                } else if aj < 0.0 {
                    best = best.min((h - lo) / -aj);
                }
            }
        }
        *slot = if best.is_finite() { best } else { 0.0 };
    }
    out
}

/// The default envelope for `airframe`: the fixed state bounds above, a force of
/// [`DEFAULT_FORCE_FRACTION`] of the believed weight and a torque of
/// [`DEFAULT_TORQUE_FRACTION`] of each axis' authority at the believed hover thrust.
pub fn default_envelope(airframe: &Airframe, allocator: &Allocator) -> Envelope {
    let weight_n = airframe.mass_kg * GRAVITY_M_S2;
    let authority = torque_authority(airframe, allocator, weight_n);
    Envelope {
        max_tilt_rad: DEFAULT_MAX_TILT_DEG.to_radians(),
        max_rate_rad_s: DEFAULT_MAX_RATE_RAD_S,
        max_speed_m_s: DEFAULT_MAX_SPEED_M_S,
        max_offset_m: DEFAULT_MAX_OFFSET_M,
        max_force_n: DEFAULT_FORCE_FRACTION * weight_n,
        max_torque_n_m: authority.map(|t| DEFAULT_TORQUE_FRACTION * t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::AirframeSource;
    use crate::allocation::Wrench;
    use crate::math::Vec3;

    fn quad_x() -> (Airframe, Allocator) {
        let af = Airframe::from_source(&AirframeSource::resolve("quad_x").unwrap()).unwrap();
        let alloc = Allocator::new(&af).unwrap();
        (af, alloc)
    }

    #[test]
    fn quad_x_authority_matches_the_hand_calculation() {
        // X quad, l = 0.25 m: roll arm l/√2; hover ω² = m g / (4 c_T) = 629 880 (rad/s)²,
        // headroom to ω_max² = 1.21e6 is 580 120, the binding side. Roll: 4 rotors × c_T ×
        // (l/√2) × 580 120 = 2.396 N·m; yaw: 4 × c_Q × 580 120 = 0.8131 N·m.
        let (af, alloc) = quad_x();
        let t = torque_authority(&af, &alloc, 1.5 * GRAVITY_M_S2);
        let headroom = 1100f64.powi(2) - 1.5 * GRAVITY_M_S2 / (4.0 * 5.84e-6);
        let roll = 4.0 * 5.84e-6 * 0.25 / 2f64.sqrt() * headroom;
        let yaw = 4.0 * 3.504e-7 * headroom;
        assert!((t[0] - roll).abs() < 1e-9 * roll, "{t:?} vs {roll}");
        assert!((t[1] - roll).abs() < 1e-9 * roll, "{t:?}");
        assert!((t[2] - yaw).abs() < 1e-9 * yaw, "{t:?} vs {yaw}");
    }

    #[test]
    fn the_authority_is_exactly_what_the_allocator_applies_unsaturated() {
        let (af, alloc) = quad_x();
        let hover = 1.5 * GRAVITY_M_S2;
        let t = torque_authority(&af, &alloc, hover);
        for i in 0..3 {
            for (scale, saturated) in [(0.999, false), (1.01, true)] {
                let mut torque_b = Vec3::zeros();
                torque_b[i] = -scale * t[i];
                let out = alloc.allocate(&Wrench {
                    thrust_n: hover,
                    torque_b,
                });
                assert_eq!(out.saturation.is_saturated(), saturated, "axis {i} × {scale}");
            }
        }
    }

    #[test]
    fn an_infeasible_thrust_has_no_authority() {
        let (af, alloc) = quad_x();
        assert_eq!(torque_authority(&af, &alloc, 1e3), [0.0; 3]);
    }

    #[test]
    fn the_default_envelope_scales_with_the_airframe() {
        let (af, alloc) = quad_x();
        let e = default_envelope(&af, &alloc);
        assert!((e.max_force_n - 0.2 * 1.5 * GRAVITY_M_S2).abs() < 1e-12);
        assert!((e.max_torque_n_m[0] - 0.2 * torque_authority(&af, &alloc, 1.5 * GRAVITY_M_S2)[0]).abs() < 1e-12);
        assert!(e.validate().is_ok());
    }
}
