//! Applies one unit's [`SensorFault`] to the healthy samples of its model (docs/model.md §10.6).
//!
//! The models always run, fault or not: their noise, bias and drift keep evolving while a sensor
//! is off, and their random streams never depend on faults. The layer draws from a stream of its
//! own, records every healthy sample in a fixed delay line (for `Delayed`) and remembers the last
//! healthy one (for `Stuck`).

use rand_chacha::ChaCha8Rng;

use super::fault::{SensorFault, SensorUnit, MAX_EXTRA_DELAY_S};
use super::gauss::uniform;
use super::ring::Ring;
use super::schedule::TIME_EPS_S;

/// What a per-sensor `Wrong` or `Garbage` rule may use.
pub(crate) struct FaultCtx<'a> {
    /// The failed unit (the IMU halves share a sample type).
    pub(crate) unit: SensorUnit,
    /// Time since the fault's onset [s].
    pub(crate) since_onset_s: f64,
    /// A uniform in [0, 1) drawn once at the onset.
    pub(crate) onset_draw: f64,
    /// The layer's own stream.
    pub(crate) rng: &'a mut ChaCha8Rng,
}

/// A sample type the fault layer can handle.
pub(crate) trait Reading: Copy {
    /// Time stamp [s].
    fn t_s(&self) -> f64;
    /// The same values with time stamp `t_s` [s].
    fn restamped(self, t_s: f64) -> Self;
    /// A `Garbage` sample replacing this healthy one.
    fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self;
    /// A `Wrong` sample replacing this healthy one.
    fn wrong(self, ctx: &mut FaultCtx<'_>) -> Self;
}

/// The fault state of one unit.
#[derive(Debug, Clone)]
pub(crate) struct FaultLayer<S> {
    unit: SensorUnit,
    fault: SensorFault,
    rng: ChaCha8Rng,
    /// Time of the first `apply` after the fault was set [s].
    onset_s: Option<f64>,
    onset_draw: f64,
    /// Healthy samples produced since the onset.
    produced: u64,
    /// Intermittent: current window index and whether it is on.
    window: Option<(u64, bool)>,
    last_good: Option<S>,
    history: Ring<S>,
}

impl<S: Reading> FaultLayer<S> {
    /// A healthy layer for `unit`, whose model produces at most `rate_hz` [Hz] samples; the delay
    /// line covers [`MAX_EXTRA_DELAY_S`] at that rate. `fill` only initialises storage.
    pub(crate) fn new(unit: SensorUnit, rate_hz: f64, rng: ChaCha8Rng, fill: S) -> Self {
        let rate = if rate_hz.is_finite() {
            rate_hz.clamp(1.0, 10_000.0)
        } else {
            1.0
        };
        let capacity = (MAX_EXTRA_DELAY_S * rate).ceil() as usize + 2;
        Self {
            unit,
            fault: SensorFault::Ok,
            rng,
            onset_s: None,
            onset_draw: 0.0,
            produced: 0,
            window: None,
            last_good: None,
            history: Ring::new(capacity, fill),
        }
    }

    /// The active fault.
    pub(crate) fn fault(&self) -> SensorFault {
        self.fault
    }

    /// Sets the fault (sanitised); a different fault starts a new onset.
    pub(crate) fn set(&mut self, fault: SensorFault) {
        let fault = fault.sanitized();
        if fault != self.fault {
            self.fault = fault;
            self.onset_s = None;
            self.produced = 0;
            self.window = None;
        }
    }

    /// What the flight controller receives at plant time `t_s` [s] when the model produced
    /// `healthy` (or nothing) in this call.
    pub(crate) fn apply(&mut self, t_s: f64, healthy: Option<S>) -> Option<S> {
        let onset_s = match self.onset_s {
            Some(t) => t,
            None => {
                self.onset_draw = uniform(&mut self.rng);
                *self.onset_s.insert(t_s)
            }
        };
        let s = healthy?;
        self.history.push_back(s);
        let mut ctx = FaultCtx {
            unit: self.unit,
            since_onset_s: t_s - onset_s,
            onset_draw: self.onset_draw,
            rng: &mut self.rng,
        };
        let out = match self.fault {
            SensorFault::Ok => Some(s),
            SensorFault::Off => None,
            SensorFault::Stuck => Some(self.last_good.get_or_insert(s).restamped(t_s)),
            SensorFault::Garbage => Some(s.garbage(&mut ctx)),
            SensorFault::Wrong => Some(s.wrong(&mut ctx)),
            SensorFault::Slow { divisor } => (self.produced % u64::from(divisor.max(1)) == 0).then_some(s),
            SensorFault::Delayed { extra_s } => self.delayed(t_s - extra_s).map(|d| d.restamped(t_s)),
            SensorFault::Intermittent { period_s, availability } => {
                self.window_on(t_s - onset_s, period_s, availability).then_some(s)
            }
        };
        if self.fault != SensorFault::Stuck {
            self.last_good = Some(s);
        }
        self.produced += 1;
        out
    }

