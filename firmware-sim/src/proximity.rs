//! Ground- and ceiling-effect thrust factors per rotor (docs/ground_ceiling.md).
//!
//! A [`ProximityModel`] maps a rotor's distance to a surface `h` [m] to the factor by which its
//! thrust is multiplied. The raw laws are singular close to the surface, so the model applies the
//! simulator rules of docs/ground_ceiling.md §5: clamp at `h_min`, cap the factor, return
//! exactly 1 above the cutoff `h_cut`, and blend C¹ over `[0.8 h_cut, h_cut]`.

use thiserror::Error;

/// The raw thrust-ratio law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ProximityLaw {
    /// Single rotor, method of images (Cheeseman & Bennett 1955), docs/ground_ceiling.md §2, eq. (2.1):
    /// `k = 1 / (1 − (ρ/4z)²)`.
    CheesemanBennett,
    /// Multirotor ground effect (Sanchez-Cuevas et al. 2017), docs/ground_ceiling.md §3, eq. (3.1).
    Multirotor {
        /// Spacing d between adjacent rotors [m].
        spacing_m: f64,
        /// Distance b used by the body-lift term [m].
        body_distance_m: f64,
        /// Empirical body-lift gain K_b [-] (to be confirmed from the paper; 0 = pure images).
        body_gain: f64,
    },
    /// Ceiling effect (Sanchez-Cuevas et al., ICUAS 2017), docs/ground_ceiling.md §4, eq. (4.1):
    /// `k = 1 / (1 − (1/k1)(ρ/(z + k2))²)`.
    Ceiling {
        /// Fitted constant k1 [-].
        k1: f64,
        /// Fitted offset k2 [m].
        k2_m: f64,
    },
}

/// A law that cannot be used as configured.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ProximityError {
    /// The cap must exceed 1.
    #[error("cap {0} must be greater than 1")]
    Cap(f64),
    /// The cutoff must lie above the clamp height.
    #[error("cutoff {cutoff} m must be above the clamp height {h_min} m")]
    Cutoff {
        /// Configured cutoff [m].
        cutoff: f64,
        /// Clamp height [m].
        h_min: f64,
    },
}

impl ProximityError {
    /// Name of the configuration field at fault.
    pub fn field(&self) -> &'static str {
        match self {
            Self::Cap(_) => "cap",
            Self::Cutoff { .. } => "cutoff",
        }
    }
}

/// A proximity law with its clamp, cap and cutoff resolved at load time.
#[derive(Debug, Clone, PartialEq)]
pub struct ProximityModel {
    law: ProximityLaw,
    radius_m: f64,
    h_min_m: f64,
    h_cut_m: f64,
    cap: f64,
}

/// Raw factor at which the default cutoff is placed (docs/ground_ceiling.md §5.5).
const CUTOFF_EXCESS: f64 = 1e-3;

impl ProximityModel {
    /// Default cap on the thrust factor [-].
    pub const DEFAULT_CAP: f64 = 2.0;

    /// Resolves the clamp height (rule 3) and, unless given, the cutoff (rule 5) of a law for
    /// rotors of radius `radius_m` [m].
    pub fn new(law: ProximityLaw, radius_m: f64, cap: f64, cutoff_m: Option<f64>) -> Result<Self, ProximityError> {
        if !(cap > 1.0 && cap.is_finite()) {
            return Err(ProximityError::Cap(cap));
        }
        let mut model = Self {
            law,
            radius_m,
            h_min_m: 0.0,
            h_cut_m: f64::INFINITY,
            cap,
        };
        model.h_min_m = match law {
            ProximityLaw::CheesemanBennett => 0.5 * radius_m,
            _ => (0.5 * radius_m).max(1.2 * model.singularity_m()),
        };
        model.h_cut_m = match cutoff_m {
            Some(c) if c.is_finite() && c > model.h_min_m => c,
            Some(c) => {
                return Err(ProximityError::Cutoff {
                    cutoff: c,
                    h_min: model.h_min_m,
                })
            }
            None => model.default_cutoff_m(),
        };
        Ok(model)
    }

    /// Height below which the law is evaluated at `h_min` [m].
    pub fn clamp_height_m(&self) -> f64 {
        self.h_min_m
    }

