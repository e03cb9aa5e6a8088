//! Setpoint generators: the take-off climb, the trajectory generators, the guidance of the
//! commander's modes, the motion limits they keep, the limiter offboard setpoints go through,
//! the sticks with the reference the stick modes fly, the orbit and the follow-me point; the
//! uploaded geofence and rally points the commander checks and returns to.

mod climb;
mod descent;
pub mod fence_path;
mod follow;
pub mod geo;
pub mod geofence;
mod heading;
mod limits;
pub mod mission;
mod mode_reference;
mod orbit;
pub mod rally;
mod setpoint_limiter;
mod stick_reference;
mod sticks;
mod track;
pub mod trajectory;

pub use climb::ClimbProfile;
pub use descent::DescentProfile;
pub use follow::{FollowAltitude, FollowParams, FollowTarget};
pub use geo::Home;
pub use geofence::Geofence;
pub use heading::{HeadingSlew, HeadingStep};
pub use limits::MotionLimits;
pub use mission::{HereParts, Mission, MissionItem};
pub use mode_reference::Guidance;
pub use orbit::{Orbit, OrbitYaw, ORBIT_RADIUS_M};
pub use rally::{RallyPoints, RallyRule};
pub use setpoint_limiter::SetpointLimiter;
pub use stick_reference::StickReference;
pub use sticks::{StickError, StickMotion, StickShaping, Sticks};
pub use track::{Track, TrackLeg};
pub use trajectory::{Trajectory, TrajectorySample, TrajectorySpec};
