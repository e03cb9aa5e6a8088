//! Datagram ↔ MAVLink frames (docs/mavlink.md §13.2, §13.3). Pure: bytes in, typed messages out.
//!
//! Every datagram is parsed with a fresh reader (frames never straddle datagrams), MAVLink 1 and
//! 2 alike, truncated MAVLink 2 payloads included. A COMMAND_LONG / COMMAND_INT whose command id
//! the crate's `MavCmd` enum does not know still yields its sender, target and id, so it can be
//! answered with `MAV_RESULT_UNSUPPORTED`; [`unsupported_command_ack`] builds that reply by hand.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavResult, COMMAND_ACK_DATA};
use mavlink::{MAVLinkMessageRaw, MAVLinkV2MessageRaw, MavHeader, MavlinkVersion, Message};

/// COMMAND_INT message id.
const COMMAND_INT_ID: u32 = 75;
/// COMMAND_LONG message id.
const COMMAND_LONG_ID: u32 = 76;
/// Byte offset of `command` (u16 LE) in both COMMAND_LONG and COMMAND_INT payloads.
const COMMAND_OFFSET: usize = 28;
/// Length of the COMMAND_INT payload without extensions (the longer of the two).
const COMMAND_PAYLOAD_LEN: usize = 35;

/// One frame found in a datagram.
#[derive(Debug, Clone, PartialEq)]
pub enum Inbound {
    /// A CRC-valid frame of a message this dialect knows.
    Message {
        /// Sender and sequence.
        header: MavHeader,
        /// Wire version.
        version: MavlinkVersion,
        /// The message.
        message: Box<MavMessage>,
    },
    /// A CRC-valid COMMAND_LONG / COMMAND_INT whose command (or an enum field) the crate cannot parse.
    UnknownCommand {
        /// Sender and sequence.
        header: MavHeader,
        /// The raw command id.
        command: u16,
        /// Addressed system.
        target_system: u8,
        /// Addressed component.
        target_component: u8,
    },
    /// A CRC-valid frame whose payload could not be parsed (counted, otherwise ignored).
    Unparsable {
        /// Message id.
        message_id: u32,
    },
}

/// Every frame in `datagram`, in order; garbage between frames is skipped.
pub fn decode_datagram(datagram: &[u8]) -> Vec<Inbound> {
    decode_datagram_checked(datagram, |_| Some(()))
        .into_iter()
        .map(|(frame, ())| frame)
        .collect()
}

/// Every CRC-valid frame of `datagram` that `check` admits, with what `check` said of it;
/// frames it refuses (`None`: a bad signature, say) are skipped before their payload is parsed.
pub fn decode_datagram_checked<T>(
    datagram: &[u8],
    mut check: impl FnMut(&MAVLinkMessageRaw) -> Option<T>,
) -> Vec<(Inbound, T)> {
    let mut reader = mavlink::MavlinkReader::with_capacity(0, datagram);
    let mut out = Vec::new();
    while let Ok(raw) = reader.read_any_raw_message::<MavMessage>() {
        let Some(verdict) = check(&raw) else {
            continue;
        };
        let header = MavHeader {
            system_id: raw.system_id(),
            component_id: raw.component_id(),
            sequence: raw.sequence(),
        };
        let id = raw.message_id();
        let frame = match MavMessage::parse(raw.version(), id, raw.payload()) {
            Ok(message) => Inbound::Message {
                header,
                version: raw.version(),
                message: Box::new(message),
            },
            Err(_) if id == COMMAND_LONG_ID || id == COMMAND_INT_ID => {
                let mut payload = [0u8; COMMAND_PAYLOAD_LEN];
                let n = raw.payload().len().min(COMMAND_PAYLOAD_LEN);
                payload[..n].copy_from_slice(&raw.payload()[..n]);
                Inbound::UnknownCommand {
                    header,
                    command: u16::from_le_bytes([payload[COMMAND_OFFSET], payload[COMMAND_OFFSET + 1]]),
                    target_system: payload[COMMAND_OFFSET + 2],
                    target_component: payload[COMMAND_OFFSET + 3],
                }
            }
            Err(_) => Inbound::Unparsable { message_id: id },
        };
        out.push((frame, verdict));
    }
    out
}

