//! Estimator gains from an analog Chebyshev type-I low-pass (docs/estimator.md §3–§4).
//!
//! Prototype poles `p_k = Wp (−sinh v sin θ_k + j cosh v cos θ_k)`, `θ_k = (2k − 1)π/(2r)`,
//! `v = asinh(1/ε)/r`, `ε = √(10^(Rp/10) − 1)` (docs/estimator.md §3.2, eqs. (3.2)–(3.5)); the
//! monic denominator `∏ (s − p_k)` is expanded over real factors (docs/estimator.md §3.2, eq. (3.6));
//! `c_j = ∏_{i=j+1}^{r} K_i` (docs/estimator.md §2, eq. (2.5)) inverts to `K_i = c_{i−1}/c_i`
//! (docs/estimator.md §3.1, eq. (3.1)). The forward-Euler update at Ts has discrete poles
//! `1 + Ts p_k`, stable iff all lie inside the unit circle, i.e.
//! `Wp < Wp_max = min_k 2(−Re p̂_k)/(Ts |p̂_k|²)` with p̂ the poles for Wp = 1
//! (docs/estimator.md §4, eqs. (4.6)–(4.8)).

use thiserror::Error;

/// Highest estimator order accepted.
pub const MAX_ORDER: usize = 20;

/// Chebyshev-I low-pass design for the wrench estimator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChebyshevDesign {
    /// Filter order r (= estimator order) [-].
    pub order: usize,
    /// Passband ripple Rp [dB].
    pub ripple_db: f64,
    /// Passband edge Wp [rad/s].
    pub passband_rad_s: f64,
}

/// A design that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DesignError {
    /// Order outside 1 … [`MAX_ORDER`].
    #[error("order {0} must be between 1 and {MAX_ORDER}")]
    Order(usize),
    /// Ripple not a positive finite number.
    #[error("ripple {0} dB must be a positive number")]
    Ripple(f64),
    /// Passband edge not a positive finite number.
    #[error("passband edge {0} rad/s must be a positive number")]
    Passband(f64),
    /// Sample time not a positive finite number.
    #[error("sample time {0} s must be a positive number")]
    SampleTime(f64),
    /// The forward-Euler update would be unstable at this sample time.
    #[error("order {order}, {ripple_db} dB, Wp = {wp} rad/s is unstable at Ts = {ts} s: the largest stable passband edge for this order and ripple is {max_stable_wp:.4} rad/s")]
    Unstable {
        /// Order.
        order: usize,
        /// Ripple [dB].
        ripple_db: f64,
        /// Requested passband edge [rad/s].
        wp: f64,
        /// Sample time [s].
        ts: f64,
        /// Largest stable passband edge [rad/s].
        max_stable_wp: f64,
    },
}

/// A complex pole (re, im) [rad/s].
pub type Pole = (f64, f64);

impl ChebyshevDesign {
    fn check(&self) -> Result<(), DesignError> {
        if self.order == 0 || self.order > MAX_ORDER {
            return Err(DesignError::Order(self.order));
        }
        if !(self.ripple_db.is_finite() && self.ripple_db > 0.0) {
            return Err(DesignError::Ripple(self.ripple_db));
        }
        if !(self.passband_rad_s.is_finite() && self.passband_rad_s > 0.0) {
            return Err(DesignError::Passband(self.passband_rad_s));
        }
        Ok(())
    }

    /// Analog prototype poles p_1 … p_r [rad/s].
    pub fn poles(&self) -> Result<Vec<Pole>, DesignError> {
        self.check()?;
        Ok(unit_poles(self.order, self.ripple_db)
            .into_iter()
            .map(|(re, im)| (re * self.passband_rad_s, im * self.passband_rad_s))
            .collect())
    }

    /// Monic denominator in ascending powers: c[0] … c[r], c[r] = 1.
    pub fn monic_denominator(&self) -> Result<Vec<f64>, DesignError> {
        let poles = self.poles()?;
        let r = self.order;
        let mut poly = vec![1.0];
        for &(re, im) in &poles[..r / 2] {
            poly = multiply(&poly, &[re * re + im * im, -2.0 * re, 1.0]);
        }
        if r % 2 == 1 {
            poly = multiply(&poly, &[-poles[r / 2].0, 1.0]);
        }
        Ok(poly)
    }

    /// Largest passband edge whose forward-Euler update is stable at `ts_s` [s] [rad/s].
    pub fn max_stable_passband_rad_s(&self, ts_s: f64) -> Result<f64, DesignError> {
        if !(ts_s.is_finite() && ts_s > 0.0) {
            return Err(DesignError::SampleTime(ts_s));
        }
        let unit = ChebyshevDesign {
            passband_rad_s: 1.0,
            ..*self
        };
        unit.check()?;
        Ok(unit_poles(self.order, self.ripple_db)
            .into_iter()
            .map(|(re, im)| 2.0 * (-re) / (ts_s * (re * re + im * im)))
            .fold(f64::INFINITY, f64::min))
    }

    /// True when every discrete pole `1 + Ts p_k` lies inside the unit circle.
    pub fn is_stable_at(&self, ts_s: f64) -> Result<bool, DesignError> {
        Ok(self
            .poles()?
            .iter()
            .all(|(re, im)| (1.0 + ts_s * re).hypot(ts_s * im) < 1.0))
    }

