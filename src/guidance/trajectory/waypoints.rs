//! A chain of rest-to-rest quintic legs through waypoints, with an optional hold at each
//! intermediate waypoint. Every leg starts and ends at rest, so position, velocity and
//! acceleration are continuous at the joins and each leg ends exactly on its waypoint.

use super::error::positive;
use super::quintic::Quintic;
use super::{TrajectoryError, TrajectorySample};
use crate::math::{wrap_pi, Vec3};

/// Ratio of a quintic move's peak speed to its mean speed, `s′(½) = 15/8`.
pub const QUINTIC_PEAK_OVER_MEAN: f64 = 1.875;

/// One waypoint: a position and the heading to have on arrival.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    /// Position, world NED [m].
    pub pos_w: Vec3,
    /// Heading on arrival [rad].
    pub yaw_rad: f64,
}

/// How long each leg takes.
#[derive(Debug, Clone, PartialEq)]
pub enum LegTiming {
    /// The same duration for every leg [s].
    Each(f64),
    /// One duration per leg, in order [s].
    PerLeg(Vec<f64>),
    /// Durations from peak speeds: `T = max(1.875·L/speed, 1.875·|Δψ|/yaw_rate, min)`.
    Speed {
        /// Peak speed along a leg [m/s].
        speed_m_s: f64,
        /// Peak heading rate, if limited [rad/s].
        yaw_rate_rad_s: Option<f64>,
        /// Shortest leg [s].
        min_s: f64,
    },
}

/// One leg of a [`Waypoints`] trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedLeg {
    /// Time the leg starts, from the start of the trajectory [s].
    pub start_s: f64,
    /// The move itself (its time runs from `start_s`).
    pub path: Quintic,
}

/// Rest-to-rest legs through waypoints; the first waypoint is the start. Before t = 0 it holds
/// the first waypoint, after the last leg the last one.
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoints {
    first: Waypoint,
    legs: Vec<TimedLeg>,
}

fn err(field: &str, reason: String) -> TrajectoryError {
    TrajectoryError::new(field, reason)
}

impl Waypoints {
    /// Legs through `points` (at least one), timed by `timing`, pausing `hold_s` [s] at each
    /// intermediate waypoint. Errors name the scenario field: `waypoints`, `segment_time`,
    /// `speed`, `yaw_rate`, `min_segment_time`, `hold`.
    pub fn new(points: &[Waypoint], timing: &LegTiming, hold_s: f64) -> Result<Self, TrajectoryError> {
        let Some(&first) = points.first() else {
            return Err(err("waypoints", "needs at least 1 waypoint, got none".into()));
        };
        for (i, p) in points.iter().enumerate() {
            if !(p.pos_w.iter().all(|c| c.is_finite()) && p.yaw_rad.is_finite()) {
                return Err(err(&format!("waypoints[{i}]"), "must be finite numbers".into()));
            }
        }
        if !(hold_s.is_finite() && hold_s >= 0.0) {
            return Err(err("hold", format!("must be zero or positive, got {hold_s}")));
        }
        let n_legs = points.len() - 1;
        let durations = match timing {
            LegTiming::Each(t) => vec![positive("segment_time", *t)?; n_legs],
            LegTiming::PerLeg(ts) if ts.len() != n_legs => {
                let reason = format!("needs one duration per leg ({n_legs}), got {}", ts.len());
                return Err(err("segment_time", reason));
            }
            LegTiming::PerLeg(ts) => (ts.iter().enumerate())
                .map(|(i, t)| positive(&format!("segment_time[{i}]"), *t))
                .collect::<Result<_, _>>()?,
            LegTiming::Speed {
                speed_m_s,
                yaw_rate_rad_s,
                min_s,
            } => {
                let v = positive("speed", *speed_m_s)?;
                let w = yaw_rate_rad_s.map(|w| positive("yaw_rate", w)).transpose()?;
                let min = positive("min_segment_time", *min_s)?;
                (points.windows(2))
                    .map(|p| {
                        let l = (p[1].pos_w - p[0].pos_w).norm();
                        let turn = wrap_pi(p[1].yaw_rad - p[0].yaw_rad).abs();
                        let t_turn = w.map_or(0.0, |w| QUINTIC_PEAK_OVER_MEAN * turn / w);
                        (QUINTIC_PEAK_OVER_MEAN * l / v).max(t_turn).max(min)
                    })
                    .collect()
            }
        };
        let mut start_s = 0.0;
        let mut legs = Vec::with_capacity(n_legs);
        for (p, duration_s) in points.windows(2).zip(durations) {
            let path = Quintic {
                start_w: p[0].pos_w,
                goal_w: p[1].pos_w,
                duration_s,
                start_yaw_rad: p[0].yaw_rad,
                goal_yaw_rad: p[1].yaw_rad,
            };
            legs.push(TimedLeg { start_s, path });
            start_s += duration_s + hold_s;
        }
        Ok(Self { first, legs })
    }

    /// The legs in order.
    pub fn legs(&self) -> &[TimedLeg] {
        &self.legs
    }

    /// The first waypoint (the start).
    pub fn first(&self) -> Waypoint {
        self.first
    }

    /// Time of arrival at the last waypoint [s]; 0 with a single waypoint.
    pub fn duration_s(&self) -> f64 {
        self.legs.last().map_or(0.0, |l| l.start_s + l.path.duration_s)
    }