/// `message` from `header` as one unsigned MAVLink 2 frame (to be sealed by `signing` or sent
/// as `raw_bytes()`).
pub fn frame_message(header: MavHeader, message: &MavMessage) -> MAVLinkV2MessageRaw {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message(header, message);
    raw
}

/// Appends `message` from `header` as one unsigned MAVLink 2 frame to `buf`.
pub fn encode_v2(header: MavHeader, message: &MavMessage, buf: &mut Vec<u8>) {
    buf.extend_from_slice(frame_message(header, message).raw_bytes());
}

/// Appends one MAVLink 2 frame of message `message_id` from `header` carrying `payload` as is
/// (at most 255 bytes; longer is cut), with the CRC the dialect expects for that id: what a
/// sender that got the fields wrong but the framing right would send (fuzzing, flood tests).
pub fn frame_v2(header: MavHeader, message_id: u32, payload: &[u8], buf: &mut Vec<u8>) {
    let raw = frame_payload(header, message_id, MavMessage::extra_crc(message_id), payload);
    buf.extend_from_slice(raw.raw_bytes());
}

/// One unsigned MAVLink 2 frame of message `message_id` from `header` carrying `payload` as is
/// (at most 255 bytes; longer is cut) with CRC extra `crc_extra`: a frame built by hand, for a
/// payload the crate's encoder cannot make (docs/mavlink.md §13.5).
pub fn frame_payload(header: MavHeader, message_id: u32, crc_extra: u8, payload: &[u8]) -> MAVLinkV2MessageRaw {
    let payload = &payload[..payload.len().min(255)];
    let len = payload.len();
    let mut raw = MAVLinkV2MessageRaw::new();
    let b = raw.as_mut_slice();
    b[0] = mavlink::MAV_STX_V2;
    b[1] = len as u8;
    b[2..5].copy_from_slice(&[0, 0, header.sequence]);
    b[5] = header.system_id as u8;
    b[6] = header.component_id;
    b[7..V2_HEADER_LEN].copy_from_slice(&message_id.to_le_bytes()[..3]);
    b[V2_HEADER_LEN..V2_HEADER_LEN + len].copy_from_slice(payload);
    let crc = mavlink::calculate_crc(&b[1..V2_HEADER_LEN + len], crc_extra);
    b[V2_HEADER_LEN + len..V2_HEADER_LEN + len + 2].copy_from_slice(&crc.to_le_bytes());
    raw
}

/// A MAVLink 2 COMMAND_ACK with `MAV_RESULT_UNSUPPORTED` for a command id the dialect may not
/// know, addressed to `target_system`/`target_component` (docs/mavlink.md §13.3).
pub fn unsupported_command_ack(
    header: MavHeader,
    command: u16,
    target_system: u8,
    target_component: u8,
) -> MAVLinkV2MessageRaw {
    command_ack_frame(
        header,
        command,
        MavResult::MAV_RESULT_UNSUPPORTED,
        (target_system, target_component),
    )
}

/// A MAVLink 2 COMMAND_ACK with `result` for a command id the dialect may not know (an unknown
/// command, or ArduCopter's ACK of SET_MODE, whose "command" is the message id 11), addressed to
/// `target` (system, component): the crate encodes an ACK for a placeholder command, then the
/// command bytes are replaced and the CRC recomputed.
pub fn command_ack_frame(header: MavHeader, command: u16, result: MavResult, target: (u8, u8)) -> MAVLinkV2MessageRaw {
    let ack = MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        result,
        target_system: target.0,
        target_component: target.1,
        ..Default::default()
    });
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message(header, &ack);
    // STX, 9 header bytes, payload (command u16 LE first), CRC.
    raw.as_mut_slice()[V2_HEADER_LEN..V2_HEADER_LEN + 2].copy_from_slice(&command.to_le_bytes());
    recompute_crc(&mut raw);
    raw
}

/// STX and the 9 header bytes of a MAVLink 2 frame.
const V2_HEADER_LEN: usize = 10;

