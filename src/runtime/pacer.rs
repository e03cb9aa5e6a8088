//! Pacing simulated time against the wall clock, for the autopilot's tick threads and
//! `sim --speedup`. Tick k is due at the deadline `t0 + k·dt/N` (N = speed-up); nothing waits at
//! `--speedup max`. When late, the missed ticks run back-to-back with the fixed dt (physics never
//! skips) up to [`MAX_BACKLOG`] of wall time, then the schedule is rebased on now and an overrun
//! counted. The [`Pacer`] is given the time and says how long to sleep; the thread sleeps.

use std::time::{Duration, Instant};

/// Missed ticks run back-to-back up to this much wall time before the schedule is rebased.
pub const MAX_BACKLOG: Duration = Duration::from_millis(100);

/// Slowest and fastest numeric speed-up.
pub const SPEEDUP_RANGE: (f64, f64) = (0.1, 1000.0);

/// How fast simulated time runs against the wall clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pace {
    /// Simulated seconds per wall second (0.1 … 1000; 1 = real time).
    Speedup(f64),
    /// As fast as the CPU allows.
    Max,
}

impl Pace {
    /// Wall time of one tick of `dt`, `None` for [`Pace::Max`].
    pub fn tick_period(self, dt: Duration) -> Option<Duration> {
        match self {
            Pace::Speedup(x) => Some(dt.div_f64(x)),
            Pace::Max => None,
        }
    }
}

impl std::str::FromStr for Pace {
    type Err = String;

    /// `max`, or a number of simulated seconds per wall second in [`SPEEDUP_RANGE`].
    fn from_str(text: &str) -> Result<Self, String> {
        if text.trim().eq_ignore_ascii_case("max") {
            return Ok(Pace::Max);
        }
        let (lo, hi) = SPEEDUP_RANGE;
        match text.trim().parse::<f64>() {
            Ok(x) if (lo..=hi).contains(&x) => Ok(Pace::Speedup(x)),
            _ => Err(format!("--speedup {text}: must be a number from {lo} to {hi}, or max")),
        }
    }
}

/// What to do before the next tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wait {
    /// Sleep this long, then tick.
    Sleep(Duration),
    /// Tick now (due, or late within the backlog).
    Now,
    /// Tick now: the backlog exceeded [`MAX_BACKLOG`] and the schedule starts again from now
    /// (one overrun).
    Rebased,
}

/// The deadline schedule of a paced loop (module docs).
#[derive(Debug, Clone)]
pub struct Pacer {
    period: Option<Duration>,
    base: Instant,
    next: u64,
}

impl Pacer {
    /// A schedule of `pace` for ticks of `dt`, tick 0 due at `start`.
    pub fn new(pace: Pace, dt: Duration, start: Instant) -> Self {
        Self {
            period: pace.tick_period(dt),
            base: start,
            next: 0,
        }
    }

    /// Paced at all (false at [`Pace::Max`], where [`Self::next_tick`] always says [`Wait::Now`]).
    pub fn is_paced(&self) -> bool {
        self.period.is_some()
    }

    /// At wall time `now`, what to do before the next tick; the tick is then counted as run.
    pub fn next_tick(&mut self, now: Instant) -> Wait {
        let Some(period) = self.period else {
            return Wait::Now;
        };
        let deadline = self.base + period.mul_f64(self.next as f64);
        let wait = if deadline > now {
            Wait::Sleep(deadline - now)
        } else if now - deadline > MAX_BACKLOG {
            self.base = now;
            self.next = 0;
            Wait::Rebased
        } else {
            Wait::Now
        };
        self.next += 1;
        wait
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_period_scales_with_the_speedup() {
        let dt = Duration::from_millis(1);
        assert_eq!(Pace::Speedup(1.0).tick_period(dt), Some(dt));
        assert_eq!(Pace::Speedup(20.0).tick_period(dt), Some(Duration::from_micros(50)));
        assert_eq!(Pace::Speedup(0.1).tick_period(dt), Some(Duration::from_millis(10)));
        assert_eq!(Pace::Max.tick_period(dt), None);
    }

    #[test]
    fn speedup_parses_numbers_in_range_and_max() {
        assert_eq!("20".parse::<Pace>(), Ok(Pace::Speedup(20.0)));
        assert_eq!("MAX".parse::<Pace>(), Ok(Pace::Max));
        assert_eq!("0.1".parse::<Pace>(), Ok(Pace::Speedup(0.1)));
        for bad in ["0", "1001", "fast", "NaN", "-2"] {
            let e = bad.parse::<Pace>().unwrap_err();
            assert!(e.contains(bad) && e.contains("or max"), "{e}");
        }
    }

    #[test]
    fn deadlines_advance_by_one_period_per_tick() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let mut p = Pacer::new(Pace::Speedup(2.0), ms(2), t0);
        assert!(p.is_paced());
        // Tick 0 is due at t0, tick 1 at t0 + 1 ms, tick 2 at t0 + 2 ms.
        assert_eq!(p.next_tick(t0), Wait::Now);
        assert_eq!(p.next_tick(t0), Wait::Sleep(ms(1)));
        assert_eq!(
            p.next_tick(t0 + ms(1) + Duration::from_micros(500)),
            Wait::Sleep(Duration::from_micros(500))
        );
        // Late within the backlog: tick 3 (due at 3 ms) runs at once at 50 ms.
        assert_eq!(p.next_tick(t0 + ms(50)), Wait::Now);
    }

    #[test]
    fn a_backlog_beyond_the_limit_rebases_the_schedule() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let mut p = Pacer::new(Pace::Speedup(1.0), ms(1), t0);
        assert_eq!(p.next_tick(t0), Wait::Now);
        let late = t0 + ms(1) + MAX_BACKLOG + ms(1);
        assert_eq!(p.next_tick(late), Wait::Rebased);
        // The schedule starts again at `late`: the next tick is due 1 ms later.
        assert_eq!(p.next_tick(late), Wait::Sleep(ms(1)));
    }

    #[test]
    fn max_never_waits() {
        let t0 = Instant::now();
        let mut p = Pacer::new(Pace::Max, Duration::from_millis(1), t0);
        assert!(!p.is_paced());
        for _ in 0..3 {
            assert_eq!(p.next_tick(t0), Wait::Now);
        }
    }
}
