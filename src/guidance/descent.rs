//! The landing descent (PX4's multicopter landing speeds): fast high up, slowing down near the
//! ground, at the landing speed for the touch-down.
//!
//! ```text
//! v(h) = v_fast                                              h ≥ h₁   (MPC_Z_VEL_MAX_DN above MPC_LAND_ALT1)
//!      = v_land + k (h − h₂),  k = (v_fast − v_land)/(h₁ − h₂)  h₂ < h < h₁
//!      = v_land                                              h ≤ h₂   (MPC_LAND_SPEED below MPC_LAND_ALT2)
//! ```
//! The reference height h(t) starts from rest at h₀ with the acceleration `MPC_ACC_DOWN_MAX`
//! up to v(h₀), then solves ḣ = −v(h) in closed form: linear above h₁, u = h − h₂ + v_land/k
//! decays as u₀ e^{−k t} between h₁ and h₂, linear again below h₂.

/// Landing speeds by height (PX4 parameter names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DescentProfile {
    /// Descent speed high up [m/s] (`MPC_Z_VEL_MAX_DN`, 1.5).
    pub fast_m_s: f64,
    /// Touch-down speed [m/s] (`MPC_LAND_SPEED`, 0.7).
    pub land_m_s: f64,
    /// Height below which the descent slows down [m] (`MPC_LAND_ALT1`, 10).
    pub slow_from_m: f64,
    /// Height below which it descends at the touch-down speed [m] (`MPC_LAND_ALT2`, 5).
    pub land_from_m: f64,
    /// Acceleration from rest to the first speed [m/s²] (`MPC_ACC_DOWN_MAX`, 3).
    pub acc_m_s2: f64,
}

impl Default for DescentProfile {
    fn default() -> Self {
        Self {
            fast_m_s: 1.5,
            land_m_s: 0.7,
            slow_from_m: 10.0,
            land_from_m: 5.0,
            acc_m_s2: 3.0,
        }
    }
}

impl DescentProfile {
    /// (h₁, h₂) with h₁ ≥ h₂ (an `MPC_LAND_ALT1` below `MPC_LAND_ALT2` means no slowing band).
    fn heights(&self) -> (f64, f64) {
        (self.slow_from_m.max(self.land_from_m), self.land_from_m)
    }

    /// Descent speed at height `h_m` [m] above the ground [m/s].
    pub fn speed_m_s(&self, h_m: f64) -> f64 {
        let (fast, land) = (self.fast_m_s.max(self.land_m_s), self.land_m_s);
        let (h1, h2) = self.heights();
        if h_m <= h2 {
            land
        } else if h_m >= h1 {
            fast
        } else {
            land + (fast - land) * (h_m - h2) / (h1 - h2)
        }
    }

    /// Height [m] and descent speed [m/s] at `t_s` [s] after a descent began at rest at height
    /// `h0_m`: accelerating at `acc_m_s2` to the speed of `h0_m`, then following the profile.
    pub fn at(&self, h0_m: f64, t_s: f64) -> (f64, f64) {
        let (h, v, _) = self.sample(h0_m, t_s);
        (h, v)
    }

    /// Height [m], descent speed [m/s] and downward acceleration [m/s²] at `t_s` [s] after a
    /// descent began at rest at `h0_m` (see [`DescentProfile::at`]).
    pub fn sample(&self, h0_m: f64, t_s: f64) -> (f64, f64, f64) {
        self.sample_from(h0_m, 0.0, t_s)
    }

    /// [`DescentProfile::sample`] for a descent that began at height `h0_m` [m] moving down at
    /// `v0_m_s` [m/s] (negative while climbing): the speed changes at `acc_m_s2` from v₀ to the
    /// profile's speed v₁ at `h0_m` (a climb is stopped first, overshooting by v₀² / 2a), then
    /// follows the profile. Over t ≤ |v₁ − v₀| / a: h = h₀ − v₀ t − ½ a t², v = v₀ + a t.
    pub fn sample_from(&self, h0_m: f64, v0_m_s: f64, t_s: f64) -> (f64, f64, f64) {
        let t = t_s.max(0.0);
        let v1 = self.speed_m_s(h0_m);
        let dv = v1 - v0_m_s;
        let acc = self.acc_m_s2.max(0.1);
        let t_acc = dv.abs() / acc;
        if t < t_acc {
            let a = acc * dv.signum();
            return (h0_m - v0_m_s * t - 0.5 * a * t * t, v0_m_s + a * t, a);
        }
        self.cruising(h0_m - 0.5 * (v0_m_s + v1) * t_acc, t - t_acc)
    }

