//! One MAVLink FTP server (PX4 runs one per MAVLink instance, i.e. per link): requests in,
//! replies out, as PX4's `MavlinkFTP` answers them. A reply carries the request's sequence
//! number plus one, its session and offset, and the request opcode; a failure is a NAK whose
//! data is the error code (and the errno after FailErrno). A request whose sequence number is
//! the one just answered gets the last reply again, when that reply was small (≤ 4 data bytes:
//! the replies with side effects), as PX4 does for a lost ACK. Sessions are bounded
//! ([`MAX_SESSIONS`]) and closed after [`SESSION_IDLE_S`] without a request. A burst read
//! answers nothing at once: [`FtpServer::burst_frame`] then yields the file from the offset,
//! one data reply after another with consecutive sequence numbers, and a NAK EOF after the
//! last byte. Pure: the caller passes the time and paces the burst.
//!
//! Sessions are numbered by a [`SessionRule`]: PX4's (the server picks a free slot and names it
//! in the open's ACK) or ArduPilot's (one file open at a time, under the number the client
//! chose; see the rule's docs for what was checked in ArduPilot's source).
//!
//! `@PARAM/param.pck` (`param_file.rs`) opens as PX4 opens it: for reading, a snapshot of the
//! vehicle's parameters ([`Storage::params`]); for writing, an upload held in the session. The
//! TerminateSession of an upload is not answered at once: the file, read, is handed out
//! ([`FtpServer::take_upload`]) for the vehicle to apply, and the answer comes when it has
//! ([`FtpServer::answer_upload`]); the same TerminateSession repeated meanwhile is ignored.

use super::param_file::ParamFile;
use super::param_pck::{is_param_path, parse_upload, PackedValue, PckError};
use super::payload::{ErrorCode, Opcode, Payload, DATA_MAX, EINVAL};
use super::session_rule::{SessionRule, ARDUPILOT_TAKEOVER_S};
use super::storage::Storage;
use super::vfs::Entry;

/// Sessions open at once (PX4 keeps one per link: a second open gets NoSessionsAvailable).
pub const MAX_SESSIONS: usize = 1;
/// Sessions are closed after this long without a request [s] (PX4: 10 s).
pub const SESSION_IDLE_S: f64 = 10.0;

/// An open file.
#[derive(Debug, Clone, PartialEq)]
enum Session {
    /// A file of the storage.
    File {
        /// Normalised path.
        path: String,
        /// Opened for writing (CreateFile, OpenFileWO).
        write: bool,
    },
    /// The packed parameters.
    Params(ParamFile),
}

impl Session {
    /// Size of the open file [bytes].
    fn size(&self, fs: &mut Storage) -> Result<u64, ErrorCode> {
        match self {
            Self::File { path, .. } => fs.size(path),
            Self::Params(file) => Ok(file.size() as u64),
        }
    }

    /// Up to `max` bytes of the open file from `offset`; Eof at or past its end.
    fn read(&self, fs: &mut Storage, offset: u32, max: usize) -> Result<Vec<u8>, ErrorCode> {
        match self {
            Self::File { path, .. } => fs.read_at(path, offset, max),
            Self::Params(file) => file.read(offset, max),
        }
    }
}

/// A parameter upload whose TerminateSession waits for the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamUpload {
    /// The TerminateSession to answer ([`FtpServer::answer_upload`]).
    pub request: Payload,
    /// The parameters in file order, or why the file was refused.
    pub parsed: Result<Vec<(String, PackedValue)>, PckError>,
}

/// A burst read in progress.
#[derive(Debug, Clone, PartialEq)]
struct Burst {
    session: u8,
    offset: u32,
    /// Sequence number of the next frame.
    seq: u16,
}

/// The FTP server of one link.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FtpServer {
    /// How sessions are numbered.
    rule: SessionRule,
    /// The client's number of the open file under ArduPilot's rule (the file is `sessions[0]`).
    current: Option<u8>,
    sessions: [Option<Session>; MAX_SESSIONS],
    /// The last reply when it had at most 4 data bytes (sent again for a repeated request).
    last_reply: Option<Payload>,
    burst: Option<Burst>,
    /// Time of the last request or burst frame [s].
    last_activity_s: f64,
    /// An upload read at its TerminateSession, until taken.
    upload: Option<ParamUpload>,
    /// Sequence number of the TerminateSession whose answer waits for the vehicle.
    awaiting: Option<u16>,
}

