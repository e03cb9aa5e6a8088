//! Setpoint generators: the take-off climb, the trajectory generators, the guidance of the
//! commander's modes, the motion limits they keep and the limiter offboard setpoints go through;
//! the uploaded geofence and rally points the commander checks and returns to.

mod climb;
mod descent;
pub mod geo;
pub mod geofence;
mod guidance;
mod limits;
pub mod mission;
pub mod rally;
mod setpoint_limiter;
pub mod trajectory;

pub use climb::ClimbProfile;
pub use descent::DescentProfile;
pub use geo::Home;
pub use geofence::Geofence;
pub use guidance::Guidance;
pub use limits::MotionLimits;
pub use mission::{Mission, MissionItem};
pub use rally::RallyPoints;
pub use setpoint_limiter::SetpointLimiter;
pub use trajectory::{Trajectory, TrajectorySample, TrajectorySpec};
