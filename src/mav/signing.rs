//! MAVLink 2 message signing (docs/mavlink.md §10): the key, the timestamps and the unsigned policy.
//! Pure: the wall clock comes in as a signing timestamp ([`timestamp_from_unix_us`]); the key
//! file and the persisted timestamp are the runtime's (`runtime::signing_store`).
//!
//! A signed frame carries incompat flag 0x01 and 13 more bytes: link id, a 48-bit timestamp in
//! 10 µs units since 2015-01-01 UTC, and the first 48 bits of
//! SHA-256(key ‖ header ‖ payload ‖ CRC ‖ link id ‖ timestamp).

use std::collections::HashMap;

use mavlink::{MAVLinkMessageRaw, MAVLinkV2MessageRaw};
use sha2::{Digest, Sha256};

use super::codec::recompute_crc;

/// Unix time of the signing epoch, 2015-01-01 00:00:00 UTC [s].
pub const SIGNING_EPOCH_UNIX_S: u64 = 1_420_070_400;
/// A stream not seen before is accepted only this far behind our timestamp: 60 s [10 µs].
pub const NEW_STREAM_WINDOW: u64 = 6_000_000;
/// Messages accepted unsigned while a key is set: HEARTBEAT and RADIO_STATUS (what a radio
/// modem sends on its own). PX4 also lets ADSB_VEHICLE and COLLISION through; this vehicle does
/// nothing with them, so they are dropped like the rest.
pub const UNSIGNED_ALLOWED: [u32; 2] = [0, 109];
/// Streams remembered at most; beyond, the stalest is forgotten (it then has to pass the
/// new-stream window again).
pub const MAX_STREAMS: usize = 4096;
/// Incompatibility flag of a signed frame.
const IFLAG_SIGNED: u8 = 0x01;

/// A 32-byte signing key. Its `Debug` never shows the bytes.
#[derive(Clone, PartialEq, Eq)]
pub struct SigningKey([u8; 32]);

impl std::fmt::Debug for SigningKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SigningKey(<redacted>)")
    }
}

/// Why a key file was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum KeyError {
    /// Empty, or only white space.
    #[error("the key file is empty (expected 32 key bytes or a passphrase)")]
    Empty,
    /// Neither 32 bytes nor UTF-8 text.
    #[error("the key file is {0} bytes of binary: expected exactly 32 key bytes or a UTF-8 passphrase")]
    NotAKey(usize),
}

impl SigningKey {
    /// The key `bytes` as they are.
    pub fn from_bytes(bytes: [u8; 32]) -> Self {
        Self(bytes)
    }

    /// SHA-256 of `passphrase` (MAVProxy's `signing setup PASSPHRASE`, pymavlink's convention).
    pub fn from_passphrase(passphrase: &str) -> Self {
        Self(Sha256::digest(passphrase.as_bytes()).into())
    }

    /// A key file: exactly 32 bytes are the key; anything else is a passphrase (UTF-8, surrounding
    /// white space and the final newline ignored).
    pub fn from_file_contents(contents: &[u8]) -> Result<Self, KeyError> {
        if let Ok(bytes) = <[u8; 32]>::try_from(contents) {
            return Ok(Self(bytes));
        }
        let text = std::str::from_utf8(contents).map_err(|_| KeyError::NotAKey(contents.len()))?;
        match text.trim() {
            "" => Err(KeyError::Empty),
            passphrase => Ok(Self::from_passphrase(passphrase)),
        }
    }

    /// The 32 key bytes (for the key file only).
    pub fn bytes(&self) -> &[u8; 32] {
        &self.0
    }

    /// All zero: SETUP_SIGNING's "disable signing".
    pub fn is_zero(&self) -> bool {
        self.0 == [0; 32]
    }
}

/// Unix time [µs] of signing timestamp `timestamp` [10 µs since 2015-01-01]; 0 for 0 (a clock
/// that was never set).
pub fn unix_us_from_timestamp(timestamp: u64) -> u64 {
    if timestamp == 0 {
        0
    } else {
        timestamp * 10 + SIGNING_EPOCH_UNIX_S * 1_000_000
    }
}

/// Signing timestamp of Unix time `unix_us` [µs]: 10 µs units since 2015-01-01 (0 before).
pub fn timestamp_from_unix_us(unix_us: u128) -> u64 {
    let since = unix_us.saturating_sub(u128::from(SIGNING_EPOCH_UNIX_S) * 1_000_000) / 10;
    u64::try_from(since).unwrap_or(u64::MAX)
}

