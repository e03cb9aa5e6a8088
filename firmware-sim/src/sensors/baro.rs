//! The barometer: static pressure and temperature of the ISA troposphere at the vehicle's
//! altitude (docs/model.md §10.4, eqs. (10.9)–(10.11)).
//!
//! Altitude above mean sea level is the origin's altitude minus the NED z coordinate. Noise and
//! drift are given **in metres of altitude** and added to that altitude before it is turned into
//! a pressure, so they mean the same at every height. The temperature is that of the true
//! altitude, without noise.
//!
//! Faults (docs/model.md §10.6): `Wrong` reports the pressure of an altitude 100 m higher (the
//! offset PX4 uses for a wrong GPS altitude); `Garbage` draws the pressure uniformly over a
//! MS5611-class sensor's range, 10–1200 mbar, and the temperature over −40…85 °C.

use rand_chacha::ChaCha8Rng;

use super::fault_layer::{FaultCtx, Reading};
use super::gauss::{gaussian, uniform_in};
use super::schedule::RateSchedule;
use crate::plant::TruthState;

/// ISA sea-level pressure p_0 [Pa].
pub const ISA_SEA_LEVEL_PA: f64 = 101_325.0;
/// ISA sea-level temperature T_0 [K].
pub const ISA_SEA_LEVEL_K: f64 = 288.15;
/// ISA temperature lapse rate Γ of the troposphere [K/m].
pub const ISA_LAPSE_K_M: f64 = 0.0065;
/// Exponent g_0 / (R Γ) of the ISA pressure (docs/model.md §10.4, eq. (10.11)), with
/// g_0 = 9.80665 m/s² and the specific gas constant of dry air R = 287.05287 J/(kg·K) [-].
pub const ISA_EXPONENT: f64 = 9.806_65 / (287.052_87 * ISA_LAPSE_K_M);
/// Altitude offset of the `Wrong` fault [m].
pub const BARO_WRONG_OFFSET_M: f64 = 100.0;

/// Temperature of the ISA troposphere at `alt_m` [m] above mean sea level [K]
/// (docs/model.md §10.4, eq. (10.10)).
pub fn isa_temperature_k(alt_m: f64) -> f64 {
    ISA_SEA_LEVEL_K - ISA_LAPSE_K_M * alt_m
}

/// Pressure of the ISA troposphere at `alt_m` [m] above mean sea level [Pa]
/// (docs/model.md §10.4, eq. (10.11)); valid up to the tropopause at 11 km.
pub fn isa_pressure_pa(alt_m: f64) -> f64 {
    ISA_SEA_LEVEL_PA * (isa_temperature_k(alt_m) / ISA_SEA_LEVEL_K).powf(ISA_EXPONENT)
}

/// Altitude above mean sea level [m] at which the ISA troposphere has pressure `pressure_pa`
/// [Pa]: the inverse of [`isa_pressure_pa`].
pub fn isa_altitude_m(pressure_pa: f64) -> f64 {
    (1.0 - (pressure_pa / ISA_SEA_LEVEL_PA).powf(1.0 / ISA_EXPONENT)) * ISA_SEA_LEVEL_K / ISA_LAPSE_K_M
}

/// Barometer parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaroConfig {
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// Altitude above mean sea level of the plant's origin, z = 0 [m]; `None`: the home's
    /// altitude, wherever the vehicle is placed (`rotorpilot run --home`).
    pub origin_alt_m: Option<f64>,
    /// White noise, standard deviation in altitude [m].
    pub noise_m: f64,
    /// Random walk of the altitude offset: it changes by N(0, σ²Δt) over Δt [m/√s].
    pub drift_m_sqrt_s: f64,
}

impl BaroConfig {
    /// PX4 SITL's simulated barometer (`sensor_baro_sim`), the default: 50 Hz at the home's
    /// altitude, white noise of 1 Pa (≈ 0.085 m at PX4's default home, 488 m), no drift.
    pub fn typical() -> Self {
        Self {
            rate_hz: 50.0,
            origin_alt_m: None,
            noise_m: 0.085,
            drift_m_sqrt_s: 0.0,
        }
    }

    /// A barometer under propeller wash on a real vehicle: noise 0.5 m (below EKF2_BARO_NOISE =
    /// 3.5 m, the estimator's deliberately cautious figure) and a drift of 0.03 m/√s, about
    /// 0.7 m over ten minutes. Rate and origin as typical.
    pub fn hardware() -> Self {
        Self {
            noise_m: 0.5,
            drift_m_sqrt_s: 0.03,
            ..Self::typical()
        }
    }

    /// No noise and no drift: the exact ISA pressure of the true altitude.
    pub fn ideal() -> Self {
        Self {
            noise_m: 0.0,
            drift_m_sqrt_s: 0.0,
            ..Self::typical()
        }
    }
}

/// One barometer sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaroSample {
    /// Time of the sample [s].
    pub t_s: f64,
    /// Static pressure [Pa].
    pub pressure_pa: f64,
    /// Air temperature [°C].
    pub temperature_c: f64,
}

impl BaroSample {
    pub(crate) const ZERO: Self = Self {
        t_s: 0.0,
        pressure_pa: 0.0,
        temperature_c: 0.0,
    };
}

impl Reading for BaroSample {
    fn t_s(&self) -> f64 {
        self.t_s
    }

    fn restamped(self, t_s: f64) -> Self {
        Self { t_s, ..self }
    }

    fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self {
        Self {
            pressure_pa: uniform_in(ctx.rng, 1_000.0, 120_000.0),
            temperature_c: uniform_in(ctx.rng, -40.0, 85.0),
            ..self
        }
    }