/// Recomputes the CRC of `raw` after its header or payload bytes were changed in place.
pub fn recompute_crc(raw: &mut MAVLinkV2MessageRaw) {
    let len = usize::from(raw.payload_length());
    let extra = MavMessage::extra_crc(raw.message_id());
    let bytes = raw.as_mut_slice();
    let crc = mavlink::calculate_crc(&bytes[1..V2_HEADER_LEN + len], extra);
    bytes[V2_HEADER_LEN + len..V2_HEADER_LEN + len + 2].copy_from_slice(&crc.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::command_long;
    use mavlink::dialects::ardupilotmega::HEARTBEAT_DATA;

    fn header(system_id: u32) -> MavHeader {
        MavHeader {
            system_id,
            component_id: 190,
            sequence: 7,
        }
    }

    #[test]
    fn frame_v2_matches_the_crate_encoder() {
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA::default());
        let mut expected = Vec::new();
        encode_v2(header(255), &hb, &mut expected);
        let payload = &expected[10..expected.len() - 2];
        let mut framed = Vec::new();
        frame_v2(header(255), 0, payload, &mut framed);
        assert_eq!(framed, expected);
    }

    #[test]
    fn v1_and_v2_frames_round_trip_and_garbage_is_skipped() {
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA::default());
        let arm = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let cmd = MavMessage::COMMAND_LONG(command_long((1, 1), MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, arm));
        let mut buf = vec![0x00, 0x13, 0x37];
        encode_v2(header(255), &hb, &mut buf);
        buf.extend_from_slice(&[0xFD, 0x01]); // a truncated frame start
        mavlink::write_v1_msg(&mut buf, header(254), &cmd).unwrap();
        let frames = decode_datagram(&buf);
        assert_eq!(frames.len(), 2, "{frames:?}");
        match &frames[1] {
            Inbound::Message {
                header,
                version,
                message,
            } => {
                assert_eq!((header.system_id, *version), (254, MavlinkVersion::V1));
                assert_eq!(**message, cmd);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn truncated_v2_payload_parses() {
        // MAVLink 2 cuts trailing zeros: a COMMAND_LONG with confirmation 0 is 32 bytes long.
        let cmd = MavMessage::COMMAND_LONG(command_long((1, 1), MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0; 7]));
        let mut buf = Vec::new();
        encode_v2(header(255), &cmd, &mut buf);
        assert_eq!(buf[1], 32);
        assert!(matches!(&decode_datagram(&buf)[0], Inbound::Message { message, .. } if **message == cmd));
    }

    #[test]
    fn unknown_command_id_is_recovered_and_answered() {
        let cmd = MavMessage::COMMAND_LONG(command_long((1, 0), MavCmd::MAV_CMD_DO_SET_MODE, [0.0; 7]));
        let mut buf = Vec::new();
        encode_v2(header(255), &cmd, &mut buf);
        // Patch the command id to 31999 (not in MavCmd) and fix the CRC.
        let len = usize::from(buf[1]);
        buf[10 + COMMAND_OFFSET..12 + COMMAND_OFFSET].copy_from_slice(&31999u16.to_le_bytes());
        let crc = mavlink::calculate_crc(&buf[1..10 + len], MavMessage::extra_crc(76));
        buf[10 + len..12 + len].copy_from_slice(&crc.to_le_bytes());
        let frames = decode_datagram(&buf);
        assert_eq!(
            frames,
            vec![Inbound::UnknownCommand {
                header: header(255),
                command: 31999,
                target_system: 1,
                target_component: 0
            }]
        );
        // The hand-built ACK equals the crate's encoding for a known command with the same fields.
        let ack = unsupported_command_ack(header(1), 176, 255, 190);
        let mut expected = Vec::new();
        encode_v2(
            header(1),
            &MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
                command: MavCmd::MAV_CMD_DO_SET_MODE,
                result: MavResult::MAV_RESULT_UNSUPPORTED,
                target_system: 255,
                target_component: 190,
                ..Default::default()
            }),
            &mut expected,
        );
        assert_eq!(ack.raw_bytes(), expected);
        let unknown = unsupported_command_ack(header(1), 31999, 255, 190);
        assert!(matches!(
            &decode_datagram(unknown.raw_bytes())[0],
            Inbound::Unparsable { message_id: 77 }
        ));
    }
}