    /// Gains K_1 … K_r for sample time `ts_s` [s]; refuses an unstable design, naming the
    /// largest stable passband edge.
    ///
    /// ```
    /// use rotorpilot::wrench_estimator::ChebyshevDesign;
    /// let d = ChebyshevDesign { order: 1, ripple_db: 3.0, passband_rad_s: 2.0 };
    /// let k = d.gains(1e-3).unwrap();
    /// assert!((k[0] - 2.004754586015201).abs() < 1e-12);
    /// ```
    pub fn gains(&self, ts_s: f64) -> Result<Vec<f64>, DesignError> {
        let max_stable_wp = self.max_stable_passband_rad_s(ts_s)?;
        if !self.is_stable_at(ts_s)? {
            return Err(DesignError::Unstable {
                order: self.order,
                ripple_db: self.ripple_db,
                wp: self.passband_rad_s,
                ts: ts_s,
                max_stable_wp,
            });
        }
        Ok(estimator_gains(&self.monic_denominator()?))
    }
}

/// Estimator gains from a monic denominator (ascending powers, c[r] = 1): `K_i = c_{i−1}/c_i`,
/// i = 1 … r (docs/estimator.md §3.1, eq. (3.1)).
pub fn estimator_gains(c: &[f64]) -> Vec<f64> {
    c.windows(2).map(|w| w[0] / w[1]).collect()
}

/// Poles for Wp = 1, in the order k = 1 … r.
fn unit_poles(order: usize, ripple_db: f64) -> Vec<Pole> {
    let eps = (10f64.powf(ripple_db / 10.0) - 1.0).sqrt();
    let v = (1.0 / eps).asinh() / order as f64;
    (1..=order)
        .map(|k| {
            let theta = (2 * k - 1) as f64 * std::f64::consts::PI / (2 * order) as f64;
            let im = v.cosh() * theta.cos();
            // The middle pole of an odd order is exactly real.
            (-v.sinh() * theta.sin(), if 2 * k - 1 == order { 0.0 } else { im })
        })
        .collect()
}

/// Product of two polynomials in ascending powers.
fn multiply(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn design(order: usize, ripple_db: f64, wp: f64) -> ChebyshevDesign {
        ChebyshevDesign {
            order,
            ripple_db,
            passband_rad_s: wp,
        }
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    #[test]
    fn first_order_golden() {
        let c = design(1, 3.0, 2.0).monic_denominator().unwrap();
        assert!(close(c[0], 2.004754586015201, 1e-12) && c[1] == 1.0);
        let eps = 0.997_628_345_110_983_4;
        assert!(close(design(1, 3.0, 2.0).gains(1e-3).unwrap()[0], 2.0 / eps, 1e-12));
    }

    #[test]
    fn seventh_order_golden() {
        let descending = [
            1.0,
            1.1368401966214219,
            7.646202816327117,
            6.651529192122977,
            16.82951700040185,
            9.600533199327506,
            9.353792060928335,
            2.0047545860152005,
        ];
        let gains = [
            0.214325331689727,
            0.9742992255454671,
            0.5704580350760077,
            2.5301726135896807,
            0.8699127334053722,
            6.725837843393368,
            1.1368401966214219,
        ];
        let d = design(7, 3.0, 2.0);
        let c = d.monic_denominator().unwrap();
        for (got, want) in c.iter().rev().zip(descending) {
            assert!(close(*got, want, 1e-12), "{got} vs {want}");
        }
        for (got, want) in d.gains(1e-3).unwrap().iter().zip(gains) {
            assert!(close(*got, want, 1e-12), "{got} vs {want}");
        }
        // Slowest pole −0.0563 ± 1.965j (17.8 s time constant).
        let slow = d.poles().unwrap().iter().map(|p| -p.0).fold(f64::INFINITY, f64::min);
        assert!((slow - 0.0563).abs() < 1e-4 && (1.0 / slow - 17.8).abs() < 0.05);
    }

    #[test]
    fn gains_rebuild_the_denominator_by_eq_20() {
        let d = design(5, 1.0, 7.0);
        let c = d.monic_denominator().unwrap();
        let k = estimator_gains(&c);
        for j in 0..5 {
            let prod: f64 = k[j..].iter().product();
            assert!(close(prod, c[j], 1e-12));
        }
    }

    #[test]
    fn stability_bound_table() {
        // Largest stable passband edge [rad/s] per order r, for a ripple of 3 dB and of 1 dB.
        let ripples_db = [3.0, 1.0];
        let table = [
            (1, [1995.0, 1017.0]),
            (2, [910.0, 995.0]),
            (3, [355.0, 497.0]),
            (5, [117.0, 181.0]),
            (7, [58.0, 92.0]),
            (10, [28.0, 45.0]),
            (13, [16.5, 26.5]),
        ];
        for (r, edges) in table {
            for (ripple_db, wp) in ripples_db.into_iter().zip(edges) {
                let got = design(r, ripple_db, 1.0).max_stable_passband_rad_s(1e-3).unwrap();
                assert!((got - wp).abs() / wp < 0.01, "r {r}, {ripple_db} dB: {got} vs {wp}");
            }
        }
    }

    #[test]
    fn unstable_design_is_refused_naming_the_bound() {
        let e = design(13, 3.0, 20.0).gains(1e-3).unwrap_err();
        match e {
            DesignError::Unstable { max_stable_wp, .. } => assert!((max_stable_wp - 16.5).abs() < 0.2),
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().contains("largest stable passband edge"));
        assert!(design(13, 3.0, 2.0).gains(1e-3).is_ok());
        assert!(matches!(design(0, 3.0, 2.0).gains(1e-3), Err(DesignError::Order(0))));
        assert!(matches!(design(2, -1.0, 2.0).gains(1e-3), Err(DesignError::Ripple(_))));
        assert!(matches!(
            design(2, 3.0, f64::NAN).gains(1e-3),
            Err(DesignError::Passband(_))
        ));
    }
}
