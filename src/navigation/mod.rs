//! Setpoint generators.

mod climb;

pub use climb::ClimbProfile;
