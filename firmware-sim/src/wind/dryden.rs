//! Dryden turbulence of MIL-F-8785C, low-altitude form (docs/model.md §5.3, eqs. (5.7)–(5.10)):
//! three shaping filters driven by seeded white noise give the gust velocity along the mean
//! wind (u), across it (v) and vertically (w).

use rand_chacha::ChaCha8Rng;

use crate::sensors::gauss::gaussian;

/// Metres per foot: the standard's scale lengths and heights are in feet.
const M_PER_FT: f64 = 0.3048;
/// Lowest and highest heights of the low-altitude model [ft].
const HEIGHT_RANGE_FT: (f64, f64) = (10.0, 1000.0);
/// Lowest airspeed the filters are evaluated at [m/s]: the frozen-field model needs the air to
/// move past the vehicle; below this the turbulence is carried past at this speed.
pub const MIN_AIRSPEED_M_S: f64 = 1.0;

/// Intensities σ [m/s] and scale lengths L [m] of the three components at one height
/// (docs/model.md §5.3, eqs. (5.7)–(5.8)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrydenScales {
    /// σ_u, σ_v, σ_w [m/s].
    pub sigma_m_s: [f64; 3],
    /// L_u, L_v, L_w [m].
    pub length_m: [f64; 3],
}

impl DrydenScales {
    /// Scales at height `height_m` [m] above ground for the wind speed `w20_m_s` [m/s] measured
    /// at 20 ft (6.1 m); the height is held within the model's 10–1000 ft.
    pub fn low_altitude(height_m: f64, w20_m_s: f64) -> Self {
        let h_ft = (height_m / M_PER_FT).clamp(HEIGHT_RANGE_FT.0, HEIGHT_RANGE_FT.1);
        let base = 0.177 + 0.000823 * h_ft;
        let sigma_w = 0.1 * w20_m_s;
        let sigma_uv = sigma_w / base.powf(0.4);
        let l_uv = h_ft / base.powf(1.2) * M_PER_FT;
        Self {
            sigma_m_s: [sigma_uv, sigma_uv, sigma_w],
            length_m: [l_uv, l_uv, h_ft * M_PER_FT],
        }
    }
}

/// The three shaping filters' states: u is first order, v and w second order
/// (docs/model.md §5.3, eqs. (5.9)–(5.10)).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DrydenFilter {
    u: f64,
    /// Per lateral/vertical component: (first lag, second lag).
    vw: [(f64, f64); 2],
}

impl DrydenFilter {
    /// Turbulence velocity along (u, v, w) = (mean-wind direction, across it, down) [m/s].
    pub fn velocity(&self) -> [f64; 3] {
        let out = |(a, z): (f64, f64)| (1.0 - 3f64.sqrt()) * z + 3f64.sqrt() * a;
        [self.u, out(self.vw[0]), out(self.vw[1])]
    }

