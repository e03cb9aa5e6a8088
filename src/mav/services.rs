//! Small request/reply services (docs/mavlink.md §4, §9): the messages REQUEST_MESSAGE can ask for,
//! AUTOPILOT_VERSION, PING and TIMESYNC (MAVLink FTP is [`super::ftp`]). Pure.
//!
//! PING is deprecated in the spec, but MAVSDK sends one every 5 s to PX4 and expects the reply.
#![allow(deprecated)]

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavProtocolCapability, AUTOPILOT_VERSION_DATA, PING_DATA, TIMESYNC_DATA,
};
use mavlink::MavHeader;

use super::ardupilot::copter_param_face::COPTER_RELEASE;
use super::identity::Personality;
use super::stream_messages::TelemetryStream;
use super::translate::Identity;

/// A message sent on request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OneShot {
    /// AUTOPILOT_VERSION (148).
    AutopilotVersion,
    /// PROTOCOL_VERSION (300).
    ProtocolVersion,
    /// AVAILABLE_MODES (435) of one mode (1-based) or of all (0).
    AvailableModes(u8),
    /// COMPONENT_METADATA (397): where the general metadata file is.
    ComponentMetadata,
    /// COMPONENT_INFORMATION (395, deprecated; PX4 still answers it) likewise.
    ComponentInformation,
    /// One message of a telemetry stream.
    TelemetryStream(TelemetryStream),
}

/// The message REQUEST_MESSAGE(`id`, `param2`) asks for, when we can produce it.
pub(super) fn one_shot(id: f32, param2: f32) -> Option<OneShot> {
    Some(match id as u32 {
        148 => OneShot::AutopilotVersion,
        300 => OneShot::ProtocolVersion,
        395 => OneShot::ComponentInformation,
        397 => OneShot::ComponentMetadata,
        // PX4 rounds the index; NaN (unset) asks for all.
        435 if param2.is_nan() || (0.0..=255.0).contains(&param2.round()) => {
            OneShot::AvailableModes(if param2.is_nan() { 0 } else { param2.round() as u8 })
        }
        // Any streamed message (CURRENT_MODE, SYSTEM_TIME, HOME_POSITION, …), as PX4 answers
        // REQUEST_MESSAGE for its streams.
        other => OneShot::TelemetryStream(*TelemetryStream::ALL.iter().find(|s| s.message_id() == other)?),
    })
}

/// AUTOPILOT_VERSION (docs/mavlink.md §4): MISSION_INT, COMMAND_INT, PARAM_ENCODE_BYTEWISE,
/// SET_ATTITUDE_TARGET, SET_POSITION_TARGET_LOCAL_NED / _GLOBAL_INT, MAVLINK2, FTP (served by
/// [`super::ftp`]) and the fence and rally plans (MISSION_FENCE, MISSION_RALLY, as PX4); the
/// version packs 0.1.0 as a release (type byte 255); `uid` is unique per system id. Presented as
/// ArduCopter (docs/ardupilot.md §1): Copter's capabilities (MISSION_FLOAT, parameters cast, not
/// byte-wise, FLIGHT_TERMINATION) and its release, [`COPTER_RELEASE`].
pub fn autopilot_version(id: &Identity) -> MavMessage {
    use MavProtocolCapability as C;
    let common = C::MAV_PROTOCOL_CAPABILITY_MISSION_INT
        | C::MAV_PROTOCOL_CAPABILITY_COMMAND_INT
        | C::MAV_PROTOCOL_CAPABILITY_SET_ATTITUDE_TARGET
        | C::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED
        | C::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_GLOBAL_INT
        | C::MAV_PROTOCOL_CAPABILITY_MAVLINK2
        | C::MAV_PROTOCOL_CAPABILITY_FTP
        | C::MAV_PROTOCOL_CAPABILITY_MISSION_FENCE
        | C::MAV_PROTOCOL_CAPABILITY_MISSION_RALLY;
    let (capabilities, flight_sw_version) = match id.personality {
        Personality::Px4 => (
            common | C::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE,
            (1 << 16) | 255,
        ),
        // ArduCopter: floats in MISSION_ITEM, parameters cast, flight termination; its release as
        // major.minor.patch, official (255).
        Personality::ArduPilot => {
            let (major, minor, patch) = COPTER_RELEASE;
            (
                common
                    | C::MAV_PROTOCOL_CAPABILITY_MISSION_FLOAT
                    | C::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST
                    | C::MAV_PROTOCOL_CAPABILITY_FLIGHT_TERMINATION,
                (u32::from(major) << 24) | (u32::from(minor) << 16) | (u32::from(patch) << 8) | 255,
            )
        }
    };
    MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
        capabilities,
        uid: 0x5250_0000_0000_0000 | u64::from(id.system_id),
        flight_sw_version,
        ..Default::default()
    })
}