    /// The newest recorded sample taken at or before `t_s`; the oldest one when the line no longer
    /// reaches back that far; nothing before the first such sample exists.
    fn delayed(&self, t_s: f64) -> Option<S> {
        if let Some(s) = self.history.newest_first().find(|s| s.t_s() <= t_s + TIME_EPS_S) {
            return Some(s);
        }
        if self.history.is_full() {
            self.history.front()
        } else {
            None
        }
    }

    /// Whether the window containing `since_onset_s` delivers; one draw per window entered.
    fn window_on(&mut self, since_onset_s: f64, period_s: f64, availability: f64) -> bool {
        let index = ((since_onset_s + TIME_EPS_S) / period_s).floor().max(0.0) as u64;
        match self.window {
            Some((w, on)) if w == index => on,
            _ => {
                let on = uniform(&mut self.rng) < availability;
                self.window = Some((index, on));
                on
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::gauss::seeded_stream;

    /// A scalar reading: garbage is the onset draw, wrong adds the time since onset.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Scalar {
        t_s: f64,
        x: f64,
    }

    impl Reading for Scalar {
        fn t_s(&self) -> f64 {
            self.t_s
        }
        fn restamped(self, t_s: f64) -> Self {
            Self { t_s, ..self }
        }
        fn garbage(self, ctx: &mut FaultCtx<'_>) -> Self {
            Self {
                x: ctx.onset_draw,
                ..self
            }
        }
        fn wrong(self, ctx: &mut FaultCtx<'_>) -> Self {
            Self {
                x: self.x + ctx.since_onset_s,
                ..self
            }
        }
    }

    /// A 10 Hz layer (delay line of 12 samples).
    fn layer() -> FaultLayer<Scalar> {
        FaultLayer::new(SensorUnit::Baro, 10.0, seeded_stream(1, 8), Scalar { t_s: 0.0, x: 0.0 })
    }

    /// Sample k of a 10 Hz sensor whose value is 100 k.
    fn sample(k: u32) -> Scalar {
        Scalar {
            t_s: f64::from(k) * 0.1,
            x: 100.0 * f64::from(k),
        }
    }

    #[test]
    fn stuck_without_an_earlier_sample_sticks_at_the_first_one() {
        let mut l = layer();
        l.set(SensorFault::Stuck);
        assert_eq!(l.apply(0.0, Some(sample(0))), Some(sample(0)));
        assert_eq!(
            l.apply(0.1, Some(sample(1))),
            Some(sample(0).restamped(0.1)),
            "stuck at the first one"
        );
        assert_eq!(l.apply(0.15, None), None, "no healthy sample, nothing repeated");
    }

    #[test]
    fn delayed_waits_at_start_and_falls_back_to_the_oldest_sample_past_its_capacity() {
        let mut l = layer();
        l.set(SensorFault::Delayed { extra_s: 0.25 });
        assert_eq!(l.apply(0.0, Some(sample(0))), None);
        assert_eq!(l.apply(0.1, Some(sample(1))), None);
        assert_eq!(l.apply(0.2, Some(sample(2))), None);
        assert_eq!(l.apply(0.3, Some(sample(3))), Some(sample(0).restamped(0.3)));
        l.set(SensorFault::Delayed { extra_s: 1.0 });
        for k in 4..20 {
            let expected = (k >= 10).then(|| sample(k - 10).restamped(f64::from(k) * 0.1));
            assert_eq!(l.apply(f64::from(k) * 0.1, Some(sample(k))), expected, "k {k}");
        }
        // A sensor faster than its layer was sized for (1 Hz: a 3-sample line) delayed by 1 s:
        // once the line is full, the oldest sample it still holds.
        let mut fast = FaultLayer::new(SensorUnit::Baro, 1.0, seeded_stream(1, 8), sample(0));
        fast.set(SensorFault::Delayed { extra_s: 1.0 });
        assert_eq!(fast.apply(0.0, Some(sample(0))), None);
        assert_eq!(fast.apply(0.1, Some(sample(1))), None);
        for k in 2..20 {
            assert_eq!(
                fast.apply(f64::from(k) * 0.1, Some(sample(k))).unwrap().x,
                100.0 * f64::from(k - 2)
            );
        }
    }

    #[test]
    fn onset_is_the_first_apply_after_a_change_and_repeating_a_fault_keeps_it() {
        let mut l = layer();
        l.apply(0.0, Some(sample(0)));
        l.set(SensorFault::Wrong);
        assert_eq!(l.apply(0.5, None), None);
        assert!(
            (l.apply(0.6, Some(sample(6))).unwrap().x - 600.1).abs() < 1e-12,
            "onset at 0.5 s"
        );
        l.set(SensorFault::Wrong);
        let out = l.apply(0.7, Some(sample(7))).unwrap();
        assert!((out.x - (700.0 + 0.2)).abs() < 1e-12);
        let draw = l.apply(0.8, Some(sample(8))).map(|s| s.x);
        l.set(SensorFault::Garbage);
        let g1 = l.apply(0.9, Some(sample(9))).unwrap().x;
        let g2 = l.apply(1.0, Some(sample(10))).unwrap().x;
        assert_eq!(g1, g2, "one onset draw");
        assert!((0.0..1.0).contains(&g1) && draw != Some(g1));
    }
}
