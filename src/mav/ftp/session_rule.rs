//! How an FTP server numbers its sessions: PX4's way or ArduPilot's ([`SessionRule`]). Pure.

use super::payload::ErrorCode;

/// ArduPilot's server lets the open file sit this long without a reply before a request under
/// another session number may take its place, or an OpenFileRO replace it [s] (GCS_FTP.cpp's
/// `FTP_SESSION_TIMEOUT`, 3000 ms).
pub const ARDUPILOT_TAKEOVER_S: f64 = 3.0;

/// How a server numbers its sessions.
///
/// ArduPilot's rule, as read in ArduPilot/ardupilot `libraries/GCS_MAVLink/GCS_FTP.cpp` (the
/// single-session server of ArduCopter 4.x, `GCS_MAVLINK::ftp_worker`, at commit dc22505c; the
/// session logic is the same in the later 4.x copies):
/// - every reply, NAKs and burst frames included, carries the session number of its request;
/// - OpenFileRO, OpenFileWO and CreateFile open the one file under the number the client sent;
///   an open while a file is open is refused with Fail, except that an OpenFileRO finding the
///   file idle for more than 3 s closes it and opens the new one;
/// - a request under another number while a file is open is refused with InvalidSession while
///   the open file had a reply in the last 3 s; after that the old file is closed and the
///   request runs; a TerminateSession or ResetSessions under another number is ACKed and closes
///   nothing (so TerminateSession with nothing open is ACKed too);
/// - ReadFile, BurstReadFile or WriteFile with nothing open are refused with FileNotFound;
/// - a request repeated (same session, sequence number one before the last reply's) gets the
///   last reply again; the file stays open until closed or taken over (no idle expiry).
///
/// So a new open does not replace an open file at once. Here the repeated reply is kept only
/// when small (≤ 4 data bytes), as for PX4, since a burst here interleaves with requests.
/// ArduPilot's newest server (class `GCS_FTP`) keeps five sessions keyed by sender and number;
/// ArduCopter 4.5, whose banner this vehicle shows, keeps one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SessionRule {
    /// PX4's `MavlinkFTP`: an open takes a free slot (0 first), the ACK names it, a request
    /// names a slot, an unknown one is InvalidSession; idle sessions close after
    /// [`SESSION_IDLE_S`](super::SESSION_IDLE_S).
    #[default]
    Px4,
    /// ArduPilot's `GCS_FTP`: one session at a time, numbered by the client (above).
    ArduPilot,
}

impl SessionRule {
    /// The slot of session number `id`: the number itself (PX4), the one file's (ArduPilot).
    pub(super) fn slot(self, id: u8) -> usize {
        match self {
            Self::Px4 => usize::from(id),
            Self::ArduPilot => 0,
        }
    }

    /// The refusal of a request on a session that is not open.
    pub(super) fn not_open(self) -> ErrorCode {
        match self {
            Self::Px4 => ErrorCode::InvalidSession,
            Self::ArduPilot => ErrorCode::FileNotFound,
        }
    }
}
