//! The GPS receiver: position and velocity in the plant's local NED frame at a fixed rate, with
//! latency, white noise and a slowly wandering error (docs/model.md §10.3, eqs. (10.6)–(10.8)).
//!
//! Measurements are taken on the grid t_k = k / rate and delivered `latency_s` later: the sample
//! arriving at t measures the truth at t − latency and is time-stamped t (its arrival). Pending
//! measurements wait in a ring buffer sized at construction. The flight controller converts the
//! local position to latitude and longitude itself.
//!
//! Faults (docs/model.md §10.6), after PX4's GNSS failure injection: `Wrong` makes the position
//! drift east at up to 2 m/s, blended in over 5 s so position and velocity stay consistent, while
//! the fix still looks healthy; `Garbage` loses the fix for 1–6 s (drawn at the onset), then
//! delivers a degraded 3D fix with 2–6 satellites, h_acc 20–40 m, v_acc 30–54 m,
//! speed_acc 80–120 m/s, and position and velocity jitter within those accuracies.

use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

use super::fault_layer::{FaultCtx, Reading};
use super::gauss::{gaussian3, uniform_in};
use super::ring::Ring;
use super::schedule::{RateSchedule, TIME_EPS_S};
use crate::plant::TruthState;

/// Longest latency the GPS model accepts [s]; longer values are clamped.
pub const MAX_GPS_LATENCY_S: f64 = 1.0;
/// Speed the `Wrong` fault's position drift reaches [m/s] (docs/model.md §10.6, eq. (10.15)).
pub const GPS_WRONG_DRIFT_M_S: f64 = 2.0;
/// Blend-in time constant of the `Wrong` drift [s] (docs/model.md §10.6, eq. (10.15)).
pub const GPS_WRONG_BLEND_S: f64 = 5.0;

/// GPS parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsConfig {
    /// Measurement rate [Hz].
    pub rate_hz: f64,
    /// Time from measurement to delivery [s], in [0, [`MAX_GPS_LATENCY_S`]].
    pub latency_s: f64,
    /// Horizontal white position noise, standard deviation per axis [m].
    pub h_noise_m: f64,
    /// Vertical white position noise, standard deviation [m].
    pub v_noise_m: f64,
    /// Horizontal wandering error, stationary standard deviation per axis [m].
    pub h_wander_m: f64,
    /// Vertical wandering error, stationary standard deviation [m].
    pub v_wander_m: f64,
    /// Correlation time of the wandering error [s].
    pub wander_tau_s: f64,
    /// White velocity noise, standard deviation per axis [m/s].
    pub vel_noise_m_s: f64,
    /// Satellites used [-]; 4 or more give a 3D fix, 3 a 2D fix, fewer none.
    pub satellites: u8,
    /// Horizontal accuracy the receiver reports [m].
    pub h_acc_m: f64,
    /// Vertical accuracy the receiver reports [m].
    pub v_acc_m: f64,
    /// Speed accuracy the receiver reports [m/s].
    pub speed_acc_m_s: f64,
}

impl GpsConfig {
    /// PX4 SITL's simulated receiver (`sensor_gps_sim`), the default: a position error that is a
    /// first-order Gauss–Markov process of 0.025 m per horizontal axis and 0.037 m vertically
    /// (1.5 ×) with a 0.46 s correlation time (PX4's 0.76 per 8 Hz step), no white part;
    /// velocity noise 0.024 m/s (its 0.02 m/s Markov process's stationary figure). 10 Hz;
    /// latency 110 ms (EKF2_GPS_DELAY). 10 satellites (SIM_GPS_USED); reported accuracies eph
    /// 0.9 m, epv 1.78 m, speed 0.4 m/s, as PX4 SITL reports them.
    pub fn typical() -> Self {
        Self {
            rate_hz: 10.0,
            latency_s: 0.11,
            h_noise_m: 0.0,
            v_noise_m: 0.0,
            h_wander_m: 0.025,
            v_wander_m: 0.037,
            wander_tau_s: 0.46,
            vel_noise_m_s: 0.024,
            satellites: 10,
            h_acc_m: 0.9,
            v_acc_m: 1.78,
            speed_acc_m_s: 0.4,
        }
    }