impl FtpServer {
    /// A server with no session open that numbers sessions by `rule`.
    pub fn new(rule: SessionRule) -> Self {
        Self {
            rule,
            ..Self::default()
        }
    }

    /// How this server numbers its sessions.
    pub fn rule(&self) -> SessionRule {
        self.rule
    }

    /// The reply to `req` at `now_s` [s] against `fs`; `None` when none is due now: a burst
    /// started (its frames come from [`burst_frame`](Self::burst_frame)), or an upload waits for
    /// the vehicle ([`take_upload`](Self::take_upload)).
    pub fn handle(&mut self, fs: &mut Storage, req: &Payload, now_s: f64) -> Option<Payload> {
        let idle_s = now_s - self.last_activity_s;
        self.last_activity_s = now_s;
        if self.awaiting == Some(req.seq) && req.opcode == Opcode::TerminateSession as u8 {
            return None;
        }
        let result = if usize::from(req.size) > DATA_MAX {
            Err(ErrorCode::InvalidDataSize)
        } else {
            if let Some(last) = &self.last_reply {
                let same_session = self.rule == SessionRule::Px4 || last.session == req.session;
                if req.seq.wrapping_add(1) == last.seq && same_session {
                    return Some(last.clone());
                }
            }
            self.work(fs, req, idle_s)
        };
        self.last_reply = None;
        let reply = match result {
            Ok(None) => return None,
            Ok(Some(reply)) => reply,
            Err(error) => req.nak(error),
        };
        self.remember(&reply);
        Some(reply)
    }

    /// The upload whose TerminateSession came last, read, once.
    pub fn take_upload(&mut self) -> Option<ParamUpload> {
        self.upload.take()
    }

    /// The answer to an upload's TerminateSession `request`: an ACK, or a NAK with the error;
    /// remembered, so that the request repeated gets it again.
    pub fn answer_upload(&mut self, request: &Payload, result: Result<(), ErrorCode>) -> Payload {
        if self.awaiting == Some(request.seq) {
            self.awaiting = None;
        }
        let reply = match result {
            Ok(()) => request.ack(Vec::new()),
            Err(error) => request.nak(error),
        };
        self.last_reply = None;
        self.remember(&reply);
        reply
    }

    /// True while a burst has frames to send.
    pub fn bursting(&self) -> bool {
        self.burst.is_some()
    }

    /// The next frame of the burst in progress at `now_s` [s], `None` when there is none.
    pub fn burst_frame(&mut self, fs: &mut Storage, now_s: f64) -> Option<Payload> {
        let burst = self.burst.as_mut()?;
        self.last_activity_s = now_s;
        let mut frame = Payload::request(Opcode::Ack, burst.seq, burst.session, burst.offset, &[]);
        frame.req_opcode = Opcode::BurstReadFile as u8;
        burst.seq = burst.seq.wrapping_add(1);
        let slot = self.rule.slot(burst.session);
        let session = self.sessions.get(slot).and_then(Option::as_ref);
        let error = match session.map(|s| s.read(fs, burst.offset, DATA_MAX)) {
            None => Some(ErrorCode::InvalidSession),
            Some(Err(e)) => Some(e),
            Some(Ok(bytes)) => {
                frame.data = bytes;
                frame.size = frame.data.len() as u8;
                burst.offset += u32::from(frame.size);
                None
            }
        };
        if let Some(error) = error {
            frame.opcode = Opcode::Nak as u8;
            frame.data = error.bytes();
            frame.size = frame.data.len() as u8;
            self.burst = None;
        }
        self.last_reply = None;
        self.remember(&frame);
        Some(frame)
    }

    /// Closes every session after [`SESSION_IDLE_S`] without activity by `now_s` [s] (PX4's
    /// rule; ArduPilot's keeps the file open until another session takes its place).
    pub fn expire(&mut self, now_s: f64) {
        let idle = now_s - self.last_activity_s > SESSION_IDLE_S;
        if self.rule == SessionRule::Px4 && self.sessions.iter().any(Option::is_some) && idle {
            *self = Self::new(self.rule);
        }
    }

