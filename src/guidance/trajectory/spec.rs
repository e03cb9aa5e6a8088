//! The `[trajectory]` table of a scenario file: a hand-written description, `kind` first, built
//! into a [`Trajectory`] with every number checked. Positions are world NED `[x, y, z]` [m]
//! (x north, y east, z down: 2 m up is z = −2), headings in degrees (0 = north, 90 = east),
//! times in seconds. Unknown keys are refused.
//!
//! ```toml
//! [trajectory]
//! kind = "circle"
//! centre = [0, 0, -2]
//! radius = 1.5
//! period = 10
//! ```

use serde::Deserialize;

use super::error::{heading, point, positive, TrajectoryError};
use super::{Circle, CircleParams, CircleYaw, Hover, LegTiming, Quintic, Trajectory};
use super::{Waypoint, Waypoints};

/// Leg durations of a waypoint trajectory: one number for every leg, or a list with one per leg.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum SegmentTime {
    /// The same duration for every leg [s].
    Each(f64),
    /// One duration per leg [s].
    PerLeg(Vec<f64>),
}

/// Heading along a circle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum YawMode {
    /// Constant heading, `yaw` [deg] (default 0).
    #[default]
    Fixed,
    /// Nose along the direction of travel.
    Tangent,
}

/// Turning direction of a circle, seen from above.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// North → east → south (heading increases).
    #[default]
    Clockwise,
    /// North → west → south (heading decreases).
    Counterclockwise,
}

/// A `[trajectory]` table, tagged by `kind`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TrajectorySpec {
    /// `kind = "hover"`: hold a point.
    Hover {
        /// Point held, `[x, y, z]` NED [m].
        position: [f64; 3],
        /// Heading [deg], default 0.
        #[serde(default)]
        yaw: f64,
    },
    /// `kind = "quintic"`: rest-to-rest minimum-jerk move.
    Quintic {
        /// Start point, `[x, y, z]` NED [m].
        start: [f64; 3],
        /// Goal point, `[x, y, z]` NED [m].
        goal: [f64; 3],
        /// Duration of the move [s].
        duration: f64,
        /// Heading at the start [deg], default 0.
        #[serde(default)]
        yaw: f64,
        /// Heading at the goal [deg], default `yaw`; turns the shorter way.
        goal_yaw: Option<f64>,
    },
    /// `kind = "waypoints"`: rest-to-rest legs; the first waypoint is the start.
    Waypoints {
        /// `[[x, y, z], [x, y, z, yaw], ...]` [m, m, m, deg]; a waypoint without a heading keeps
        /// the previous one (0 for the first).
        waypoints: Vec<Vec<f64>>,
        /// Leg duration [s]: one number, or one per leg. Give this or `speed`.
        segment_time: Option<SegmentTime>,
        /// Peak speed of each leg [m/s] (a leg of length L takes 1.875·L/speed). Give this or
        /// `segment_time`.
        speed: Option<f64>,
        /// With `speed`: peak heading rate [deg/s], if limited.
        yaw_rate: Option<f64>,
        /// With `speed`: shortest leg [s], default 1.
        min_segment_time: Option<f64>,
        /// Pause at each intermediate waypoint [s], default 0.
        #[serde(default)]
        hold: f64,
    },
    /// `kind = "circle"`: horizontal circle starting at `centre + [radius, 0, 0]` (due north).
    Circle {
        /// Centre `[x, y, z]` NED [m]; z is the altitude flown. `center` is accepted too.
        #[serde(alias = "center")]
        centre: [f64; 3],
        /// Radius [m].
        radius: f64,
        /// Time per lap at full speed [s].
        period: f64,
        /// Spin-up (and spin-down) time from rest [s], default `period`.
        ramp: Option<f64>,
        /// Laps from start to stop, ramps included (may be fractional); default: forever.
        laps: Option<f64>,
        /// `"clockwise"` (default) or `"counterclockwise"`, seen from above.
        #[serde(default)]
        direction: Direction,
        /// `"fixed"` (default) or `"tangent"`.
        #[serde(default)]
        yaw_mode: YawMode,
        /// With `yaw_mode = "fixed"`: heading [deg], default 0.
        yaw: Option<f64>,
    },
}

