//! The 251-byte payload of FILE_TRANSFER_PROTOCOL (msg 110) as MAVLink FTP lays it out: a
//! 12-byte header (sequence number, session, opcode, size, request opcode, burst-complete flag,
//! padding, offset; little endian) and up to 239 data bytes; the opcodes and NAK error codes
//! PX4's server uses. Pure.

use mavlink::dialects::ardupilotmega::{MavMessage, FILE_TRANSFER_PROTOCOL_DATA};

/// Bytes of the FILE_TRANSFER_PROTOCOL payload.
pub const PAYLOAD_LEN: usize = 251;
/// Bytes of the header before the data.
const HEADER_LEN: usize = 12;
/// Largest data field [bytes] (PX4's `kMaxDataLength`).
pub const DATA_MAX: usize = PAYLOAD_LEN - HEADER_LEN;

/// Request and response opcodes (`payload[3]`), numbered as MAVLink FTP numbers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Opcode {
    /// Nothing; always ACKed.
    None = 0,
    /// Closes one session.
    TerminateSession = 1,
    /// Closes every session.
    ResetSessions = 2,
    /// Lists the entries of a directory from an entry offset.
    ListDirectory = 3,
    /// Opens a file for reading; answers the session and the file size.
    OpenFileRO = 4,
    /// Reads up to `size` bytes at `offset` of a session.
    ReadFile = 5,
    /// Creates (or truncates) a file for writing.
    CreateFile = 6,
    /// Writes the data at `offset` of a session.
    WriteFile = 7,
    /// Removes a file.
    RemoveFile = 8,
    /// Creates a directory.
    CreateDirectory = 9,
    /// Removes an empty directory.
    RemoveDirectory = 10,
    /// Opens a file for writing, creating it when missing.
    OpenFileWO = 11,
    /// Truncates (or extends) a file to `offset` bytes.
    TruncateFile = 12,
    /// Renames the first NUL-terminated path to the second.
    Rename = 13,
    /// CRC-32 of a whole file.
    CalcFileCRC32 = 14,
    /// Streams a session's file from `offset` in a sequence of replies.
    BurstReadFile = 15,
    /// Positive response.
    Ack = 128,
    /// Negative response; `data[0]` is an [`ErrorCode`].
    Nak = 129,
}

impl Opcode {
    /// The opcode of `byte`, `None` for a number MAVLink FTP does not define.
    pub fn from_u8(byte: u8) -> Option<Self> {
        use Opcode::*;
        Some(match byte {
            0 => None,
            1 => TerminateSession,
            2 => ResetSessions,
            3 => ListDirectory,
            4 => OpenFileRO,
            5 => ReadFile,
            6 => CreateFile,
            7 => WriteFile,
            8 => RemoveFile,
            9 => CreateDirectory,
            10 => RemoveDirectory,
            11 => OpenFileWO,
            12 => TruncateFile,
            13 => Rename,
            14 => CalcFileCRC32,
            15 => BurstReadFile,
            128 => Ack,
            129 => Nak,
            _ => return Option::None,
        })
    }
}

/// Why a request failed: `data[0]` of a NAK (MAVLink FTP's error codes, as PX4 sends them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorCode {
    /// Unknown failure.
    Fail,
    /// Failed with this errno (sent in `data[1]`).
    FailErrno(u8),
    /// `size` beyond [`DATA_MAX`].
    InvalidDataSize,
    /// The session is not open.
    InvalidSession,
    /// Every session is in use.
    NoSessionsAvailable,
    /// Offset at or past the end of a file or directory.
    Eof,
    /// Opcode not handled.
    UnknownCommand,
    /// The file or directory exists already.
    FileExists,
    /// The path may not be written (or is outside what may be reached).
    FileProtected,
    /// No file or directory at the path.
    FileNotFound,
}