    /// Height above which the factor is exactly 1 [m].
    pub fn cutoff_m(&self) -> f64 {
        self.h_cut_m
    }

    /// The law in use.
    pub fn law(&self) -> ProximityLaw {
        self.law
    }

    /// Thrust factor at distance `h_m` [m] from the surface, following
    /// docs/ground_ceiling.md §5.3–§5.5, eq. (5.4):
    /// 1 above the cutoff, blended with `S(x) = 3x² − 2x³` over `[0.8 h_cut, h_cut]`, the raw law
    /// at `max(h, h_min)` below, capped, and never a division by a non-positive denominator.
    pub fn factor(&self, h_m: f64) -> f64 {
        if h_m >= self.h_cut_m {
            return 1.0;
        }
        let raw = self.raw_factor(h_m.max(self.h_min_m));
        let blend_start = 0.8 * self.h_cut_m;
        if h_m <= blend_start {
            return raw;
        }
        let x = (self.h_cut_m - h_m) / (0.2 * self.h_cut_m);
        1.0 + (raw - 1.0) * x * x * (3.0 - 2.0 * x)
    }

    /// The capped raw law at `h_m` [m], without clamp, cutoff or blend.
    pub fn raw_factor(&self, h_m: f64) -> f64 {
        let d = self.denominator(h_m);
        if d <= 1.0 / self.cap {
            self.cap
        } else {
            1.0 / d
        }
    }

    /// Denominator of the law: the factor is its reciprocal.
    fn denominator(&self, h: f64) -> f64 {
        let rho = self.radius_m;
        match self.law {
            ProximityLaw::CheesemanBennett => {
                let a = rho / (4.0 * h);
                1.0 - a * a
            }
            ProximityLaw::Multirotor {
                spacing_m: d,
                body_distance_m: b,
                body_gain: kb,
            } => {
                let a = rho / (4.0 * h);
                let r2 = rho * rho;
                let h2 = 4.0 * h * h;
                let pow32 = |s: f64| s * s.sqrt();
                1.0 - a * a
                    - r2 * h / pow32(d * d + h2)
                    - 0.5 * r2 * h / pow32(2.0 * d * d + h2)
                    - 2.0 * r2 * kb * h / pow32(b * b + h2)
            }
            ProximityLaw::Ceiling { k1, k2_m } => {
                let a = rho / (h + k2_m);
                1.0 - a * a / k1
            }
        }
    }

    /// Largest root z* of the denominator (0 when it has none above zero), by a geometric scan
    /// down from far away and bisection.
    fn singularity_m(&self) -> f64 {
        let mut hi = 100.0 * self.radius_m;
        let floor = 1e-6 * self.radius_m;
        while hi > floor {
            let lo = 0.99 * hi;
            if self.denominator(lo) <= 0.0 {
                return self.bisect(lo, hi, |h| self.denominator(h) > 0.0);
            }
            hi = lo;
        }
        0.0
    }

    /// Largest height at which the raw factor still reaches `1 + 1e-3`.
    fn default_cutoff_m(&self) -> f64 {
        let threshold = 1.0 + CUTOFF_EXCESS;
        let mut hi = 1000.0 * self.radius_m;
        while hi > self.h_min_m {
            let lo = 0.99 * hi;
            if self.raw_factor(lo) >= threshold {
                return self.bisect(lo, hi, |h| self.raw_factor(h) < threshold);
            }
            hi = lo;
        }
        // The law never exceeds the threshold: any cutoff above the clamp height is exact.
        self.h_min_m * 1.25
    }

