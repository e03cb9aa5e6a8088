//! Setpoint generators: the take-off climb and the trajectory generators.

mod climb;
pub mod trajectory;

pub use climb::ClimbProfile;
pub use trajectory::{Trajectory, TrajectorySample, TrajectorySpec};
