//! The ArduCopter personality (docs/ardupilot.md): what a vehicle presented as ArduCopter
//! (`--autopilot ardupilot`) says and understands where ArduCopter differs from PX4. The same
//! commander, navigation and control fly it; only the face differs. Pure.
//!
//! # Layout
//! - [`copter_modes`]: Copter's mode numbers and names, the commander mode flying each, the
//!   number a HEARTBEAT shows ([`copter_modes::ModeShown`]) and Copter's HEARTBEAT.
//! - [`copter_messages`]: Copter's own streamed messages (RAW_IMU, AHRS, AHRS2, SIMSTATE,
//!   VIBRATION, …), built from the snapshot.
//! - [`copter_params`]: Copter's parameter names for the settings the vehicle has, their units
//!   and storage types, and Copter's defaults.
//! - [`copter_link_params`]: what the link holds that Copter shows as parameters
//!   (`SYSID_THISMAV`, the `SRn_*` stream rates).
//! - [`copter_param_face`]: [`copter_param_face::CopterParamView`], the one parameter table
//!   under those names (PARAM_VALUE, PARAM_SET, `@PARAM/param.pck`), and the banner said before
//!   a parameter list.
//! - [`copter_rc`]: SITL's RC receiver ([`copter_rc::CopterReceiver`]): its channels, their
//!   overrides (RC_CHANNELS_OVERRIDE), RC_CHANNELS and the sticks they give the commander.
//! - [`copter_streams`]: Copter's stream groups ([`copter_streams::CopterGroup`]): the `SRn_*`
//!   suffix, MAV_DATA_STREAM id and messages of each.
//! - [`copter_targets`]: GUIDED's position targets as Copter reads them (offset and body frames,
//!   the force bit, a stop for what it cannot fly).
//! - [`copter_failsafes`]: Copter's failsafe texts ("GCS Failsafe", "Battery Failsafe", "EKF
//!   variance", "Circle fence breached" …) and whether one is active (HEARTBEAT CRITICAL).
//! - [`copter_texts`]: what Copter says where PX4 says it otherwise ("PreArm: …", "Mode change
//!   to … failed", "Arming motors").
//! - [`copter_ingest`]: the inbound messages Copter treats differently (mode changes by Copter
//!   number, NAV_TAKEOFF in GUIDED, guided targets only in GUIDED), decided before the shared
//!   [`ingest`](super::ingest::ingest).
//! - [`copter_mission`]: the mission plan as Copter numbers it (item 0 is home, flown items
//!   from 1), MISSION_ITEM ↔ MISSION_ITEM_INT, AUTO's take-off rule, downloads' `current` flag.
//! - [`copter_plans`]: fence and rally plans as Copter checks and stores them.

pub mod copter_failsafes;
pub mod copter_ingest;
pub mod copter_link_params;
pub mod copter_messages;
pub mod copter_mission;
pub mod copter_modes;
pub mod copter_param_face;
pub mod copter_params;
pub mod copter_plans;
pub mod copter_rc;
pub mod copter_streams;
pub mod copter_targets;
pub mod copter_texts;