/// What to do with one received frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Signing off, or a good signature with a fresh timestamp: handle it, its sender is a peer.
    Trusted,
    /// Unsigned but of a kind accepted unsigned ([`UNSIGNED_ALLOWED`]): handle it, register nothing.
    UnsignedAllowed,
    /// Drop it (counted).
    Dropped(DropReason),
}

/// Why a frame was dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DropReason {
    /// Unsigned (or MAVLink 1) and not in [`UNSIGNED_ALLOWED`].
    Unsigned,
    /// The signature does not match the key.
    BadSignature,
    /// Timestamp not newer than the stream's last (a replay).
    Replayed,
    /// A new stream more than [`NEW_STREAM_WINDOW`] behind our timestamp.
    Stale,
}

/// Frames dropped so far, by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DropCounts {
    /// Unsigned and not allowed.
    pub unsigned: u64,
    /// Wrong signature.
    pub bad_signature: u64,
    /// Replayed or stale timestamps.
    pub old_timestamp: u64,
}

impl DropCounts {
    /// Every dropped frame.
    pub fn total(&self) -> u64 {
        self.unsigned + self.bad_signature + self.old_timestamp
    }
}

/// The signing state of one vehicle (shared by its links).
#[derive(Debug, Default)]
pub struct Signing {
    key: Option<SigningKey>,
    /// The last timestamp sent or seen in a good frame [10 µs].
    timestamp: u64,
    /// Last timestamp per (link id, system id, component id) of good frames.
    streams: HashMap<(u8, u32, u8), u64>,
    dropped: DropCounts,
}

impl Signing {
    /// Signing with `key` (`None`: off until SETUP_SIGNING), starting from the persisted
    /// `timestamp` [10 µs].
    pub fn new(key: Option<SigningKey>, timestamp: u64) -> Self {
        Self {
            key,
            timestamp,
            ..Default::default()
        }
    }

    /// A key is set: incoming frames are checked and outgoing ones signed.
    pub fn enabled(&self) -> bool {
        self.key.is_some()
    }

    /// The last timestamp sent or seen [10 µs] (what the runtime persists).
    pub fn timestamp(&self) -> u64 {
        self.timestamp
    }

    /// Frames dropped so far.
    pub fn dropped(&self) -> DropCounts {
        self.dropped
    }

    /// SETUP_SIGNING: `key` with `initial_timestamp` [10 µs]; an all-zero key turns signing off.
    /// The timestamp never goes back; streams seen under the old key are forgotten.
    pub fn set_key(&mut self, key: SigningKey, initial_timestamp: u64) {
        self.key = (!key.is_zero()).then_some(key);
        self.timestamp = self.timestamp.max(initial_timestamp);
        self.streams.clear();
    }

    /// The verdict on `frame` at wall-clock timestamp `now` [10 µs]; a trusted signed frame
    /// advances its stream and our timestamp, a dropped one is counted.
    pub fn check(&mut self, frame: &MAVLinkMessageRaw, now: u64) -> Verdict {
        let verdict = self.verdict(frame, now);
        if let Verdict::Dropped(reason) = verdict {
            match reason {
                DropReason::Unsigned => self.dropped.unsigned += 1,
                DropReason::BadSignature => self.dropped.bad_signature += 1,
                DropReason::Replayed | DropReason::Stale => self.dropped.old_timestamp += 1,
            }
        }
        verdict
    }