/// errno: is a directory.
pub const EISDIR: u8 = 21;
/// errno: invalid argument.
pub const EINVAL: u8 = 22;
/// errno: no space left on the device.
pub const ENOSPC: u8 = 28;
/// errno: directory not empty.
pub const ENOTEMPTY: u8 = 39;
/// errno: not a directory.
pub const ENOTDIR: u8 = 20;

impl ErrorCode {
    /// The NAK data: the code, and the errno after [`ErrorCode::FailErrno`].
    pub fn bytes(self) -> Vec<u8> {
        match self {
            Self::Fail => vec![1],
            Self::FailErrno(errno) => vec![2, errno],
            Self::InvalidDataSize => vec![3],
            Self::InvalidSession => vec![4],
            Self::NoSessionsAvailable => vec![5],
            Self::Eof => vec![6],
            Self::UnknownCommand => vec![7],
            Self::FileExists => vec![8],
            Self::FileProtected => vec![9],
            Self::FileNotFound => vec![10],
        }
    }
}

/// One FTP payload, header fields decoded; `data` holds the `size` bytes that count.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Payload {
    /// Sequence number: a reply carries the request's plus one.
    pub seq: u16,
    /// Session id.
    pub session: u8,
    /// Opcode byte (an [`Opcode`] when defined).
    pub opcode: u8,
    /// The request's opcode, in a reply.
    pub req_opcode: u8,
    /// Set in the last reply of a burst.
    pub burst_complete: bool,
    /// Byte offset (read, write, burst, truncate) or entry offset (list).
    pub offset: u32,
    /// The data: at most [`DATA_MAX`] bytes.
    pub data: Vec<u8>,
    /// The `size` byte as received (it may exceed [`DATA_MAX`] in a malformed request).
    pub size: u8,
}