/// Reply to a PING addressed to everyone (target 0/0), else `None` (a reply to ours).
pub fn ping_reply(sender: &MavHeader, ping: &PING_DATA) -> Option<MavMessage> {
    (ping.target_system == 0 && ping.target_component == 0).then_some({
        MavMessage::PING(PING_DATA {
            time_usec: ping.time_usec,
            seq: ping.seq,
            target_system: sender.system_id as u8,
            target_component: sender.component_id,
        })
    })
}

/// Reply to a TIMESYNC request (`tc1 == 0`) with our clock `now_ns` [ns]; `None` for replies.
pub fn timesync_reply(sender: &MavHeader, sync: &TIMESYNC_DATA, now_ns: i64) -> Option<MavMessage> {
    (sync.tc1 == 0).then_some({
        MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: now_ns,
            ts1: sync.ts1,
            target_system: sender.system_id as u8,
            target_component: sender.component_id,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::gcs_header;

    fn gcs() -> MavHeader {
        MavHeader {
            component_id: 230,
            ..gcs_header(0)
        }
    }

    #[test]
    fn ping_and_timesync_answer_requests_only() {
        let ping = PING_DATA {
            time_usec: 123,
            seq: 7,
            target_system: 0,
            target_component: 0,
        };
        let Some(MavMessage::PING(p)) = ping_reply(&gcs(), &ping) else {
            panic!("no reply");
        };
        assert_eq!((p.time_usec, p.seq, p.target_system), (123, 7, 255));
        assert!(ping_reply(
            &gcs(),
            &PING_DATA {
                target_system: 1,
                ..ping
            }
        )
        .is_none());
        let sync = TIMESYNC_DATA {
            tc1: 0,
            ts1: 55,
            target_system: 0,
            target_component: 0,
        };
        let Some(MavMessage::TIMESYNC(t)) = timesync_reply(&gcs(), &sync, 999) else {
            panic!("no reply");
        };
        assert_eq!((t.tc1, t.ts1), (999, 55));
        assert!(timesync_reply(&gcs(), &TIMESYNC_DATA { tc1: 5, ..sync }, 999).is_none());
    }

    #[test]
    fn autopilot_version_advertises_mavlink2_and_ftp() {
        let copter = Identity::autopilot(2, 4).with_personality(Personality::ArduPilot);
        let MavMessage::AUTOPILOT_VERSION(v) = autopilot_version(&copter) else {
            panic!("not AUTOPILOT_VERSION");
        };
        assert_eq!(v.flight_sw_version, 0x0405_07FF, "4.5.7, official");
        assert!(v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST));
        assert!(!v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE));
        let MavMessage::AUTOPILOT_VERSION(v) = autopilot_version(&Identity::autopilot(2, 4)) else {
            panic!("not a version");
        };
        assert!(v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2));
        let plans = MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_FENCE
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_RALLY;
        assert!(v.capabilities.contains(plans));
        assert!(v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_FTP));
        assert_eq!(v.uid & 0xFF, 2);
    }
}
