//! Setpoint generators: the take-off climb, the trajectory generators, the guidance of the
//! commander's modes, the motion limits they keep and the limiter offboard setpoints go through.

mod climb;
mod descent;
pub mod geo;
mod guidance;
mod limits;
pub mod mission;
mod setpoint_limiter;
pub mod trajectory;

pub use climb::ClimbProfile;
pub use descent::DescentProfile;
pub use geo::Home;
pub use guidance::Guidance;
pub use limits::MotionLimits;
pub use mission::{Mission, MissionItem};
pub use setpoint_limiter::SetpointLimiter;
pub use trajectory::{Trajectory, TrajectorySample, TrajectorySpec};