impl Payload {
    /// FILE_TRANSFER_PROTOCOL carrying this payload to the system and component `target`.
    pub fn message(&self, target: (u8, u8)) -> MavMessage {
        MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
            target_network: 0,
            target_system: target.0,
            target_component: target.1,
            payload: self.encode(),
        })
    }

    /// The payload in `bytes`; data beyond [`DATA_MAX`] cannot exist, so a larger `size` keeps
    /// every data byte and records the size for the InvalidDataSize check.
    pub fn decode(bytes: &[u8; PAYLOAD_LEN]) -> Self {
        let size = bytes[4];
        let len = usize::from(size).min(DATA_MAX);
        Self {
            seq: u16::from_le_bytes([bytes[0], bytes[1]]),
            session: bytes[2],
            opcode: bytes[3],
            req_opcode: bytes[5],
            burst_complete: bytes[6] != 0,
            offset: u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]),
            data: bytes[HEADER_LEN..HEADER_LEN + len].to_vec(),
            size,
        }
    }

    /// The 251 bytes on the wire; `size` is the data length (data beyond [`DATA_MAX`] is cut).
    pub fn encode(&self) -> [u8; PAYLOAD_LEN] {
        let mut out = [0u8; PAYLOAD_LEN];
        let len = self.data.len().min(DATA_MAX);
        out[0..2].copy_from_slice(&self.seq.to_le_bytes());
        out[2] = self.session;
        out[3] = self.opcode;
        out[4] = len as u8;
        out[5] = self.req_opcode;
        out[6] = u8::from(self.burst_complete);
        out[8..12].copy_from_slice(&self.offset.to_le_bytes());
        out[HEADER_LEN..HEADER_LEN + len].copy_from_slice(&self.data[..len]);
        out
    }

    /// A request with `opcode`, `seq`, `session`, `offset` and `data` (a client's, for tests
    /// and the bench).
    pub fn request(opcode: Opcode, seq: u16, session: u8, offset: u32, data: &[u8]) -> Self {
        let data = data[..data.len().min(DATA_MAX)].to_vec();
        Self {
            seq,
            session,
            opcode: opcode as u8,
            req_opcode: 0,
            burst_complete: false,
            offset,
            size: data.len() as u8,
            data,
        }
    }

    /// The reply to this request: `seq + 1`, the same session and offset, `req_opcode` set,
    /// ACK with `data`.
    pub fn ack(&self, data: Vec<u8>) -> Self {
        Self {
            seq: self.seq.wrapping_add(1),
            opcode: Opcode::Ack as u8,
            req_opcode: self.opcode,
            burst_complete: false,
            size: data.len().min(DATA_MAX) as u8,
            data,
            ..self.clone()
        }
    }

    /// The NAK of this request with `error`.
    pub fn nak(&self, error: ErrorCode) -> Self {
        Self {
            opcode: Opcode::Nak as u8,
            ..self.ack(error.bytes())
        }
    }

    /// The path in the data: the bytes up to the first NUL (C string semantics, as PX4 reads
    /// it), `None` when they are not UTF-8.
    pub fn path(&self) -> Option<&str> {
        let end = self.data.iter().position(|b| *b == 0).unwrap_or(self.data.len());
        std::str::from_utf8(&self.data[..end]).ok()
    }

    /// The second NUL-separated path of a Rename, `None` when there is none.
    pub fn second_path(&self) -> Option<&str> {
        let first = self.data.iter().position(|b| *b == 0)?;
        let rest = &self.data[first + 1..];
        let end = rest.iter().position(|b| *b == 0).unwrap_or(rest.len());
        (end > 0).then_some(())?;
        std::str::from_utf8(&rest[..end]).ok()
    }

    /// The first four data bytes as a little-endian u32 (file sizes, CRCs, bytes written).
    pub fn data_u32(&self) -> Option<u32> {
        let b = self.data.get(..4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_round_trips_in_wire_order() {
        let mut p = Payload::request(Opcode::ReadFile, 0x1234, 3, 0xA0B0C0D0, b"abc");
        p.burst_complete = true;
        p.req_opcode = 9;
        let bytes = p.encode();
        assert_eq!(&bytes[..12], &[0x34, 0x12, 3, 5, 3, 9, 1, 0, 0xD0, 0xC0, 0xB0, 0xA0]);
        assert_eq!(&bytes[12..15], b"abc");
        assert_eq!(Payload::decode(&bytes), p);
    }

    #[test]
    fn replies_echo_the_request_and_naks_carry_their_code() {
        let req = Payload::request(Opcode::OpenFileRO, u16::MAX, 0, 7, b"/x\0");
        let ack = req.ack(vec![1, 0, 0, 0]);
        assert_eq!((ack.seq, ack.opcode, ack.req_opcode, ack.offset), (0, 128, 4, 7));
        assert_eq!(ack.data_u32(), Some(1));
        let nak = req.nak(ErrorCode::FailErrno(ENOSPC));
        assert_eq!((nak.opcode, nak.size, nak.data.clone()), (129, 2, vec![2, 28]));
        assert_eq!(req.nak(ErrorCode::FileNotFound).data, vec![10]);
        assert_eq!(Opcode::from_u8(15), Some(Opcode::BurstReadFile));
        assert_eq!(Opcode::from_u8(16), None);
    }

    #[test]
    fn paths_stop_at_nul_and_a_rename_has_two() {
        let req = Payload::request(Opcode::Rename, 0, 0, 0, b"/a/b\0/c\0junk");
        assert_eq!(req.path(), Some("/a/b"));
        assert_eq!(req.second_path(), Some("/c"));
        assert_eq!(Payload::request(Opcode::Rename, 0, 0, 0, b"/a").second_path(), None);
        assert_eq!(
            Payload::request(Opcode::OpenFileRO, 0, 0, 0, &[0xff, 0xfe]).path(),
            None
        );
        let mut bytes = [0u8; PAYLOAD_LEN];
        bytes[4] = 250;
        let p = Payload::decode(&bytes);
        assert_eq!((p.size, p.data.len()), (250, DATA_MAX));
    }
}
