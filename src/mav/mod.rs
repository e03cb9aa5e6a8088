//! MAVLink: the only module that names the `mavlink` crate (architecture.md §3): the codec
//! (bytes ↔ frames) and the translation between messages and the commander.

pub mod codec;
pub mod duplicates;
pub mod offboard;
pub mod params;
pub mod services;
pub mod telemetry;
pub mod translate;

pub use mavlink::dialects::common::{MavCmd, MavMessage, MavResult, MavSeverity, COMMAND_LONG_DATA};
pub use mavlink::MavHeader;
