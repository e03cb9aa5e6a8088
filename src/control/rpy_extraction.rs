//! Outer-loop output of the RPY laws (docs/control.md §4.1, used by docs/control.md §4, §6): from the
//! desired acceleration μ_d to collective thrust and desired roll and pitch, with the corrected
//! definition `μ_d = g e3 − (u_T/m) R_b(η_d) e3` (docs/control.md §4.1, eq. (4.2);
//! docs/homework.md §3, E1), giving (docs/control.md §4.1, eqs. (4.3)–(4.5)):
//!
//! ```text
//! u_T = m √( μ_x² + μ_y² + (μ_z − g)² )
//! φ_d = asin( m (μ_y cos ψ_d − μ_x sin ψ_d) / u_T )
//! θ_d = atan2( −(μ_x cos ψ_d + μ_y sin ψ_d),  g − μ_z )
//! ```

use crate::math::{Vec3, GRAVITY_M_S2};

/// Guards of the extraction (docs/control.md §4.1, §8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtractionLimits {
    /// Largest tilt of the thrust direction [rad]; kept well below π/2 (RPY singularity).
    pub tilt_max_rad: f64,
    /// Margin ε_z: μ_z is kept ≤ g − ε_z so thrust never vanishes [m/s²].
    pub eps_z_m_s2: f64,
    /// Largest collective thrust the rotors give [N].
    pub thrust_max_n: f64,
}

/// Thrust and desired roll and pitch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extraction {
    /// Collective thrust u_T [N], clamped to `[0, thrust_max_n]`.
    pub thrust_n: f64,
    /// φ_d [rad].
    pub roll_rad: f64,
    /// θ_d [rad].
    pub pitch_rad: f64,
    /// The horizontal demand was scaled to the tilt limit.
    pub tilt_limited: bool,
    /// μ_z was lowered to g − ε_z.
    pub vertical_limited: bool,
    /// u_T exceeded the rotors' maximum.
    pub thrust_clamped: bool,
}

/// Thrust, φ_d and θ_d that realise `mu` [m/s²] at heading `yaw_rad` for mass `mass_kg`.
pub fn extract(mu: Vec3, yaw_rad: f64, mass_kg: f64, limits: &ExtractionLimits) -> Extraction {
    let g = GRAVITY_M_S2;
    let mut mu = mu;
    let vertical_limited = mu.z > g - limits.eps_z_m_s2;
    if vertical_limited {
        mu.z = g - limits.eps_z_m_s2;
    }
    let horizontal = mu.xy().norm();
    let allowed = limits.tilt_max_rad.tan() * (g - mu.z);
    let tilt_limited = horizontal > allowed;
    if tilt_limited {
        let s = allowed / horizontal;
        mu.x *= s;
        mu.y *= s;
    }
    let thrust = mass_kg * (mu.x * mu.x + mu.y * mu.y + (mu.z - g) * (mu.z - g)).sqrt();
    let (sy, cy) = yaw_rad.sin_cos();
    let roll = (mass_kg * (mu.y * cy - mu.x * sy) / thrust).clamp(-1.0, 1.0).asin();
    let pitch = (-(mu.x * cy + mu.y * sy)).atan2(g - mu.z);
    let thrust_clamped = thrust > limits.thrust_max_n;
    Extraction {
        thrust_n: thrust.min(limits.thrust_max_n),
        roll_rad: roll,
        pitch_rad: pitch,
        tilt_limited,
        vertical_limited,
        thrust_clamped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::e3;
    use crate::rpy::rotation;

    fn limits() -> ExtractionLimits {
        ExtractionLimits {
            tilt_max_rad: 0.8,
            eps_z_m_s2: 0.5,
            thrust_max_n: 100.0,
        }
    }

    #[test]
    fn extracted_attitude_reproduces_the_demanded_acceleration() {
        let m = 1.5;
        for (mu, yaw) in [
            (Vec3::new(1.0, -0.5, 0.3), 0.4),
            (Vec3::new(-2.0, 1.5, -1.0), -2.5),
            (Vec3::zeros(), 1.0),
        ] {
            let e = extract(mu, yaw, m, &limits());
            // Definition (docs/control.md §4.1, eq. (4.2)): μ = g e3 − (u_T/m) R(η_d) e3.
            let back = GRAVITY_M_S2 * e3() - e.thrust_n / m * rotation(&Vec3::new(e.roll_rad, e.pitch_rad, yaw)) * e3();
            assert!((back - mu).norm() < 1e-12, "{mu} → {back}");
            assert!(!e.tilt_limited && !e.vertical_limited);
        }
    }

    #[test]
    fn north_acceleration_pitches_nose_down_and_hover_is_level() {
        let e = extract(Vec3::new(1.0, 0.0, 0.0), 0.0, 1.5, &limits());
        assert!(e.pitch_rad < 0.0 && e.roll_rad.abs() < 1e-15);
        let h = extract(Vec3::zeros(), 0.0, 1.5, &limits());
        assert!((h.thrust_n - 1.5 * GRAVITY_M_S2).abs() < 1e-12);
    }

    #[test]
    fn guards_limit_tilt_free_fall_and_thrust() {
        let e = extract(Vec3::new(30.0, 0.0, 0.0), 0.0, 1.5, &limits());
        assert!(e.tilt_limited && (e.pitch_rad.abs() - 0.8).abs() < 1e-12);
        let f = extract(Vec3::new(0.0, 0.0, 2.0 * GRAVITY_M_S2), 0.0, 1.5, &limits());
        assert!(f.vertical_limited && (f.thrust_n - 0.75).abs() < 1e-12);
        let c = extract(Vec3::new(0.0, 0.0, -100.0), 0.0, 1.5, &limits());
        assert!(c.thrust_clamped && c.thrust_n == 100.0);
    }
}