fn only_with_speed(field: &str, v: Option<f64>) -> Result<(), TrajectoryError> {
    match v {
        Some(_) => Err(TrajectoryError::new(field, "only with `speed`".into())),
        None => Ok(()),
    }
}

impl TrajectorySpec {
    /// Checks every field and builds the trajectory.
    pub fn build(&self) -> Result<Trajectory, TrajectoryError> {
        match self {
            Self::Hover { position, yaw } => Ok(Trajectory::Hover(Hover {
                pos_w: point("position", *position)?,
                yaw_rad: heading("yaw", *yaw)?,
            })),
            Self::Quintic {
                start,
                goal,
                duration,
                yaw,
                goal_yaw,
            } => Ok(Trajectory::Quintic(Quintic {
                start_w: point("start", *start)?,
                goal_w: point("goal", *goal)?,
                duration_s: positive("duration", *duration)?,
                start_yaw_rad: heading("yaw", *yaw)?,
                goal_yaw_rad: heading("goal_yaw", goal_yaw.unwrap_or(*yaw))?,
            })),
            Self::Waypoints {
                waypoints,
                segment_time,
                speed,
                yaw_rate,
                min_segment_time,
                hold,
            } => {
                let mut points = Vec::with_capacity(waypoints.len());
                let mut yaw_rad = 0.0;
                for (i, w) in waypoints.iter().enumerate() {
                    let field = format!("waypoints[{i}]");
                    let (xyz, yaw) = match w.as_slice() {
                        [x, y, z] => ([*x, *y, *z], None),
                        [x, y, z, yaw] => ([*x, *y, *z], Some(*yaw)),
                        _ => {
                            let reason = format!("needs [x, y, z] or [x, y, z, yaw], got {w:?}");
                            return Err(TrajectoryError::new(&field, reason));
                        }
                    };
                    if let Some(deg) = yaw {
                        yaw_rad = heading(&field, deg)?;
                    }
                    points.push(Waypoint {
                        pos_w: point(&field, xyz)?,
                        yaw_rad,
                    });
                }
                let timing = match (segment_time, speed) {
                    (Some(_), Some(_)) => {
                        let reason = "give `segment_time` or `speed`, not both".into();
                        return Err(TrajectoryError::new("segment_time", reason));
                    }
                    (None, None) => {
                        let reason = "missing: give `segment_time` [s] or `speed` [m/s]".into();
                        return Err(TrajectoryError::new("segment_time", reason));
                    }
                    (Some(st), None) => {
                        only_with_speed("yaw_rate", *yaw_rate)?;
                        only_with_speed("min_segment_time", *min_segment_time)?;
                        match st {
                            SegmentTime::Each(t) => LegTiming::Each(*t),
                            SegmentTime::PerLeg(ts) => LegTiming::PerLeg(ts.clone()),
                        }
                    }
                    (None, Some(v)) => LegTiming::Speed {
                        speed_m_s: *v,
                        yaw_rate_rad_s: yaw_rate.map(f64::to_radians),
                        min_s: min_segment_time.unwrap_or(1.0),
                    },
                };
                Ok(Trajectory::Waypoints(Waypoints::new(&points, &timing, *hold)?))
            }
            Self::Circle {
                centre,
                radius,
                period,
                ramp,
                laps,
                direction,
                yaw_mode,
                yaw,
            } => {
                let yaw = match (yaw_mode, yaw) {
                    (YawMode::Fixed, y) => CircleYaw::Fixed(heading("yaw", y.unwrap_or(0.0))?),
                    (YawMode::Tangent, None) => CircleYaw::Tangent,
                    (YawMode::Tangent, Some(_)) => {
                        let reason = "only with yaw_mode = \"fixed\"".into();
                        return Err(TrajectoryError::new("yaw", reason));
                    }
                };
                Ok(Trajectory::Circle(Circle::new(CircleParams {
                    centre_w: point("centre", *centre)?,
                    radius_m: *radius,
                    period_s: *period,
                    ramp_s: ramp.unwrap_or(*period),
                    laps: *laps,
                    clockwise: *direction == Direction::Clockwise,
                    yaw,
                })?))
            }
        }
    }
}

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;