    /// A u-blox-class receiver on a real vehicle: white 0.3 m and wandering 0.4 m horizontally
    /// (together 0.5 m = EKF2_GPS_P_NOISE), vertical ones 1.5 times larger, the wander's
    /// correlation time 60 s (PX4's Gazebo GPS plugin), velocity noise 0.1 m/s (between PX4
    /// SITL's ≈ 0.02 m/s and EKF2_GPS_V_NOISE = 0.3 m/s). A height on it wanders by about half a
    /// metre a minute, as on a real vehicle. Rate, latency and reported figures as typical.
    pub fn hardware() -> Self {
        Self {
            h_noise_m: 0.3,
            v_noise_m: 0.45,
            h_wander_m: 0.4,
            v_wander_m: 0.6,
            wander_tau_s: 60.0,
            vel_noise_m_s: 0.1,
            ..Self::typical()
        }
    }

    /// No noise, no wander, no latency; rate, satellites and reported accuracies as typical.
    pub fn ideal() -> Self {
        Self {
            latency_s: 0.0,
            h_noise_m: 0.0,
            v_noise_m: 0.0,
            h_wander_m: 0.0,
            v_wander_m: 0.0,
            vel_noise_m_s: 0.0,
            ..Self::typical()
        }
    }

    /// The fix `satellites` give: 3D from 4, 2D with 3, none below.
    pub fn fix(&self) -> GpsFix {
        match self.satellites {
            0..=2 => GpsFix::NoFix,
            3 => GpsFix::Fix2d,
            _ => GpsFix::Fix3d,
        }
    }
}

/// Fix type as the receiver reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GpsFix {
    /// No position.
    NoFix,
    /// Horizontal position only.
    Fix2d,
    /// Full 3D position.
    Fix3d,
}

/// One GPS sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsSample {
    /// Arrival time [s]; the measurement is `latency_s` older.
    pub t_s: f64,
    /// Position in the plant's local NED frame [m].
    pub pos_w: Vector3<f64>,
    /// Velocity in NED [m/s].
    pub vel_w: Vector3<f64>,
    /// Reported horizontal accuracy [m].
    pub h_acc_m: f64,
    /// Reported vertical accuracy [m].
    pub v_acc_m: f64,
    /// Reported speed accuracy [m/s].
    pub speed_acc_m_s: f64,
    /// Fix type.
    pub fix: GpsFix,
    /// Satellites used [-].
    pub satellites: u8,
}

impl GpsSample {
    pub(crate) const ZERO: Self = Self {
        t_s: 0.0,
        pos_w: Vector3::new(0.0, 0.0, 0.0),
        vel_w: Vector3::new(0.0, 0.0, 0.0),
        h_acc_m: 0.0,
        v_acc_m: 0.0,
        speed_acc_m_s: 0.0,
        fix: GpsFix::NoFix,
        satellites: 0,
    };
}

impl Reading for GpsSample {
    fn t_s(&self) -> f64 {
        self.t_s
    }

    fn restamped(self, t_s: f64) -> Self {
        Self { t_s, ..self }
    }

    /// A lost fix for 1 + 5u seconds, then a degraded one (docs/model.md §10.6, eq. (10.16)).
    fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self {
        let blackout_s = 1.0 + 5.0 * ctx.onset_draw;
        if ctx.since_onset_s < blackout_s {
            return Self {
                vel_w: Vector3::zeros(),
                h_acc_m: 1e6,
                v_acc_m: 1e6,
                speed_acc_m_s: 100.0,
                fix: GpsFix::NoFix,
                satellites: 0,
                ..self
            };
        }
        let rng = &mut *ctx.rng;
        let satellites = uniform_in(rng, 2.0, 7.0).floor() as u8;
        let h_acc_m = uniform_in(rng, 20.0, 40.0);
        let v_acc_m = uniform_in(rng, 30.0, 54.0);
        let speed_acc_m_s = uniform_in(rng, 80.0, 120.0);
        let dp = Vector3::new(uniform_in(rng, -1.0, 1.0), uniform_in(rng, -1.0, 1.0), 0.0) * h_acc_m;
        let dv = Vector3::new(uniform_in(rng, -2.0, 2.0), uniform_in(rng, -2.0, 2.0), 0.0);
        Self {
            pos_w: self.pos_w + dp,
            vel_w: self.vel_w + dv,
            h_acc_m,
            v_acc_m,
            speed_acc_m_s,
            fix: GpsFix::Fix3d,
            satellites: satellites.clamp(2, 6),
            ..self
        }
    }

    /// An eastward drift, blended in; fix quality untouched (docs/model.md §10.6, eq. (10.15)).
    fn wrong(self, ctx: &mut FaultCtx<'_>) -> Self {
        let (p, v) = wrong_drift(ctx.since_onset_s);
        let east = Vector3::new(0.0, 1.0, 0.0);
        Self {
            pos_w: self.pos_w + east * p,
            vel_w: self.vel_w + east * v,
            ..self
        }
    }
}

