//! A sensor whose readings repeat exactly is stuck: PX4's data validator marks it stale after
//! 100 repeated values (a three-valued reading: 34 samples in a row) and the sensors module stops
//! publishing it, so the estimator sees no data from it until its readings change again
//! (docs/navigation_filter.md §9). A noisy sensor never repeats itself to the last bit. Pure.

/// Repeated values after which a sensor is stale (PX4's `VALUE_EQUAL_COUNT_DEFAULT`).
const EQUAL_VALUES_STALE: u32 = 100;

/// The stale check of one sensor of `N` values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaleCheck<const N: usize> {
    last: Option<[f64; N]>,
    equal_values: u32,
}

impl<const N: usize> Default for StaleCheck<N> {
    fn default() -> Self {
        Self {
            last: None,
            equal_values: 0,
        }
    }
}

impl<const N: usize> StaleCheck<N> {
    /// Takes a reading; true when it may be used (the sensor is not stale).
    pub fn accept(&mut self, values: [f64; N]) -> bool {
        let repeated = self.last.is_some_and(|last| last == values);
        self.equal_values = if repeated {
            self.equal_values.saturating_add(N as u32)
        } else {
            0
        };
        self.last = Some(values);
        !self.stale()
    }

    /// The readings have repeated for too long.
    pub fn stale(&self) -> bool {
        self.equal_values > EQUAL_VALUES_STALE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reading_repeated_34_times_is_stale_until_it_changes() {
        let mut c = StaleCheck::<3>::default();
        assert!(c.accept([1.0, 2.0, 3.0]));
        for _ in 0..33 {
            assert!(c.accept([1.0, 2.0, 3.0]));
        }
        assert!(!c.accept([1.0, 2.0, 3.0]), "the 35th equal reading");
        assert!(c.stale());
        assert!(c.accept([1.0, 2.0, 3.000_001]), "changed");
        let mut noisy = StaleCheck::<1>::default();
        assert!((0..1000).all(|k| noisy.accept([f64::from(k % 2)])));
    }
}