    /// Height [m], descent speed [m/s] and downward acceleration [m/s²] `t_s` [s] after passing
    /// height `h0_m` at its speed.
    fn cruising(&self, h0_m: f64, t_s: f64) -> (f64, f64, f64) {
        let t = t_s;
        let (fast, land) = (self.fast_m_s.max(self.land_m_s), self.land_m_s);
        let (h1, h2) = self.heights();
        let k = if h1 > h2 { (fast - land) / (h1 - h2) } else { 0.0 };
        // Above h₁: linear at the fast speed.
        let t1 = if h0_m > h1 { (h0_m - h1) / fast } else { 0.0 };
        if t < t1 {
            return (h0_m - fast * t, fast, 0.0);
        }
        // Between h₂ and h₁: exponential approach, if the profile has such a band.
        let (h_band, t_band) = (h0_m.min(h1), t - t1);
        if h_band > h2 && k > 0.0 {
            let u0 = h_band - h2 + land / k;
            let t2 = (u0 / (land / k)).ln() / k;
            if t_band < t2 {
                let u = u0 * (-k * t_band).exp();
                return (u + h2 - land / k, k * u, -k * k * u);
            }
            return (h2 - land * (t_band - t2), land, 0.0);
        }
        (h_band - land * t_band, land, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_descent_begun_in_a_climb_stops_the_climb_then_descends_within_the_limit() {
        let p = DescentProfile::default();
        // Climbing at 3 m/s at 20 m: stopped at 3 m/s² in 1 s, 1.5 m higher, then down.
        assert_eq!(p.sample_from(20.0, -3.0, 0.0), (20.0, -3.0, 3.0));
        let (h, v, _) = p.sample_from(20.0, -3.0, 1.0);
        assert!((h - 21.5).abs() < 1e-12 && v.abs() < 1e-12, "{h} {v}");
        let mut fastest: f64 = 0.0;
        for k in 0..40_000 {
            let (_, v, _) = p.sample_from(20.0, -3.0, f64::from(k) * 1e-3);
            fastest = fastest.max(v);
        }
        assert!((fastest - p.fast_m_s).abs() < 1e-9, "{fastest}");
        // Descending faster than the profile: slowed down to it.
        let (_, v, a) = p.sample_from(30.0, 2.5, 0.1);
        assert!(a < 0.0 && (v - 2.2).abs() < 1e-9, "{v} {a}");
        assert!((p.sample_from(30.0, 2.5, 2.0).1 - 1.5).abs() < 1e-9);
    }

    #[test]
    fn heights_follow_the_speed_profile_continuously() {
        let p = DescentProfile::default();
        assert_eq!(p.at(60.0, 0.0), (60.0, 0.0));
        assert!((p.at(60.0, 0.25).1 - 0.75).abs() < 1e-12, "accelerating at 3 m/s²");
        let (mut h_prev, dt) = (p.at(60.0, 0.5).0, 1e-3);
        for k in 501..80_000 {
            let t = k as f64 * dt;
            let (h, v) = p.at(60.0, t);
            // ḣ = −v(h): the speed is the profile's at that height, and the heights integrate it.
            assert!((v - p.speed_m_s(h)).abs() < 1e-6, "t {t}: v {v} at {h}");
            assert!(((h_prev - h) / dt - v).abs() < 2e-3, "t {t}");
            h_prev = h;
        }
        // 0.5 s to 1.5 m/s (0.375 m), 50 m fast (33.3 s), the band (5 m), then 5 m at 0.7 m/s.
        let band = f64::ln((5.0 + 0.7 / 0.16) / (0.7 / 0.16)) / 0.16;
        let (h, _) = p.at(60.0, 0.5 + (50.0 - 0.375) / 1.5 + band + 5.0 / 0.7);
        assert!(h.abs() < 1e-9, "{h}");
    }

    #[test]
    fn low_starts_descend_at_the_landing_speed() {
        let p = DescentProfile::default();
        // 0.7/3 s to reach 0.7 m/s, 0.0817 m down; then 0.7 m/s.
        let (h, v) = p.at(3.0, 1.0);
        assert!((h - (3.0 - 0.7 * 0.7 / 6.0 - 0.7 * (1.0 - 0.7 / 3.0))).abs() < 1e-12 && v == 0.7);
        assert_eq!(p.speed_m_s(-1.0), 0.7);
        assert!((p.speed_m_s(7.0) - 1.02).abs() < 1e-12);
    }
}
