//! Fixed-size history of the nominal state at every IMU sample, so that a delayed measurement can
//! be compared with the state at its time of validity
//! (docs/navigation_filter.md §7, eqs. (7.1)–(7.3)).

use crate::math::{UnitQuat, Vec3};

use super::state::turn_world;

/// Entries kept: 256 IMU samples, 255 ms at 1 kHz, more than `MAX_DELAY_S`
/// (docs/navigation_filter.md §7).
pub(super) const DELAY_BUFFER_LEN: usize = 256;

/// The kinematic part of the nominal state at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PastState {
    /// Time [s].
    pub t_s: f64,
    /// Position, local NED [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Attitude, body FRD → world NED.
    pub q_wb: UnitQuat,
}

impl Default for PastState {
    fn default() -> Self {
        Self {
            t_s: 0.0,
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            q_wb: UnitQuat::identity(),
        }
    }
}

/// Ring buffer of [`PastState`]s, allocated once.
#[derive(Debug, Clone)]
pub(super) struct DelayBuffer {
    items: Box<[PastState; DELAY_BUFFER_LEN]>,
    /// Index of the oldest entry.
    start: usize,
    len: usize,
}

impl DelayBuffer {
    /// An empty buffer.
    pub fn new() -> Self {
        Self {
            items: Box::new([PastState::default(); DELAY_BUFFER_LEN]),
            start: 0,
            len: 0,
        }
    }

    /// Forgets every entry.
    pub fn clear(&mut self) {
        self.start = 0;
        self.len = 0;
    }

    fn get(&self, i: usize) -> &PastState {
        &self.items[(self.start + i) % DELAY_BUFFER_LEN]
    }

    /// Appends the newest snapshot, dropping the oldest when full.
    pub fn push(&mut self, s: PastState) {
        if self.len < DELAY_BUFFER_LEN {
            self.items[(self.start + self.len) % DELAY_BUFFER_LEN] = s;
            self.len += 1;
        } else {
            self.items[self.start] = s;
            self.start = (self.start + 1) % DELAY_BUFFER_LEN;
        }
    }

    /// The state at time `t_s` [s], linearly interpolated between the two entries around it
    /// (docs/navigation_filter.md §7, eq. (7.2)); the newest entry for a later time; `None` when
    /// empty or when `t_s` is older than the oldest entry.
    pub fn at(&self, t_s: f64) -> Option<PastState> {
        if self.len == 0 {
            return None;
        }
        let newest = *self.get(self.len - 1);
        if t_s >= newest.t_s {
            return Some(newest);
        }
        if t_s < self.get(0).t_s {
            return None;
        }
        // Last entry with time ≤ t_s: entries [0, lo] are ≤ t_s, entries from hi on are later.
        let (mut lo, mut hi) = (0, self.len - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.get(mid).t_s <= t_s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (a, b) = (self.get(lo), self.get(hi));
        let span = b.t_s - a.t_s;
        let u = if span > 0.0 {
            ((t_s - a.t_s) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        Some(PastState {
            t_s,
            pos_w: a.pos_w.lerp(&b.pos_w, u),
            vel_w: a.vel_w.lerp(&b.vel_w, u),
            q_wb: a.q_wb.nlerp(&b.q_wb, u),
        })
    }

    /// Applies a correction, as it was applied to the current state, to every stored entry from
    /// time `from_s` [s] on (older ones are never looked up again)
    /// (docs/navigation_filter.md §7, eq. (7.3)).
    pub fn correct(&mut self, from_s: f64, dpos_w: &Vec3, dvel_w: &Vec3, dtheta_w: &Vec3) {
        // Exp(δθ) once for every entry (the same rotation as `rotate_world`'s).
        let turn = (dtheta_w.norm_squared() > 0.0).then(|| UnitQuat::from_scaled_axis(*dtheta_w));
        let first = self.first_at_or_after(from_s);
        for i in first..self.len {
            let s = &mut self.items[(self.start + i) % DELAY_BUFFER_LEN];
            s.pos_w += dpos_w;
            s.vel_w += dvel_w;
            if let Some(turn) = &turn {
                s.q_wb = turn_world(&s.q_wb, turn);
            }
        }
    }

    /// Index of the last entry older than `t_s`, so that interpolation at `t_s` still finds
    /// both neighbours (0 when none is older).
    fn first_at_or_after(&self, t_s: f64) -> usize {
        let (mut lo, mut hi) = (0, self.len);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.get(mid).t_s < t_s {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo.saturating_sub(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snap(t: f64) -> PastState {
        PastState {
            t_s: t,
            pos_w: Vec3::new(t, 2.0 * t, 0.0),
            vel_w: Vec3::new(1.0, 2.0, 0.0),
            ..PastState::default()
        }
    }

    #[test]
    fn interpolates_wraps_and_refuses_too_old() {
        let mut b = DelayBuffer::new();
        assert!(b.at(0.0).is_none());
        for k in 0..1000 {
            b.push(snap(k as f64 * 1e-3));
        }
        // Only the last 256 remain: 0.744 s … 0.999 s.
        assert!(b.at(0.7).is_none());
        let s = b.at(0.9005).unwrap();
        assert!((s.pos_w.x - 0.9005).abs() < 1e-12 && (s.pos_w.y - 1.801).abs() < 1e-12);
        assert_eq!(b.at(5.0).unwrap().t_s, 0.999);
        assert!((b.at(0.744).unwrap().pos_w.x - 0.744).abs() < 1e-12);
    }

    #[test]
    fn correction_reaches_every_entry() {
        let mut b = DelayBuffer::new();
        for k in 0..10 {
            b.push(snap(k as f64 * 1e-3));
        }
        b.correct(
            0.0,
            &Vec3::new(0.5, 0.0, 0.0),
            &Vec3::new(0.0, 0.0, 1.0),
            &Vec3::new(0.0, 0.0, 0.1),
        );
        let s = b.at(0.0).unwrap();
        assert_eq!(s.pos_w.x, 0.5);
        assert_eq!(s.vel_w.z, 1.0);
        assert!((s.q_wb.angle() - 0.1).abs() < 1e-12);
        // From 5.5 ms on: the entries at 5 ms and later move, older ones stay.
        b.correct(0.0055, &Vec3::new(1.0, 0.0, 0.0), &Vec3::zeros(), &Vec3::zeros());
        assert!((b.at(0.004).unwrap().pos_w.x - 0.504).abs() < 1e-12);
        assert!((b.at(0.005).unwrap().pos_w.x - 1.505).abs() < 1e-12);
        assert!((b.at(0.009).unwrap().pos_w.x - 1.509).abs() < 1e-12);
        b.clear();
        assert!(b.at(0.0).is_none());
    }
}