    fn verdict(&mut self, frame: &MAVLinkMessageRaw, now: u64) -> Verdict {
        let Some(key) = &self.key else {
            return Verdict::Trusted;
        };
        let unsigned = |id: u32| {
            if UNSIGNED_ALLOWED.contains(&id) {
                Verdict::UnsignedAllowed
            } else {
                Verdict::Dropped(DropReason::Unsigned)
            }
        };
        let raw = match frame {
            MAVLinkMessageRaw::V1(raw) => return unsigned(u32::from(raw.message_id())),
            MAVLinkMessageRaw::V2(raw) if raw.incompatibility_flags() & IFLAG_SIGNED == 0 => {
                return unsigned(raw.message_id())
            }
            MAVLinkMessageRaw::V2(raw) => raw,
        };
        let mut expected = [0u8; 6];
        raw.calculate_signature(&key.0, &mut expected);
        if expected != raw.signature_value() {
            return Verdict::Dropped(DropReason::BadSignature);
        }
        let stamp = raw.signature_timestamp();
        let stream = (raw.signature_link_id(), raw.system_id(), raw.component_id());
        match self.streams.get(&stream) {
            Some(&last) if stamp <= last => return Verdict::Dropped(DropReason::Replayed),
            None if stamp.saturating_add(NEW_STREAM_WINDOW) < self.timestamp.max(now) => {
                return Verdict::Dropped(DropReason::Stale)
            }
            _ => {}
        }
        if self.streams.len() >= MAX_STREAMS && !self.streams.contains_key(&stream) {
            if let Some(stalest) = self.streams.iter().min_by_key(|(_, t)| **t).map(|(k, _)| *k) {
                self.streams.remove(&stalest);
            }
        }
        self.streams.insert(stream, stamp);
        self.timestamp = self.timestamp.max(stamp);
        Verdict::Trusted
    }

    /// Signs `frame` (serialized unsigned) for link `link_id` at wall-clock timestamp `now`
    /// [10 µs] when a key is set: sets the signed flag, recomputes the CRC and appends link id,
    /// timestamp max(now, last + 1) and signature. Without a key the frame stays as it is.
    pub fn seal(&mut self, frame: &mut MAVLinkV2MessageRaw, link_id: u8, now: u64) {
        let Some(key) = &self.key else {
            return;
        };
        *frame.incompatibility_flags_mut() |= IFLAG_SIGNED;
        recompute_crc(frame);
        self.timestamp = now.max(self.timestamp + 1);
        *frame.signature_link_id_mut() = link_id;
        frame
            .signature_timestamp_bytes_mut()
            .copy_from_slice(&self.timestamp.to_le_bytes()[..6]);
        let mut signature = [0u8; 6];
        frame.calculate_signature(&key.0, &mut signature);
        frame.signature_value_mut().copy_from_slice(&signature);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, COMMAND_LONG_DATA, HEARTBEAT_DATA};
    use mavlink::Message;

    const NOW: u64 = 40_000_000_000;

    fn key(byte: u8) -> SigningKey {
        SigningKey::from_bytes([byte; 32])
    }

