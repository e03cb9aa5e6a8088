//! When a sensor that runs slower than the plant produces a sample: on the grid t_k = k / rate.

/// Slack for comparing plant times with grid times [s]: the plant counts whole nanoseconds but
/// reports f64 seconds, so a grid time may be missed by a rounding error, never by 0.1 µs.
pub(crate) const TIME_EPS_S: f64 = 1e-7;

/// Sampling grid t_k = k / rate_hz, k = 0, 1, 2, … (docs/model.md §10.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RateSchedule {
    rate_hz: f64,
    next_k: u64,
}

impl RateSchedule {
    /// A grid at `rate_hz` [Hz] starting at t = 0; a rate that is not finite and positive never
    /// falls due.
    pub(crate) fn new(rate_hz: f64) -> Self {
        Self { rate_hz, next_k: 0 }
    }

    /// True when a grid time has been reached at plant time `t_s` [s]. At most one sample per
    /// call: grid times passed between two calls collapse into this one.
    pub(crate) fn due(&mut self, t_s: f64) -> bool {
        if !(self.rate_hz.is_finite() && self.rate_hz > 0.0 && t_s.is_finite()) {
            return false;
        }
        if t_s + TIME_EPS_S < self.next_k as f64 / self.rate_hz {
            return false;
        }
        // Saturating cast: a negative time gives 0.
        self.next_k = ((t_s + TIME_EPS_S) * self.rate_hz).floor() as u64 + 1;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_hertz_on_a_one_kilohertz_clock_falls_due_every_hundredth_tick() {
        let mut s = RateSchedule::new(10.0);
        let due: Vec<u64> = (0..1000u64).filter(|&i| s.due(i as f64 * 1e-3)).collect();
        assert_eq!(due, (0..10).map(|k| k * 100).collect::<Vec<_>>());
    }

    #[test]
    fn a_slow_caller_gets_one_sample_per_call_and_bad_rates_never_fall_due() {
        let mut s = RateSchedule::new(50.0);
        assert!(s.due(0.0));
        assert!(s.due(1.0));
        assert!(!s.due(1.0));
        assert!(s.due(1.02));
        for rate in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(!RateSchedule::new(rate).due(0.0));
        }
    }
}