    /// Sample at time `t_s` [s] from the start.
    pub fn sample(&self, t_s: f64) -> TrajectorySample {
        // The last leg that has started; a leg holds its goal once done, covering the pauses.
        let i = self.legs.partition_point(|l| l.start_s <= t_s).saturating_sub(1);
        match self.legs.get(i) {
            Some(leg) => leg.path.sample(t_s - leg.start_s),
            None => TrajectorySample::at_rest(self.first.pos_w, self.first.yaw_rad),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{assert_continuous, assert_derivatives, random_times};
    use super::*;

    fn wp(x: f64, y: f64, z: f64, yaw: f64) -> Waypoint {
        Waypoint {
            pos_w: Vec3::new(x, y, z),
            yaw_rad: yaw,
        }
    }

    fn square() -> Vec<Waypoint> {
        vec![
            wp(0.0, 0.0, -2.0, 0.0),
            wp(4.0, 0.0, -2.0, 1.5),
            wp(4.0, 3.0, -3.0, 3.0),
            wp(4.0, 3.0, -3.0, -2.0),
            wp(0.0, 0.0, -2.0, 0.0),
        ]
    }

    #[test]
    fn passes_exactly_through_each_waypoint_and_is_smooth() {
        let pts = square();
        let w = Waypoints::new(&pts, &LegTiming::PerLeg(vec![2.0, 3.0, 1.5, 4.0]), 0.5).unwrap();
        assert_eq!(w.duration_s(), 2.0 + 3.0 + 1.5 + 4.0 + 3.0 * 0.5);
        for (leg, goal) in w.legs().iter().zip(&pts[1..]) {
            for t in [
                leg.start_s + leg.path.duration_s,
                leg.start_s + leg.path.duration_s + 0.5,
            ] {
                assert_eq!(w.sample(t), TrajectorySample::at_rest(goal.pos_w, goal.yaw_rad));
            }
            assert_continuous(|t| w.sample(t), leg.start_s);
            assert_continuous(|t| w.sample(t), leg.start_s + leg.path.duration_s);
        }
        let mut times = random_times(2, -1.0, w.duration_s() + 1.0, 300);
        for leg in w.legs() {
            for dt in [1e-5, 1e-3] {
                let end = leg.start_s + leg.path.duration_s;
                times.extend([leg.start_s + dt, end - dt, end + dt]);
            }
        }
        assert_derivatives(|t| w.sample(t), &times);
        assert_eq!(w.sample(-1.0).pos_w, pts[0].pos_w);
    }

    #[test]
    fn speed_timing_meets_peak_speed_and_minimum() {
        let pts = square();
        let timing = LegTiming::Speed {
            speed_m_s: 2.0,
            yaw_rate_rad_s: Some(1.0),
            min_s: 1.0,
        };
        let w = Waypoints::new(&pts, &timing, 0.0).unwrap();
        let t: Vec<f64> = w.legs().iter().map(|l| l.path.duration_s).collect();
        assert!((t[0] - 1.875 * 4.0 / 2.0).abs() < 1e-12);
        assert!((w.legs()[0].path.peak_speed_m_s() - 2.0).abs() < 1e-12);
        // Leg 3 only turns, 3 → −2 rad the short way (2π − 5 rad) at 1 rad/s peak.
        assert!((t[2] - 1.875 * (std::f64::consts::TAU - 5.0)).abs() < 1e-12);
        let still = [wp(1.0, 1.0, -1.0, 0.0), wp(1.0, 1.0, -1.0, 0.0)];
        let timing = LegTiming::Speed {
            speed_m_s: 2.0,
            yaw_rate_rad_s: None,
            min_s: 0.7,
        };
        assert_eq!(Waypoints::new(&still, &timing, 0.0).unwrap().duration_s(), 0.7);
    }

    #[test]
    fn single_waypoint_holds_and_errors_name_fields() {
        let w = Waypoints::new(&[wp(1.0, 2.0, -3.0, 0.5)], &LegTiming::Each(2.0), 0.0).unwrap();
        assert_eq!((w.duration_s(), w.sample(5.0).pos_w), (0.0, Vec3::new(1.0, 2.0, -3.0)));
        let e = |pts: &[Waypoint], t: LegTiming, h: f64| Waypoints::new(pts, &t, h).unwrap_err();
        assert_eq!(e(&[], LegTiming::Each(1.0), 0.0).field, "waypoints");
        assert_eq!(e(&square(), LegTiming::Each(0.0), 0.0).field, "segment_time");
        assert_eq!(e(&square(), LegTiming::PerLeg(vec![1.0]), 0.0).field, "segment_time");
        assert_eq!(e(&square(), LegTiming::Each(1.0), -1.0).field, "hold");
        let bad = LegTiming::PerLeg(vec![1.0, 1.0, f64::NAN, 1.0]);
        assert_eq!(e(&square(), bad, 0.0).field, "segment_time[2]");
        let nan = [wp(0.0, 0.0, 0.0, 0.0), wp(f64::INFINITY, 0.0, 0.0, 0.0)];
        assert_eq!(e(&nan, LegTiming::Each(1.0), 0.0).field, "waypoints[1]");
    }
}
