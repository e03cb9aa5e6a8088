//! MAVLink: the only module that names the `mavlink` crate. Pure: no clock, socket, thread or
//! lock; the runtime passes the time in.
//!
//! # Layout
//! - [`link`]: the vehicle's MAVLink endpoint as a state machine (datagrams and the vehicle's
//!   answers in, datagrams and requests out); everything below is what it uses.
//! - [`codec`]: bytes ↔ frames; [`signing`]: MAVLink 2 signatures and their checks.
//! - [`ingest`]: one inbound message → what the link does with it.
//! - [`translate`], [`identity`]: commands → commander requests, ACKs, HEARTBEAT.
//! - [`offboard`]: SET_POSITION_TARGET_* and SET_ATTITUDE_TARGET → setpoints.
//! - [`orbit`]: MAV_CMD_DO_ORBIT and ORBIT_EXECUTION_STATUS; [`reposition`]: MAV_CMD_DO_REPOSITION.
//! - [`failure`]: MAV_CMD_INJECT_FAILURE (motors simulated, other units refused by name).
//! - [`calibration`]: MAV_CMD_PREFLIGHT_CALIBRATION and its `[cal]` STATUSTEXT protocol.
//! - [`logs`]: the flight logs (PX4's names, the store interface) and the log protocol.
//! - [`duplicates`]: retransmitted commands; [`streams`]: per-link telemetry rates.
//! - [`telemetry`] (with `status` and `nav_status`): the streamed messages built from a snapshot;
//!   `nav_status`: GPS_RAW_INT, ESTIMATOR_STATUS, EKF_STATUS_REPORT and the raw sensors from the
//!   navigation.
//! - `ap_messages`: ArduCopter's own streamed messages (RAW_IMU, AHRS2, SIMSTATE, …) for the
//!   ArduPilot personality.
//! - [`motor_outputs`]: the motor outputs as PX4 SITL reports them (PWM, 900 µs stopped).
//! - [`services`]: AUTOPILOT_VERSION, PING, TIMESYNC.
//! - [`ftp`]: MAVLink FTP (payload, in-memory file system, server); [`metadata`]: the component
//!   metadata files it serves (general, parameters) and COMPONENT_METADATA.
//! - [`shell`]: the MAVLink shell (SERIAL_CONTROL) and its commands.
//! - [`events`]: the events protocol of a vehicle that announces by STATUSTEXT.
//! - [`modes`]: PROTOCOL_VERSION and the standard modes protocol (AVAILABLE_MODES, CURRENT_MODE).
//! - [`params`]: PARAM_VALUE / PARAM_SET encoding and PX4's `_HASH_CHECK`; [`crc32`]: its CRC.
//! - [`mission_xfer`], [`mission_items`]: the mission transfer protocol and item validation;
//!   [`plan_items`]: fence and rally items; [`plan_store`]: the stored plans, their ids and
//!   downloads; [`mission_report`]: MISSION_CURRENT (plan ids, PX4's mission mode and state).
//! - [`gcs`]: the ground-station side (its header, COMMAND_LONG, which ACK answers a command)
//!   for the bench client, the tests and the fuzz target.

mod ap_messages;
pub mod calibration;
pub mod codec;
pub mod crc32;
pub mod duplicates;
pub mod events;
pub mod failure;
pub mod ftp;
pub mod gcs;
pub mod identity;
pub mod ingest;
pub mod link;
pub mod logs;
pub mod metadata;
pub mod mission_items;
pub mod mission_report;
pub mod mission_xfer;
pub mod motor_outputs;
mod nav_status;
pub mod offboard;
pub mod orbit;
pub mod param_encoding;
pub mod plan_items;
pub mod plan_store;
pub mod reposition;
pub mod services;
pub mod shell;
pub mod signing;
pub mod standard_modes;
mod status;
pub mod stream_messages;
pub mod streams;
pub mod translate;

/// The raw MAVLink types of the bench client's API ([`crate::runners::bench::client`]): it is a ground
/// station, and the tests send and match arbitrary messages through it. The runtime never names
/// them; it deals in [`link`]'s types.
pub use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavResult};
pub use mavlink::MavHeader;
