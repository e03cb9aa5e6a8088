//! MAVLink: the only module that names the `mavlink` crate (architecture.md §3): the codec
//! (bytes ↔ frames) and the translation between messages and the commander.

pub mod codec;
pub mod duplicates;
pub mod identity;
pub mod ingest;
pub mod link;
pub mod mission_items;
pub mod mission_xfer;
pub mod offboard;
pub mod params;
pub mod services;
pub mod signing;
mod status;
pub mod streams;
pub mod telemetry;
pub mod translate;

pub use mavlink::dialects::common::{
    MavCmd, MavMessage, MavMissionResult, MavMissionType, MavResult, MavSeverity, MavType, COMMAND_LONG_DATA,
    HEARTBEAT_DATA, MESSAGE_INTERVAL_DATA, MISSION_ITEM_INT_DATA, MISSION_ITEM_REACHED_DATA,
};
pub use mavlink::{MAVLinkV2MessageRaw, MavHeader};
