//! Setpoint generators: the take-off climb, the trajectory generators and the guidance of the
//! commander's modes.

mod climb;
pub mod geo;
mod guidance;
pub mod mission;
pub mod trajectory;

pub use climb::ClimbProfile;
pub use geo::Home;
pub use guidance::{Guidance, SpeedLimits};
pub use mission::{Mission, MissionItem};
pub use trajectory::{Trajectory, TrajectorySample, TrajectorySpec};