    /// Boundary in `[lo, hi]` where `above(h)` turns true, assuming false at `lo`, true at `hi`.
    fn bisect(&self, mut lo: f64, mut hi: f64, above: impl Fn(f64) -> bool) -> f64 {
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if above(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cb(rho: f64) -> ProximityModel {
        ProximityModel::new(ProximityLaw::CheesemanBennett, rho, 2.0, None).unwrap()
    }

    #[test]
    fn cheeseman_bennett_golden_values() {
        let rho = 0.127;
        let m = cb(rho);
        assert!((m.factor(rho) - 1.0 / (1.0 - 1.0 / 16.0)).abs() < 1e-12);
        assert!((m.factor(rho) - 1.0667).abs() < 5e-5);
        assert!((m.factor(2.0 * rho) - 1.0159).abs() < 5e-5);
        assert!((m.factor(4.0 * rho) - 1.0039).abs() < 5e-5);
        assert!((m.factor(0.5 * rho) - 4.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn clamped_below_half_radius_and_at_contact() {
        let m = cb(0.1);
        let at_clamp = m.factor(0.05);
        assert_eq!(m.factor(0.01), at_clamp);
        assert_eq!(m.factor(0.0), at_clamp);
        assert_eq!(m.factor(-0.3), at_clamp);
    }

    #[test]
    fn exactly_one_beyond_cutoff_and_continuous_at_it() {
        let rho = 0.128;
        let m = cb(rho);
        let cut = m.cutoff_m();
        assert!((cut / rho - 7.9).abs() < 0.05, "cutoff {} rho", cut / rho);
        assert_eq!(m.factor(cut), 1.0);
        assert_eq!(m.factor(50.0), 1.0);
        assert!((m.factor(cut * (1.0 - 1e-9)) - 1.0).abs() < 1e-9);
        // Exactly the law below the blend band.
        let h = 0.79 * cut;
        assert_eq!(m.factor(h), m.raw_factor(h));
        // Monotone through the blend.
        let mut prev = m.factor(0.75 * cut);
        for k in 0..=100 {
            let f = m.factor((0.8 + 0.002 * k as f64) * cut);
            assert!(f <= prev + 1e-15);
            prev = f;
        }
    }

    #[test]
    fn multirotor_matches_reference_table() {
        let rho = 0.127;
        let l = 0.25;
        let cases = [
            (0.0, 1.0, 1.103),
            (1.0, 1.0, 1.225),
            (2.0, 1.0, 1.378),
            (0.0, 2.0, 1.040),
            (1.0, 5.0, 1.019),
        ];
        for (kb, z_over_rho, expected) in cases {
            let law = ProximityLaw::Multirotor {
                spacing_m: 2f64.sqrt() * l,
                body_distance_m: l,
                body_gain: kb,
            };
            let m = ProximityModel::new(law, rho, 2.0, None).unwrap();
            let f = m.factor(z_over_rho * rho);
            assert!(
                (f - expected).abs() < 1.5e-3,
                "K_b {kb} z/ρ {z_over_rho}: {f} vs {expected}"
            );
        }
    }

    #[test]
    fn multirotor_singularity_moves_up() {
        let law = ProximityLaw::Multirotor {
            spacing_m: 0.3536,
            body_distance_m: 0.25,
            body_gain: 0.0,
        };
        let m = ProximityModel::new(law, 0.127, 2.0, None).unwrap();
        assert!(m.clamp_height_m() >= 0.5 * 0.127);
        assert!(m.cutoff_m() > 10.0 * 0.127);
    }

    #[test]
    fn ceiling_placeholder_equals_image_form_and_is_never_singular_with_offset() {
        let rho = 0.127;
        let ce = ProximityModel::new(ProximityLaw::Ceiling { k1: 16.0, k2_m: 0.0 }, rho, 2.0, None).unwrap();
        assert!((ce.factor(rho) - cb(rho).factor(rho)).abs() < 1e-12);
        let off = ProximityModel::new(ProximityLaw::Ceiling { k1: 16.0, k2_m: 0.1 }, rho, 2.0, None).unwrap();
        assert_eq!(off.clamp_height_m(), 0.5 * rho);
        assert!(off.factor(0.0).is_finite() && off.factor(0.0) > 1.0);
    }

    #[test]
    fn cap_limits_the_factor() {
        let m = ProximityModel::new(ProximityLaw::CheesemanBennett, 0.1, 1.2, None).unwrap();
        assert_eq!(m.factor(0.0), 1.2);
        assert!(ProximityModel::new(ProximityLaw::CheesemanBennett, 0.1, 0.9, None).is_err());
        assert!(ProximityModel::new(ProximityLaw::CheesemanBennett, 0.1, 2.0, Some(0.01)).is_err());
    }
}
