//! Wind: a mean wind, discrete gusts and Dryden turbulence (docs/model.md §5.2–§5.3), seeded and
//! deterministic. The plant feels the wind through its drag model: drag acts on the velocity
//! relative to the air, v − w (docs/model.md §5.1, eq. (5.1)).

pub mod dryden;
pub mod gust;
mod settings;

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

pub use dryden::{DrydenFilter, DrydenScales};
pub use gust::Gust;
pub(crate) use settings::wind_settings;

/// What blows: everything optional, still air by default.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WindSettings {
    /// Mean wind: the air's velocity in world NED [m/s] (a wind from the west is +east).
    pub mean_w: Vector3<f64>,
    /// Dryden turbulence intensity: the wind speed at 20 ft W20 [m/s] (docs/model.md §5.3, eq. (5.7));
    /// `None`: no turbulence.
    pub turbulence_w20_m_s: Option<f64>,
    /// Discrete gusts.
    pub gusts: Vec<Gust>,
}

impl WindSettings {
    /// True when no air moves at any time.
    pub fn is_calm(&self) -> bool {
        self.mean_w == Vector3::zeros() && self.turbulence_w20_m_s.is_none() && self.gusts.is_empty()
    }
}

/// The wind at the vehicle, advanced once per plant step.
#[derive(Debug, Clone)]
pub struct WindField {
    settings: WindSettings,
    filter: DrydenFilter,
    rng: ChaCha8Rng,
    velocity_w: Vector3<f64>,
}

impl WindField {
    /// A wind field with turbulence drawn from `seed`.
    pub fn new(settings: WindSettings, seed: u64) -> Self {
        Self {
            velocity_w: settings.mean_w,
            settings,
            filter: DrydenFilter::default(),
            rng: crate::rand_chacha_seed(seed ^ WIND_STREAM),
        }
    }

    /// The settings.
    pub fn settings(&self) -> &WindSettings {
        &self.settings
    }

    /// Replaces the settings; the turbulence filters keep their state (a new intensity takes
    /// over smoothly) and their random stream.
    pub fn set_settings(&mut self, settings: WindSettings) {
        self.settings = settings;
        if self.settings.turbulence_w20_m_s.is_none() {
            self.filter = DrydenFilter::default();
        }
    }

    /// The air's velocity at the vehicle after the last [`Self::advance`], world NED [m/s].
    pub fn velocity_w(&self) -> Vector3<f64> {
        self.velocity_w
    }

    /// Advances to the step starting at `t_s` [s] lasting `dt_s` [s] for a vehicle at
    /// `height_m` [m] above the ground moving at `vehicle_vel_w` (world NED [m/s]); returns
    /// the wind velocity held over the step: mean + gusts + turbulence rotated from the
    /// mean-wind axes into NED (docs/model.md §5.2, eq. (5.5)).
    pub fn advance(&mut self, t_s: f64, dt_s: f64, height_m: f64, vehicle_vel_w: &Vector3<f64>) -> Vector3<f64> {
        let mean = self.settings.mean_w;
        let mut w = mean;
        for g in &self.settings.gusts {
            w += g.velocity_w(t_s);
        }
        if let Some(w20) = self.settings.turbulence_w20_m_s {
            let scales = DrydenScales::low_altitude(height_m, w20);
            let airspeed = (mean - vehicle_vel_w).norm();
            self.filter.advance(dt_s, airspeed, &scales, &mut self.rng);
            let [u, v, down] = self.filter.velocity();
            let heading = if mean.xy().norm() > 1e-6 {
                mean.y.atan2(mean.x)
            } else {
                0.0
            };
            let (s, c) = heading.sin_cos();
            w += Vector3::new(c * u - s * v, s * u + c * v, down);
        }
        self.velocity_w = w;
        w
    }
}

/// Mixed into the seed so the wind's random stream differs from the sensors' for one seed.
const WIND_STREAM: u64 = 0x5749_4e44_5749_4e44;

#[cfg(test)]
mod tests {
    use super::*;

    fn field(turbulence: Option<f64>) -> WindField {
        WindField::new(
            WindSettings {
                mean_w: Vector3::new(0.0, 5.0, 0.0),
                turbulence_w20_m_s: turbulence,
                gusts: vec![Gust {
                    start_s: 1.0,
                    duration_s: 2.0,
                    peak_w: Vector3::new(0.0, 0.0, -1.0),
                }],
            },
            7,
        )
    }

    #[test]
    fn mean_and_gusts_without_turbulence_are_exact() {
        let mut f = field(None);
        assert_eq!(
            f.advance(0.5, 1e-3, 10.0, &Vector3::zeros()),
            Vector3::new(0.0, 5.0, 0.0)
        );
        let w = f.advance(2.0, 1e-3, 10.0, &Vector3::zeros());
        assert!((w - Vector3::new(0.0, 5.0, -1.0)).norm() < 1e-12);
    }

    #[test]
    fn turbulence_is_strongest_along_the_mean_wind_and_seeded() {
        let mut f = field(Some(5.0));
        let (mut se, mut sn) = (0.0, 0.0);
        let n = 200_000;
        for k in 0..n {
            let w = f.advance(100.0 + k as f64 * 1e-2, 1e-2, 10.0, &Vector3::zeros());
            se += (w.y - 5.0).powi(2);
            sn += w.x.powi(2);
        }
        // Both horizontal components have the same σ at this height; the mean wind is east, so
        // u (east) and v (north) carry it; the sample sds agree within 20 % of the standard's σ.
        let sigma = DrydenScales::low_altitude(10.0, 5.0).sigma_m_s[0];
        for sd in [(se / n as f64).sqrt(), (sn / n as f64).sqrt()] {
            assert!((sd / sigma - 1.0).abs() < 0.2, "sd {sd} vs σ {sigma}");
        }
        let mut a = field(Some(5.0));
        let mut b = field(Some(5.0));
        for k in 0..100 {
            let t = k as f64 * 1e-3;
            assert_eq!(
                a.advance(t, 1e-3, 10.0, &Vector3::zeros()),
                b.advance(t, 1e-3, 10.0, &Vector3::zeros())
            );
        }
    }
}
