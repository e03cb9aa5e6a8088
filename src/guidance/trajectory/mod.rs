//! Pure trajectory generators: functions of time `t` [s] that give position, velocity,
//! acceleration and jerk (world NED) and heading, heading rate and heading acceleration, all
//! mutually consistent, for the position and heading loops' feed-forward.
//!
//! - [`Hover`]: hold a point at a heading.
//! - [`Quintic`]: rest-to-rest minimum-jerk move between two points (and two headings).
//! - [`Waypoints`]: rest-to-rest quintic legs through waypoints, with holds.
//! - [`Circle`]: horizontal circle with smooth start and, with laps, smooth stop.
//! - [`TrajectorySpec`]: the `[trajectory]` table of a scenario file, built into a [`Trajectory`].
//!
//! Times are relative to the trajectory's own start: before t = 0 every generator holds its start
//! at rest, after its end (if it has one) its end point at rest. Headings are wrapped into
//! (−π, π].

mod circle;
mod error;
mod hover;
mod quintic;
mod spec;
#[cfg(test)]
mod testutil;
mod waypoints;

pub use circle::{Circle, CircleParams, CircleYaw};
pub use error::TrajectoryError;
pub use hover::Hover;
pub use quintic::Quintic;
pub use spec::{Direction, SegmentTime, TrajectorySpec, YawMode};
pub use waypoints::{LegTiming, TimedLeg, Waypoint, Waypoints, QUINTIC_PEAK_OVER_MEAN};

use crate::control::FlatSetpoint;
use crate::math::{wrap_pi, Vec3};

/// A trajectory evaluated at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajectorySample {
    /// Position, world NED [m].
    pub pos_w: Vec3,
    /// Velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Acceleration, world NED [m/s²].
    pub acc_w: Vec3,
    /// Jerk, world NED [m/s³].
    pub jerk_w: Vec3,
    /// Heading ψ, wrapped into (−π, π] [rad].
    pub yaw_rad: f64,
    /// Heading rate ψ̇ [rad/s].
    pub yaw_rate_rad_s: f64,
    /// Heading acceleration ψ̈ [rad/s²].
    pub yaw_acc_rad_s2: f64,
}

impl TrajectorySample {
    /// At rest at `pos_w` [m] with heading `yaw_rad` [rad] (wrapped).
    pub fn at_rest(pos_w: Vec3, yaw_rad: f64) -> Self {
        Self {
            pos_w,
            vel_w: Vec3::zeros(),
            acc_w: Vec3::zeros(),
            jerk_w: Vec3::zeros(),
            yaw_rad: wrap_pi(yaw_rad),
            yaw_rate_rad_s: 0.0,
            yaw_acc_rad_s2: 0.0,
        }
    }

    /// The flat-output setpoint with every field set (jerk is not part of it).
    pub fn setpoint(&self) -> FlatSetpoint {
        FlatSetpoint {
            pos_w: Some(self.pos_w),
            vel_w: Some(self.vel_w),
            acc_w: Some(self.acc_w),
            yaw_rad: Some(self.yaw_rad),
            yaw_rate_rad_s: Some(self.yaw_rate_rad_s),
            yaw_acc_rad_s2: Some(self.yaw_acc_rad_s2),
        }
    }
}

/// Any trajectory generator.
#[derive(Debug, Clone, PartialEq)]
pub enum Trajectory {
    /// Hold a point.
    Hover(Hover),
    /// Rest-to-rest move between two points.
    Quintic(Quintic),
    /// Rest-to-rest legs through waypoints.
    Waypoints(Waypoints),
    /// Horizontal circle.
    Circle(Circle),
}

impl Trajectory {
    /// Sample at time `t_s` [s] from the start of the trajectory.
    pub fn sample(&self, t_s: f64) -> TrajectorySample {
        match self {
            Self::Hover(h) => h.sample(t_s),
            Self::Quintic(q) => q.sample(t_s),
            Self::Waypoints(w) => w.sample(t_s),
            Self::Circle(c) => c.sample(t_s),
        }
    }

    /// Time after which the trajectory is at rest for good [s]; `None` if it never ends (hover,
    /// circle without laps).
    pub fn duration_s(&self) -> Option<f64> {
        match self {
            Self::Hover(_) => None,
            Self::Quintic(q) => Some(q.duration_s.max(0.0)),
            Self::Waypoints(w) => Some(w.duration_s()),
            Self::Circle(c) => c.duration_s(),
        }
    }

    /// Position at t = 0, world NED [m]: where the vehicle should be when it starts.
    pub fn start_w(&self) -> Vec3 {
        match self {
            Self::Hover(h) => h.pos_w,
            Self::Quintic(q) => q.start_w,
            Self::Waypoints(w) => w.first().pos_w,
            Self::Circle(c) => c.start_w(),
        }
    }

    /// Heading at t = 0, wrapped [rad].
    pub fn start_yaw_rad(&self) -> f64 {
        self.sample(0.0).yaw_rad
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setpoint_sets_every_field_and_enum_dispatches() {
        let q = Quintic {
            start_w: Vec3::zeros(),
            goal_w: Vec3::new(0.0, 0.0, -2.0),
            duration_s: 4.0,
            start_yaw_rad: 0.0,
            goal_yaw_rad: 1.0,
        };
        let tr = Trajectory::Quintic(q);
        let sp = tr.sample(1.0).setpoint();
        assert_eq!(sp.pos_w, Some(q.sample(1.0).pos_w));
        assert_eq!(sp.yaw_acc_rad_s2, Some(q.sample(1.0).yaw_acc_rad_s2));
        assert!(sp.is_finite() && sp.vel_w.is_some() && sp.yaw_rate_rad_s.is_some());
        assert_eq!(
            (tr.duration_s(), tr.start_w(), tr.start_yaw_rad()),
            (Some(4.0), q.start_w, 0.0)
        );
        let h = Trajectory::Hover(Hover {
            pos_w: Vec3::new(1.0, 1.0, -1.0),
            yaw_rad: 0.5,
        });
        assert_eq!((h.duration_s(), h.start_w()), (None, Vec3::new(1.0, 1.0, -1.0)));
        assert_eq!(h.sample(3.0).setpoint(), FlatSetpoint::hold(h.start_w(), 0.5));
    }
}
