//! A fixed-capacity ring buffer, allocated once: the sensor suite allocates nothing per call.

/// First-in first-out buffer of at most `capacity` values; pushing onto a full ring overwrites
/// the oldest value.
#[derive(Debug, Clone)]
pub(crate) struct Ring<T> {
    buf: Vec<T>,
    /// Index of the oldest value in `buf`.
    start: usize,
    len: usize,
}

impl<T: Copy> Ring<T> {
    /// An empty ring holding up to `capacity` (at least 1) values; `fill` only initialises storage.
    pub(crate) fn new(capacity: usize, fill: T) -> Self {
        Self {
            buf: vec![fill; capacity.max(1)],
            start: 0,
            len: 0,
        }
    }

    /// True when the next push overwrites the oldest value.
    pub(crate) fn is_full(&self) -> bool {
        self.len == self.buf.len()
    }

    /// Appends `value`, dropping the oldest one when full.
    pub(crate) fn push_back(&mut self, value: T) {
        let cap = self.buf.len();
        if self.len < cap {
            self.buf[(self.start + self.len) % cap] = value;
            self.len += 1;
        } else {
            self.buf[self.start] = value;
            self.start = (self.start + 1) % cap;
        }
    }

    /// The oldest value.
    pub(crate) fn front(&self) -> Option<T> {
        (self.len > 0).then(|| self.buf[self.start])
    }

    /// Removes and returns the oldest value.
    pub(crate) fn pop_front(&mut self) -> Option<T> {
        let value = self.front()?;
        self.start = (self.start + 1) % self.buf.len();
        self.len -= 1;
        Some(value)
    }

    /// Values from the newest to the oldest.
    pub(crate) fn newest_first(&self) -> impl Iterator<Item = T> + '_ {
        let cap = self.buf.len();
        (0..self.len).map(move |i| self.buf[(self.start + self.len - 1 - i) % cap])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_order_and_overwrites_the_oldest_when_full() {
        let mut r = Ring::new(3, 0);
        assert_eq!(r.pop_front(), None);
        for v in 1..=5 {
            r.push_back(v);
        }
        assert!(r.is_full());
        assert_eq!(r.newest_first().collect::<Vec<_>>(), vec![5, 4, 3]);
        assert_eq!(r.pop_front(), Some(3));
        r.push_back(6);
        assert!(r.is_full());
        assert_eq!(
            (r.pop_front(), r.pop_front(), r.pop_front(), r.pop_front()),
            (Some(4), Some(5), Some(6), None)
        );
    }
}
