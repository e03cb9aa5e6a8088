//! Small request/reply services (mavlink.md §4, §9): the messages REQUEST_MESSAGE can ask for,
//! AUTOPILOT_VERSION, PING, TIMESYNC and the MAVLink-FTP NAK that makes MAVProxy fall back to the parameter protocol at once. Pure.
//!
//! PING is deprecated in the spec, but MAVSDK sends one every 5 s to PX4 and expects the reply.
#![allow(deprecated)]

use mavlink::dialects::common::{
    MavMessage, MavProtocolCapability, AUTOPILOT_VERSION_DATA, FILE_TRANSFER_PROTOCOL_DATA, PING_DATA, TIMESYNC_DATA,
};
use mavlink::MavHeader;

use super::telemetry::Stream;
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
    /// One message of a telemetry stream.
    Stream(Stream),
}

/// The message REQUEST_MESSAGE(`id`, `param2`) asks for, when we can produce it.
pub(super) fn one_shot(id: f32, param2: f32) -> Option<OneShot> {
    Some(match id as u32 {
        148 => OneShot::AutopilotVersion,
        300 => OneShot::ProtocolVersion,
        // PX4 rounds the index; NaN (unset) asks for all.
        435 if param2.is_nan() || (0.0..=255.0).contains(&param2.round()) => {
            OneShot::AvailableModes(if param2.is_nan() { 0 } else { param2.round() as u8 })
        }
        436 => OneShot::Stream(Stream::CurrentMode),
        1 => OneShot::Stream(Stream::SysStatus),
        30 => OneShot::Stream(Stream::Attitude),
        32 => OneShot::Stream(Stream::LocalPosition),
        33 => OneShot::Stream(Stream::GlobalPosition),
        242 => OneShot::Stream(Stream::HomePosition),
        245 => OneShot::Stream(Stream::ExtendedSysState),
        _ => return None,
    })
}

/// FTP opcodes (mavlink.md §9).
const FTP_ACK: u8 = 128;
const FTP_NAK: u8 = 129;
const FTP_TERMINATE_SESSION: u8 = 1;
const FTP_RESET_SESSIONS: u8 = 2;
const FTP_OPEN_FILE_RO: u8 = 4;
const FTP_OPEN_FILE_WO: u8 = 11;
const FTP_CREATE_FILE: u8 = 6;
const FTP_ERR_UNKNOWN_COMMAND: u8 = 7;
const FTP_ERR_FILE_NOT_FOUND: u8 = 10;

/// AUTOPILOT_VERSION (mavlink.md §4): MISSION_INT, COMMAND_INT, PARAM_ENCODE_BYTEWISE,
/// SET_ATTITUDE_TARGET, SET_POSITION_TARGET_LOCAL_NED / _GLOBAL_INT, MAVLINK2 and the fence and
/// rally plans (MISSION_FENCE, MISSION_RALLY, as PX4) — not FTP, which would make QGC try that
/// transfer; the version packs 0.1.0 as a
/// release (type byte 255); `uid` is unique per system id.
pub fn autopilot_version(id: &Identity) -> MavMessage {
    MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
        capabilities: MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_INT
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_ATTITUDE_TARGET
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_GLOBAL_INT
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_FENCE
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_RALLY,
        uid: 0x5250_0000_0000_0000 | u64::from(id.system_id),
        flight_sw_version: (1 << 16) | 255,
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

/// The FTP reply: NAK (FileNotFound for opens, UnknownCommand otherwise), ACK for session
/// resets; `seq + 1`, same session, `req_opcode` echoed.
pub fn ftp_reply(sender: &MavHeader, ftp: &FILE_TRANSFER_PROTOCOL_DATA) -> MavMessage {
    let req = &ftp.payload;
    let seq = u16::from_le_bytes([req[0], req[1]]).wrapping_add(1);
    let opcode = req[3];
    let mut payload = [0u8; 251];
    payload[0..2].copy_from_slice(&seq.to_le_bytes());
    payload[2] = req[2];
    payload[5] = opcode;
    match opcode {
        FTP_TERMINATE_SESSION | FTP_RESET_SESSIONS => payload[3] = FTP_ACK,
        _ => {
            payload[3] = FTP_NAK;
            payload[4] = 1;
            payload[12] = if matches!(opcode, FTP_OPEN_FILE_RO | FTP_OPEN_FILE_WO | FTP_CREATE_FILE) {
                FTP_ERR_FILE_NOT_FOUND
            } else {
                FTP_ERR_UNKNOWN_COMMAND
            };
        }
    }
    MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
        target_network: 0,
        target_system: sender.system_id as u8,
        target_component: sender.component_id,
        payload,
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
    fn ftp_open_gets_file_not_found_and_reset_gets_ack() {
        let mut payload = [0u8; 251];
        payload[0..2].copy_from_slice(&41u16.to_le_bytes());
        payload[2] = 3;
        payload[3] = FTP_OPEN_FILE_RO;
        let req = FILE_TRANSFER_PROTOCOL_DATA {
            target_network: 0,
            target_system: 1,
            target_component: 1,
            payload,
        };
        let MavMessage::FILE_TRANSFER_PROTOCOL(r) = ftp_reply(&gcs(), &req) else {
            panic!("not ftp");
        };
        assert_eq!(&r.payload[..6], &[42, 0, 3, FTP_NAK, 1, FTP_OPEN_FILE_RO]);
        assert_eq!(r.payload[12], FTP_ERR_FILE_NOT_FOUND);
        assert_eq!((r.target_system, r.target_component), (255, 230));
        let mut reset = req;
        reset.payload[3] = FTP_RESET_SESSIONS;
        let MavMessage::FILE_TRANSFER_PROTOCOL(r) = ftp_reply(&gcs(), &reset) else {
            panic!("not ftp");
        };
        assert_eq!(r.payload[3], FTP_ACK);
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
    fn autopilot_version_advertises_mavlink2() {
        let MavMessage::AUTOPILOT_VERSION(v) = autopilot_version(&Identity::autopilot(2, 4)) else {
            panic!("not a version");
        };
        assert!(v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2));
        let plans = MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_FENCE
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_RALLY;
        assert!(v.capabilities.contains(plans));
        assert!(!v
            .capabilities
            .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_FTP));
        assert_eq!(v.uid & 0xFF, 2);
    }
}