    fn remember(&mut self, reply: &Payload) {
        if reply.data.len() <= 4 {
            self.last_reply = Some(reply.clone());
        }
    }

    /// The open session `id` (under ArduPilot's rule, once [`Self::gate`] passed the request:
    /// the open file).
    fn session(&self, id: u8) -> Result<&Session, ErrorCode> {
        self.sessions
            .get(self.rule.slot(id))
            .and_then(Option::as_ref)
            .ok_or(self.rule.not_open())
    }

    /// Closes every session.
    fn close_all(&mut self) {
        self.sessions = Default::default();
        self.current = None;
        self.burst = None;
    }

    /// ArduPilot's check of a request's session number against the open file's, before the
    /// request runs (`idle_s` [s] since the last activity): `Ok(Some)` answers it at once (a
    /// TerminateSession or ResetSessions of another session), `Ok(None)` lets it run (it names
    /// the open file, or none is open, or the open one was idle long enough to be closed).
    fn gate(&mut self, req: &Payload, idle_s: f64) -> Result<Option<Payload>, ErrorCode> {
        if self.current.is_none() || self.current == Some(req.session) {
            return Ok(None);
        }
        let ends = [Opcode::TerminateSession as u8, Opcode::ResetSessions as u8];
        if ends.contains(&req.opcode) {
            return Ok(Some(req.ack(Vec::new())));
        }
        if idle_s < ARDUPILOT_TAKEOVER_S {
            return Err(ErrorCode::InvalidSession);
        }
        self.close_all();
        Ok(None)
    }

    /// The slot an open takes: a free one (PX4), or the one file's when nothing is open
    /// (ArduPilot; an OpenFileRO replaces a file idle for `idle_s` > [`ARDUPILOT_TAKEOVER_S`]).
    fn free_slot(&mut self, read: bool, idle_s: f64) -> Result<usize, ErrorCode> {
        match self.rule {
            SessionRule::Px4 => self
                .sessions
                .iter()
                .position(Option::is_none)
                .ok_or(ErrorCode::NoSessionsAvailable),
            SessionRule::ArduPilot => {
                if self.current.is_some() && read && idle_s > ARDUPILOT_TAKEOVER_S {
                    self.close_all();
                }
                match self.current {
                    Some(_) => Err(ErrorCode::Fail),
                    None => Ok(0),
                }
            }
        }
    }

    /// Opens `path` in a free session: ACK with the session number and the file size.
    fn open(
        &mut self,
        fs: &mut Storage,
        req: &Payload,
        write: Option<bool>,
        idle_s: f64,
    ) -> Result<Option<Payload>, ErrorCode> {
        let id = self.free_slot(write.is_none(), idle_s)?;
        let raw = req.path().ok_or(ErrorCode::Fail)?;
        let session = match write {
            None if is_param_path(raw) => Session::Params(ParamFile::open_read(raw, &fs.params)?),
            Some(_) if is_param_path(raw) => Session::Params(ParamFile::Upload(Vec::new())),
            None => Session::File {
                path: super::vfs::normalize(raw)?,
                write: false,
            },
            Some(truncate) => Session::File {
                path: fs.vfs.open_write(raw, truncate)?,
                write: true,
            },
        };
        let size = u32::try_from(session.size(fs)?).unwrap_or(u32::MAX);
        self.sessions[id] = Some(session);
        let mut reply = req.ack(size.to_le_bytes().to_vec());
        match self.rule {
            SessionRule::Px4 => reply.session = id as u8,
            SessionRule::ArduPilot => self.current = Some(req.session),
        }
        Ok(Some(reply))
    }

