//! Messages of another dialect than the common one, encoded by hand (docs/mavlink.md §13.5): the
//! crate is built with the common dialect only, so a message ArduPilot-minded ground stations
//! read (EKF_STATUS_REPORT of `ardupilotmega`) is laid out here field by field, with its id and
//! CRC extra, and framed as MAVLink 2 like any other. Pure.

use mavlink::{MAVLinkV2MessageRaw, MavHeader};

use super::codec::frame_payload;
use crate::telemetry::Snapshot;

/// EKF_STATUS_REPORT's message id (`ardupilotmega`).
pub const EKF_STATUS_REPORT_ID: u32 = 193;
/// EKF_STATUS_REPORT's CRC extra (`ardupilotmega`).
const EKF_STATUS_REPORT_CRC_EXTRA: u8 = 71;
/// Longest payload a foreign message here carries [bytes].
const MAX_PAYLOAD: usize = 32;

/// A message the common dialect does not know: id, CRC extra and wire payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForeignMessage {
    /// Message id.
    pub id: u32,
    /// CRC extra of the message's definition.
    pub crc_extra: u8,
    payload: [u8; MAX_PAYLOAD],
    len: usize,
}

impl ForeignMessage {
    /// The payload in wire order, MAVLink 2 style: trailing zero bytes cut, at least one kept.
    pub fn payload(&self) -> &[u8] {
        let end = self.payload[..self.len]
            .iter()
            .rposition(|&b| b != 0)
            .map_or(1, |i| i + 1);
        &self.payload[..end]
    }

    /// One unsigned MAVLink 2 frame of this message from `header`.
    pub fn frame(&self, header: MavHeader) -> MAVLinkV2MessageRaw {
        frame_payload(header, self.id, self.crc_extra, self.payload())
    }
}

/// Writes little-endian fields one after the other.
struct PayloadWriter {
    payload: [u8; MAX_PAYLOAD],
    len: usize,
}

impl PayloadWriter {
    fn new() -> Self {
        Self {
            payload: [0; MAX_PAYLOAD],
            len: 0,
        }
    }

    fn put(&mut self, bytes: &[u8]) {
        self.payload[self.len..self.len + bytes.len()].copy_from_slice(bytes);
        self.len += bytes.len();
    }

    fn finish(self, id: u32, crc_extra: u8) -> ForeignMessage {
        ForeignMessage {
            id,
            crc_extra,
            payload: self.payload,
            len: self.len,
        }
    }
}

/// EKF_STATUS_REPORT as ArduPilot fills it: the flags (the same bits as ESTIMATOR_STATUS's) and,
/// for velocity, horizontal position, vertical position and compass, the square root of the
/// test ratio ν² / (gate² S), which ground stations show against 0.5 (warning) and 0.8 (bad);
/// terrain and airspeed 0 (not estimated). With the state sensor every flag good and every
/// value 0. Wire order: the five floats, the flags, then the extension `airspeed_variance`.
pub fn ekf_status_report(s: &Snapshot) -> ForeignMessage {
    let (flags, [vel, pos_h, pos_v, mag, _height]) = match s.nav.filter {
        Some(f) => (f.flags, f.test_ratios.map(|r| r.max(0.0).sqrt() as f32)),
        None => (0x3FF & !0x80, [0.0; 5]),
    };
    let mut w = PayloadWriter::new();
    for v in [vel, pos_h, pos_v, mag, 0.0] {
        w.put(&v.to_le_bytes());
    }
    w.put(&flags.to_le_bytes());
    w.put(&0f32.to_le_bytes());
    w.finish(EKF_STATUS_REPORT_ID, EKF_STATUS_REPORT_CRC_EXTRA)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;
    use crate::telemetry::FilterSnapshot;

    fn header() -> MavHeader {
        MavHeader {
            system_id: 1,
            component_id: 1,
            sequence: 9,
        }
    }

    #[test]
    fn ekf_status_report_frame_has_the_ardupilot_layout_and_crc() {
        let mut s = Snapshot::initial(Home::default());
        s.nav.filter = Some(FilterSnapshot {
            flags: 0x1A7,
            test_ratios: [0.25, 0.04, 0.09, 0.16, 0.01],
            pos_std_m: (0.5, 0.8),
            vel_std_m_s: 0.2,
            heading_std_rad: 0.05,
        });
        let m = ekf_status_report(&s);
        let raw = m.frame(header());
        let bytes = raw.raw_bytes();
        assert_eq!(raw.message_id(), EKF_STATUS_REPORT_ID);
        assert_eq!(usize::from(raw.payload_length()), 22, "the zero extension is cut");
        let f = |i: usize| f32::from_le_bytes(bytes[10 + 4 * i..14 + 4 * i].try_into().unwrap());
        assert_eq!([f(0), f(1), f(2), f(3), f(4)], [0.5, 0.2, 0.3, 0.4, 0.0]);
        assert_eq!(u16::from_le_bytes([bytes[30], bytes[31]]), 0x1A7);
        let crc = mavlink::calculate_crc(&bytes[1..32], 71);
        assert_eq!(u16::from_le_bytes([bytes[32], bytes[33]]), crc);
    }

    #[test]
    fn with_the_state_sensor_every_estimate_is_good() {
        let m = ekf_status_report(&Snapshot::initial(Home::default()));
        let p = m.payload();
        assert_eq!(p.len(), 22);
        assert!(p[..20].iter().all(|&b| b == 0));
        assert_eq!(u16::from_le_bytes([p[20], p[21]]), 0x37F);
    }
}