    fn wrong(self, _ctx: &mut FaultCtx<'_>) -> Self {
        Self {
            pressure_pa: isa_pressure_pa(isa_altitude_m(self.pressure_pa) + BARO_WRONG_OFFSET_M),
            ..self
        }
    }
}

/// The healthy barometer.
#[derive(Debug, Clone)]
pub(crate) struct BaroModel {
    config: BaroConfig,
    /// Altitude above mean sea level of z = 0 [m].
    origin_alt_m: f64,
    rng: ChaCha8Rng,
    schedule: RateSchedule,
    /// Altitude offset d [m] (docs/model.md §10.4, eq. (10.9)).
    drift_m: f64,
    last_t_s: Option<f64>,
}

impl BaroModel {
    /// A barometer without drift yet, its origin (z = 0) at `origin_alt_m` [m] above mean sea
    /// level.
    pub(crate) fn new(config: BaroConfig, origin_alt_m: f64, rng: ChaCha8Rng) -> Self {
        Self {
            config,
            origin_alt_m,
            rng,
            schedule: RateSchedule::new(config.rate_hz),
            drift_m: 0.0,
            last_t_s: None,
        }
    }

    /// The sample of this tick, if one falls due (docs/model.md §10.4, eq. (10.9)); two normals per
    /// sample.
    pub(crate) fn read(&mut self, truth: &TruthState) -> Option<BaroSample> {
        if !self.schedule.due(truth.t_s) {
            return None;
        }
        let c = &self.config;
        let dt = match self.last_t_s {
            Some(t) if truth.t_s > t => truth.t_s - t,
            _ => 0.0,
        };
        self.last_t_s = Some(truth.t_s);
        self.drift_m += c.drift_m_sqrt_s * dt.sqrt() * gaussian(&mut self.rng);
        let noise_m = c.noise_m * gaussian(&mut self.rng);
        let alt_m = self.origin_alt_m - truth.body.pos_w.z;
        Some(BaroSample {
            t_s: truth.t_s,
            pressure_pa: isa_pressure_pa(alt_m + self.drift_m + noise_m),
            temperature_c: isa_temperature_k(alt_m) - 273.15,
        })
    }

    /// Current altitude offset [m] (truth for logs and tests).
    pub(crate) fn drift_m(&self) -> f64 {
        self.drift_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::gauss::seeded_stream;
    use crate::sensors::test_support::{stats, tick_s, truth_at};

    #[test]
    fn isa_pressure_at_known_altitudes() {
        assert_eq!(isa_pressure_pa(0.0), ISA_SEA_LEVEL_PA);
        assert!(
            (isa_pressure_pa(1000.0) - 89_874.6).abs() < 0.5,
            "{}",
            isa_pressure_pa(1000.0)
        );
        // Tropopause, 11 km: 22 632 Pa and 216.65 K in the standard atmosphere tables.
        assert!(
            (isa_pressure_pa(11_000.0) - 22_632.0).abs() < 2.0,
            "{}",
            isa_pressure_pa(11_000.0)
        );
        assert!((isa_temperature_k(11_000.0) - 216.65).abs() < 1e-9);
        for h in [-400.0, 0.0, 488.0, 3000.0, 10_000.0] {
            assert!((isa_altitude_m(isa_pressure_pa(h)) - h).abs() < 1e-6, "{h}");
        }
    }

    #[test]
    fn ideal_barometer_reads_the_isa_pressure_of_origin_altitude_minus_z_at_fifty_hertz() {
        let mut baro = BaroModel::new(BaroConfig::ideal(), 488.0, seeded_stream(1, 4));
        let mut n = 0;
        for i in 0..10_000 {
            let mut truth = truth_at(tick_s(i));
            truth.body.pos_w.z = -0.01 * i as f64;
            if let Some(s) = baro.read(&truth) {
                let alt = 488.0 + 0.01 * i as f64;
                assert_eq!(s.pressure_pa, isa_pressure_pa(alt));
                assert_eq!(s.temperature_c, isa_temperature_k(alt) - 273.15);
                assert_eq!(s.t_s, truth.t_s);
                assert_eq!(i % 20, 0);
                n += 1;
            }
        }
        assert_eq!(n, 500);
    }

    #[test]
    fn altitude_noise_has_the_configured_deviation() {
        let config = BaroConfig {
            noise_m: 0.5,
            ..BaroConfig::ideal()
        };
        let mut baro = BaroModel::new(config, 488.0, seeded_stream(2, 4));
        let alt = 488.0 + 1.0; // truth_at is 1 m above the origin
        let errors: Vec<f64> = (0..50_000)
            .map(|k| {
                let t = truth_at(k as f64 / 50.0);
                let s = baro.read(&t).unwrap();
                isa_altitude_m(s.pressure_pa) - alt
            })
            .collect();
        let (mean, var) = stats(&errors);
        assert!(mean.abs() < 5.0 * 0.5 / (50_000f64).sqrt(), "mean {mean}");
        assert!((var / 0.25 - 1.0).abs() < 5.0 * (2.0 / 50_000f64).sqrt(), "var {var}");
    }

    #[test]
    fn drift_variance_grows_as_sigma_squared_t() {
        let config = BaroConfig {
            drift_m_sqrt_s: 0.03,
            ..BaroConfig::ideal()
        };
        let mut ends = Vec::new();
        for seed in 0..3000 {
            let mut baro = BaroModel::new(config, 488.0, seeded_stream(seed, 4));
            for k in 0..=500 {
                baro.read(&truth_at(k as f64 / 50.0));
            }
            ends.push(baro.drift_m());
        }
        // After 10 s: Var d = σ² t = 0.009 m²; 3000 values give √(2/3000) ≈ 2.6 % standard error.
        let (_, var) = stats(&ends);
        assert!((var / (0.03 * 0.03 * 10.0) - 1.0).abs() < 0.13, "var {var}");
    }
}