    fn arm() -> MavMessage {
        MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            param1: 1.0,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        })
    }

    /// `msg` from the ground station (255, 190), signed by `signer` on link 3 at `now`.
    fn frame(msg: &MavMessage, signer: &mut Signing, now: u64) -> MAVLinkV2MessageRaw {
        let mut raw = MAVLinkV2MessageRaw::new();
        raw.serialize_message(crate::mav::gcs::gcs_header(0), msg);
        signer.seal(&mut raw, 3, now);
        raw
    }

    /// The frame as the receiver's codec reads it back from the wire.
    fn received(raw: &MAVLinkV2MessageRaw) -> MAVLinkMessageRaw {
        let mut reader = mavlink::MavlinkReader::with_capacity(0, raw.raw_bytes());
        reader.read_any_raw_message::<MavMessage>().expect("one frame")
    }

    #[test]
    fn signed_frames_pass_once_and_replays_unsigned_and_wrong_keys_are_dropped() {
        let mut gcs = Signing::new(Some(key(7)), 0);
        let mut vehicle = Signing::new(Some(key(7)), 0);
        let good = frame(&arm(), &mut gcs, NOW);
        assert_eq!(vehicle.check(&received(&good), NOW), Verdict::Trusted);
        assert_eq!(
            vehicle.check(&received(&good), NOW),
            Verdict::Dropped(DropReason::Replayed)
        );
        let next = frame(&arm(), &mut gcs, NOW);
        assert_eq!(vehicle.check(&received(&next), NOW), Verdict::Trusted);

        let mut stranger = Signing::new(Some(key(8)), 0);
        let forged = frame(&arm(), &mut stranger, NOW + 10);
        assert_eq!(
            vehicle.check(&received(&forged), NOW),
            Verdict::Dropped(DropReason::BadSignature)
        );
        let unsigned = frame(&arm(), &mut Signing::default(), NOW);
        assert_eq!(
            vehicle.check(&received(&unsigned), NOW),
            Verdict::Dropped(DropReason::Unsigned)
        );
        let heartbeat = frame(
            &MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()),
            &mut Signing::default(),
            NOW,
        );
        assert_eq!(vehicle.check(&received(&heartbeat), NOW), Verdict::UnsignedAllowed);
        let radio = frame(
            &MavMessage::RADIO_STATUS(Default::default()),
            &mut Signing::default(),
            NOW,
        );
        assert_eq!(vehicle.check(&received(&radio), NOW), Verdict::UnsignedAllowed);
        let collision = frame(&MavMessage::COLLISION(Default::default()), &mut Signing::default(), NOW);
        assert_eq!(
            vehicle.check(&received(&collision), NOW),
            Verdict::Dropped(DropReason::Unsigned)
        );
        assert_eq!(
            vehicle.dropped(),
            DropCounts {
                unsigned: 2,
                bad_signature: 1,
                old_timestamp: 1
            }
        );
    }

    #[test]
    fn a_new_stream_more_than_a_minute_old_is_stale() {
        let mut vehicle = Signing::new(Some(key(1)), 0);
        let mut gcs = Signing::new(Some(key(1)), 0);
        let old = frame(&arm(), &mut gcs, NOW - NEW_STREAM_WINDOW - 1);
        assert_eq!(vehicle.check(&received(&old), NOW), Verdict::Dropped(DropReason::Stale));
        let mut gcs = Signing::new(Some(key(1)), 0);
        let recent = frame(&arm(), &mut gcs, NOW - NEW_STREAM_WINDOW + 1);
        assert_eq!(vehicle.check(&received(&recent), NOW), Verdict::Trusted);
        assert_eq!(vehicle.timestamp(), NOW - NEW_STREAM_WINDOW + 1);
    }

    #[test]
    fn outgoing_timestamps_increase_past_the_clock_and_what_was_seen() {
        let mut vehicle = Signing::new(Some(key(2)), NOW + 500);
        let a = frame(&arm(), &mut vehicle, NOW);
        let b = frame(&arm(), &mut vehicle, NOW);
        assert_eq!(a.signature_timestamp(), NOW + 501);
        assert_eq!(b.signature_timestamp(), NOW + 502);
        let c = frame(&arm(), &mut vehicle, NOW + 1000);
        assert_eq!((c.signature_timestamp(), c.signature_link_id()), (NOW + 1000, 3));
        assert_eq!(vehicle.timestamp(), NOW + 1000);
        // The receiver's codec accepts the resealed CRC and the message parses.
        let back = received(&c);
        assert_eq!(
            MavMessage::parse(back.version(), back.message_id(), back.payload()).ok(),
            Some(arm())
        );
    }

    #[test]
    fn without_a_key_everything_is_trusted_and_nothing_is_signed() {
        let mut off = Signing::default();
        let raw = frame(&arm(), &mut off, NOW);
        assert_eq!(raw.incompatibility_flags(), 0);
        assert_eq!(off.check(&received(&raw), NOW), Verdict::Trusted);
        let mut on = Signing::new(Some(key(3)), 0);
        on.set_key(SigningKey::from_bytes([0; 32]), 0);
        assert!(!on.enabled(), "an all-zero key turns signing off");
    }

    #[test]
    fn key_files_hold_32_bytes_or_a_passphrase_and_debug_hides_them() {
        assert_eq!(SigningKey::from_file_contents(&[9; 32]), Ok(key(9)));
        // SHA-256("hello"), as `hashlib.sha256(b"hello")` gives it.
        let hello = SigningKey::from_file_contents(b"hello\n").unwrap();
        assert_eq!(
            hello.bytes()[..4],
            [0x2c, 0xf2, 0x4d, 0xba],
            "sha256(hello) = 2cf24dba…"
        );
        assert_eq!(SigningKey::from_file_contents(b" \n"), Err(KeyError::Empty));
        assert_eq!(SigningKey::from_file_contents(&[0xff; 5]), Err(KeyError::NotAKey(5)));
        assert_eq!(format!("{:?}", key(0x41)), "SigningKey(<redacted>)");
    }

    #[test]
    fn the_signing_epoch_is_2015() {
        assert_eq!(
            timestamp_from_unix_us(u128::from(SIGNING_EPOCH_UNIX_S) * 1_000_000 + 25),
            2
        );
        assert_eq!(timestamp_from_unix_us(0), 0);
    }
}