    /// Advances the filters by `dt_s` [s] at `airspeed_m_s` [m/s] with the scales `scales`,
    /// drawing three normal variates from `rng`. The first-order filter is discretised exactly
    /// (docs/model.md §5.3, eq. (5.9)); the second-order ones by holding the white noise over the
    /// step (docs/model.md §5.3, eq. (5.10)),
    /// accurate while dt ≪ L/V.
    pub fn advance(&mut self, dt_s: f64, airspeed_m_s: f64, scales: &DrydenScales, rng: &mut ChaCha8Rng) {
        let v = airspeed_m_s.max(MIN_AIRSPEED_M_S);
        let noise = [gaussian(rng), gaussian(rng), gaussian(rng)];
        let tau_u = scales.length_m[0] / v;
        let a = (-dt_s / tau_u).exp();
        self.u = a * self.u + scales.sigma_m_s[0] * (1.0 - a * a).sqrt() * noise[0];
        for (k, (lag1, lag2)) in self.vw.iter_mut().enumerate() {
            let tau = scales.length_m[k + 1] / v;
            let gain = scales.sigma_m_s[k + 1] * tau.sqrt();
            let a = (-dt_s / tau).exp();
            // White noise of unit intensity held over the step has variance 1/dt.
            let xi = noise[k + 1] / dt_s.sqrt();
            let prev = *lag1;
            *lag1 = a * *lag1 + (1.0 - a) * gain * xi;
            *lag2 = a * *lag2 + (1.0 - a) * prev;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rand_chacha_seed;

    #[test]
    fn low_altitude_scales_follow_the_standard() {
        // At 1000 ft every component has σ = 0.1 W20 and L = 1000 ft.
        let s = DrydenScales::low_altitude(1000.0 * M_PER_FT, 15.0);
        assert!((s.sigma_m_s[2] - 1.5).abs() < 1e-12);
        assert!((s.sigma_m_s[0] / s.sigma_m_s[2] - 1.0).abs() < 1e-3);
        assert!((s.length_m[0] - 1000.0 * M_PER_FT).abs() < 1.0);
        // Near the ground the horizontal components are stronger and longer than the vertical.
        let s = DrydenScales::low_altitude(10.0, 5.0);
        assert!(s.sigma_m_s[0] > 1.5 * s.sigma_m_s[2]);
        assert!(s.length_m[0] > 3.0 * s.length_m[2]);
        // Below 10 ft the model holds its 10 ft values.
        assert_eq!(
            DrydenScales::low_altitude(0.0, 5.0),
            DrydenScales::low_altitude(10.0 * M_PER_FT, 5.0)
        );
    }

    #[test]
    fn stationary_variances_match_the_intensities() {
        let scales = DrydenScales {
            sigma_m_s: [1.0, 0.8, 0.5],
            length_m: [20.0, 20.0, 10.0],
        };
        let (dt, v) = (0.01, 20.0); // τ = 1 s and 0.5 s
        let mut f = DrydenFilter::default();
        let mut rng = rand_chacha_seed(3);
        for _ in 0..2_000 {
            f.advance(dt, v, &scales, &mut rng);
        }
        let n = 400_000;
        let mut sum2 = [0.0; 3];
        let mut sum = [0.0; 3];
        for _ in 0..n {
            f.advance(dt, v, &scales, &mut rng);
            for (k, x) in f.velocity().iter().enumerate() {
                sum[k] += x;
                sum2[k] += x * x;
            }
        }
        for k in 0..3 {
            let mean = sum[k] / n as f64;
            let sd = (sum2[k] / n as f64 - mean * mean).sqrt();
            let want = scales.sigma_m_s[k];
            assert!((sd / want - 1.0).abs() < 0.08, "component {k}: sd {sd} vs σ {want}");
            assert!(mean.abs() < 0.15 * want, "component {k}: mean {mean}");
        }
    }

    #[test]
    fn correlation_time_follows_scale_length_over_airspeed() {
        // u is first order: its autocorrelation at lag τ = L/V is e^{-1}.
        let scales = DrydenScales {
            sigma_m_s: [1.0, 1.0, 1.0],
            length_m: [10.0, 10.0, 10.0],
        };
        let (dt, v) = (0.01, 10.0);
        let lag = 100; // 1 s = τ
        let mut f = DrydenFilter::default();
        let mut rng = rand_chacha_seed(11);
        let mut hist = Vec::with_capacity(300_000);
        for _ in 0..300_000 {
            f.advance(dt, v, &scales, &mut rng);
            hist.push(f.velocity()[0]);
        }
        let var = hist.iter().map(|x| x * x).sum::<f64>() / hist.len() as f64;
        let cov = hist.windows(lag + 1).map(|w| w[0] * w[lag]).sum::<f64>() / (hist.len() - lag) as f64;
        let rho = cov / var;
        assert!((rho - (-1f64).exp()).abs() < 0.05, "ρ(τ) = {rho}");
    }

    #[test]
    fn same_seed_same_gusts() {
        let scales = DrydenScales::low_altitude(10.0, 5.0);
        let run = |seed| {
            let mut f = DrydenFilter::default();
            let mut rng = rand_chacha_seed(seed);
            for _ in 0..1000 {
                f.advance(1e-3, 5.0, &scales, &mut rng);
            }
            f.velocity()
        };
        assert_eq!(run(4), run(4));
        assert_ne!(run(4), run(5));
    }
}