    /// One request's reply, `None` for a burst, or why it failed; `idle_s` [s] since the last
    /// activity before it.
    fn work(&mut self, fs: &mut Storage, req: &Payload, idle_s: f64) -> Result<Option<Payload>, ErrorCode> {
        if self.rule == SessionRule::ArduPilot {
            if let Some(reply) = self.gate(req, idle_s)? {
                return Ok(Some(reply));
            }
        }
        let path = || req.path().ok_or(ErrorCode::Fail);
        let done = |_| Ok(Some(req.ack(Vec::new())));
        let Some(opcode) = Opcode::from_u8(req.opcode) else {
            return Err(ErrorCode::UnknownCommand);
        };
        match opcode {
            Opcode::None => done(()),
            Opcode::TerminateSession => {
                if self.rule == SessionRule::Px4 {
                    self.session(req.session)?;
                }
                let closed = self
                    .sessions
                    .get_mut(self.rule.slot(req.session))
                    .and_then(Option::take);
                self.current = None;
                if self.burst.as_ref().is_some_and(|b| b.session == req.session) {
                    self.burst = None;
                }
                if let Some(Session::Params(ParamFile::Upload(bytes))) = closed {
                    self.awaiting = Some(req.seq);
                    self.upload = Some(ParamUpload {
                        request: req.clone(),
                        parsed: parse_upload(&bytes),
                    });
                    return Ok(None);
                }
                done(())
            }
            Opcode::ResetSessions => {
                self.close_all();
                done(())
            }
            Opcode::ListDirectory => Ok(Some(req.ack(list_data(&fs.list(path()?)?, req.offset)?))),
            Opcode::OpenFileRO => self.open(fs, req, None, idle_s),
            Opcode::CreateFile => self.open(fs, req, Some(true), idle_s),
            Opcode::OpenFileWO => self.open(fs, req, Some(false), idle_s),
            Opcode::ReadFile => {
                let session = self.session(req.session)?;
                Ok(Some(req.ack(session.read(fs, req.offset, usize::from(req.size))?)))
            }
            Opcode::BurstReadFile => {
                self.session(req.session)?;
                self.burst = Some(Burst {
                    session: req.session,
                    offset: req.offset,
                    seq: req.seq.wrapping_add(1),
                });
                Ok(None)
            }
            Opcode::WriteFile => {
                self.session(req.session)?;
                let written = match self.sessions.get_mut(self.rule.slot(req.session)) {
                    Some(Some(Session::File { path, write: true })) => {
                        fs.vfs.write(path, req.offset as usize, &req.data)?
                    }
                    Some(Some(Session::Params(file))) => file.write(req.offset, &req.data)?,
                    _ => return Err(ErrorCode::FileProtected),
                };
                Ok(Some(req.ack((written as u32).to_le_bytes().to_vec())))
            }
            Opcode::RemoveFile => done(fs.vfs.remove_file(path()?)?),
            Opcode::CreateDirectory => done(fs.vfs.create_dir(path()?)?),
            Opcode::RemoveDirectory => done(fs.vfs.remove_dir(path()?)?),
            Opcode::TruncateFile => done(fs.vfs.truncate(path()?, req.offset as usize)?),
            Opcode::Rename => {
                let to = req.second_path().ok_or(ErrorCode::FailErrno(EINVAL))?;
                done(fs.vfs.rename(path()?, to)?)
            }
            Opcode::CalcFileCRC32 => Ok(Some(req.ack(fs.crc32(path()?)?.to_le_bytes().to_vec()))),
            Opcode::Ack | Opcode::Nak => Err(ErrorCode::UnknownCommand),
        }
    }
}

/// The ListDirectory data from entry `offset`: `D<name>` or `F<name>\t<size>`, each
/// NUL-terminated, as many as fit (PX4's layout); EOF at or past the last entry (PX4 answers
/// an empty directory at offset 0 with an empty ACK, which makes QGroundControl ask again
/// forever on a file system without `.` entries, so EOF it is).
fn list_data(entries: &[Entry], offset: u32) -> Result<Vec<u8>, ErrorCode> {
    let start = offset as usize;
    if start >= entries.len() {
        return Err(ErrorCode::Eof);
    }
    let mut data = Vec::new();
    for entry in &entries[start..] {
        let text = match entry {
            Entry::Dir(name) => format!("D{name}"),
            Entry::File(name, size) => format!("F{name}\t{size}"),
        };
        if data.len() + text.len() + 1 > DATA_MAX {
            if data.is_empty() {
                data.extend_from_slice(b"S\0");
            }
            break;
        }
        data.extend_from_slice(text.as_bytes());
        data.push(0);
    }
    Ok(data)
}

#[cfg(test)]
#[path = "server_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "server_ardupilot_tests.rs"]
mod ardupilot_tests;