/// Position [m] and velocity [m/s] offsets of the `Wrong` fault `s` seconds after its onset
/// (docs/model.md §10.6, eq. (10.15)).
pub fn wrong_drift(s: f64) -> (f64, f64) {
    let s = s.max(0.0);
    let blend = 1.0 - (-s / GPS_WRONG_BLEND_S).exp();
    (
        GPS_WRONG_DRIFT_M_S * (s - GPS_WRONG_BLEND_S * blend),
        GPS_WRONG_DRIFT_M_S * blend,
    )
}

/// The healthy receiver.
#[derive(Debug, Clone)]
pub(crate) struct GpsModel {
    config: GpsConfig,
    latency_s: f64,
    rng: ChaCha8Rng,
    schedule: RateSchedule,
    /// Gauss–Markov error ε [m] (docs/model.md §10.3, eq. (10.7)).
    wander_w: Vector3<f64>,
    last_measure_s: Option<f64>,
    /// Measurements waiting for their delivery time, stamped with their measurement time.
    pending: Ring<GpsSample>,
}

impl GpsModel {
    /// A receiver whose wandering error starts from its stationary distribution.
    pub(crate) fn new(config: GpsConfig, mut rng: ChaCha8Rng) -> Self {
        let latency_s = if config.latency_s.is_nan() {
            0.0
        } else {
            config.latency_s.clamp(0.0, MAX_GPS_LATENCY_S)
        };
        let rate = if config.rate_hz.is_finite() {
            config.rate_hz.clamp(0.0, 10_000.0)
        } else {
            0.0
        };
        let capacity = (latency_s * rate).ceil() as usize + 2;
        let wander_w = wander_sd(&config).component_mul(&gaussian3(&mut rng, 1.0));
        Self {
            config,
            latency_s,
            rng,
            schedule: RateSchedule::new(config.rate_hz),
            wander_w,
            last_measure_s: None,
            pending: Ring::new(capacity, GpsSample::ZERO),
        }
    }

    /// The sample delivered at this tick, if any: measure when a grid time is reached, deliver
    /// what is `latency_s` old (the newest, if a slow caller let several fall due).
    pub(crate) fn read(&mut self, truth: &TruthState) -> Option<GpsSample> {
        if self.schedule.due(truth.t_s) {
            let m = self.measure(truth);
            self.pending.push_back(m);
        }
        let mut out = None;
        while let Some(m) = self.pending.front() {
            if m.t_s + self.latency_s > truth.t_s + TIME_EPS_S {
                break;
            }
            self.pending.pop_front();
            out = Some(m.restamped(truth.t_s));
        }
        out
    }

    /// A measurement of `truth` (docs/model.md §10.3, eqs. (10.6)–(10.7)); nine normals whatever the
    /// configuration.
    fn measure(&mut self, truth: &TruthState) -> GpsSample {
        let c = &self.config;
        let dt = match self.last_measure_s {
            Some(t) if truth.t_s > t => truth.t_s - t,
            _ => 0.0,
        };
        self.last_measure_s = Some(truth.t_s);
        let phi = if c.wander_tau_s > 0.0 {
            (-dt / c.wander_tau_s).exp()
        } else {
            0.0
        };
        let w = gaussian3(&mut self.rng, 1.0);
        self.wander_w = self.wander_w * phi + wander_sd(c).component_mul(&w) * (1.0 - phi * phi).sqrt();
        let white = Vector3::new(c.h_noise_m, c.h_noise_m, c.v_noise_m).component_mul(&gaussian3(&mut self.rng, 1.0));
        let vel_noise = gaussian3(&mut self.rng, c.vel_noise_m_s);
        GpsSample {
            t_s: truth.t_s,
            pos_w: truth.body.pos_w + self.wander_w + white,
            vel_w: truth.body.vel_w + vel_noise,
            h_acc_m: c.h_acc_m,
            v_acc_m: c.v_acc_m,
            speed_acc_m_s: c.speed_acc_m_s,
            fix: c.fix(),
            satellites: c.satellites,
        }
    }

    /// Current wandering error [m] (truth for logs and tests).
    pub(crate) fn wander_w(&self) -> Vector3<f64> {
        self.wander_w
    }
}

/// Stationary standard deviations of the wandering error per NED axis [m].
fn wander_sd(c: &GpsConfig) -> Vector3<f64> {
    Vector3::new(c.h_wander_m, c.h_wander_m, c.v_wander_m)
}

#[cfg(test)]
#[path = "gps_tests.rs"]
mod tests;
