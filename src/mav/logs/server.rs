//! The log protocol of one link, as PX4's MAVLink log handler serves it (one per MAVLink
//! instance): requests in, one LOG_ENTRY or LOG_DATA out at a time ([`LogServer::next_message`]),
//! the caller pacing them. Pure.
//!
//! - LOG_REQUEST_LIST takes a new snapshot of the store when `start` is 0 (or there is none):
//!   ids 0, 1, … number the logs oldest first, and later requests refer to that snapshot (a
//!   re-request of missing entries, `start` > 0, keeps it, so ids stay put). It lists the ids
//!   `start` … `end`, both clamped to the last id, each LOG_ENTRY with `num_logs`, `last_log_num`
//!   (the clamped `end`), the size in the snapshot and `time_utc` from the name. Without logs the
//!   answer is one LOG_ENTRY with `num_logs` 0 (and id, size and time 0).
//! - LOG_REQUEST_DATA (served only after a list) sends `count` bytes of log `id` from `ofs`, at
//!   most to the size in the snapshot (a log being written is served as listed), in LOG_DATA of
//!   90 bytes with their offsets; the last one may be shorter. A request at or past the end (or
//!   for 0 bytes) gets one LOG_DATA with `count` 0 at `ofs`: MAVLink's "end of log", which
//!   MAVProxy waits for when a size is a multiple of 90. A request for an id not in the snapshot
//!   gets nothing and stops the transfer in progress.
//! - A new request replaces the one in progress (listing or sending: one at a time, as PX4).
//! - LOG_REQUEST_END stops the transfer; the snapshot stays, so a client may list once and
//!   download several logs with an END after each (MAVProxy's `log download all`).
//! - LOG_ERASE is the caller's (it deletes the store's logs and [`forget`](LogServer::forget)s
//!   every link's snapshot); nothing answers it.

use mavlink::dialects::ardupilotmega::{MavMessage, LOG_DATA_DATA, LOG_ENTRY_DATA};

use super::store::{LogFile, LogStore};

/// Bytes of log data in one LOG_DATA.
pub const LOG_DATA_LEN: usize = 90;

/// A log protocol request, from its message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogRequest {
    /// LOG_REQUEST_LIST: entries `start` … `end` (0xFFFF: to the last).
    List {
        /// First id.
        start: u16,
        /// Last id.
        end: u16,
    },
    /// LOG_REQUEST_DATA: `count` bytes of log `id` from `offset`.
    Data {
        /// Log id (from LOG_ENTRY).
        id: u16,
        /// First byte [bytes].
        offset: u32,
        /// Bytes wanted.
        count: u32,
    },
    /// LOG_REQUEST_END: stop sending.
    End,
    /// LOG_ERASE: delete every log.
    Erase,
}

/// What the link is sending.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Job {
    Idle,
    /// The one LOG_ENTRY of an empty list.
    EmptyList,
    /// LOG_ENTRY for ids `next` … `last`.
    Listing {
        next: u16,
        last: u16,
    },
    /// LOG_DATA of log `id` from `offset`, `remaining` bytes more.
    Sending {
        id: u16,
        offset: u32,
        remaining: u32,
    },
}

/// The log protocol state of one link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogServer {
    /// The logs as listed by the last new LOG_REQUEST_LIST (`None`: not listed since start or
    /// erase).
    listed: Option<Vec<LogFile>>,
    job: Job,
}

impl Default for LogServer {
    fn default() -> Self {
        Self {
            listed: None,
            job: Job::Idle,
        }
    }
}

impl LogServer {
    /// `request` (not [`LogRequest::Erase`], which is the caller's) against `store`.
    pub fn handle(&mut self, store: &mut dyn LogStore, request: LogRequest) {
        match request {
            LogRequest::List { start, end } => self.list(store, start, end),
            LogRequest::Data { id, offset, count } => self.data(id, offset, count),
            LogRequest::End | LogRequest::Erase => self.job = Job::Idle,
        }
    }

    /// Drops the snapshot and the transfer (the logs were erased).
    pub fn forget(&mut self) {
        *self = Self::default();
    }

    /// True while messages remain to send.
    pub fn busy(&self) -> bool {
        self.job != Job::Idle
    }

    fn list(&mut self, store: &mut dyn LogStore, start: u16, end: u16) {
        if start == 0 || self.listed.is_none() {
            // A store that cannot be read lists as empty.
            let mut logs = store.list().unwrap_or_default();
            logs.truncate(usize::from(u16::MAX));
            self.listed = Some(logs);
        }
        let count = self.listed.as_ref().map_or(0, Vec::len) as u16;
        self.job = match count.checked_sub(1) {
            None => Job::EmptyList,
            Some(last_id) if start.min(last_id) <= end.min(last_id) => Job::Listing {
                next: start.min(last_id),
                last: end.min(last_id),
            },
            Some(_) => Job::Idle,
        };
    }

    fn data(&mut self, id: u16, offset: u32, count: u32) {
        let Some(log) = self.listed.as_ref().and_then(|l| l.get(usize::from(id))) else {
            self.job = Job::Idle;
            return;
        };
        let size = u32::try_from(log.size).unwrap_or(u32::MAX);
        self.job = Job::Sending {
            id,
            offset,
            remaining: size.saturating_sub(offset).min(count),
        };
    }

    /// The next LOG_ENTRY or LOG_DATA to send, `None` when there is none (or the store failed,
    /// which ends the transfer).
    pub fn next_message(&mut self, store: &mut dyn LogStore) -> Option<MavMessage> {
        let listed = self.listed.as_deref().unwrap_or_default();
        match self.job {
            Job::Idle => None,
            Job::EmptyList => {
                self.job = Job::Idle;
                Some(MavMessage::LOG_ENTRY(LOG_ENTRY_DATA::default()))
            }
            Job::Listing { next, last } => {
                let log = listed.get(usize::from(next)).copied()?;
                self.job = if next >= last {
                    Job::Idle
                } else {
                    Job::Listing { next: next + 1, last }
                };
                Some(MavMessage::LOG_ENTRY(LOG_ENTRY_DATA {
                    time_utc: log.utc_s,
                    size: u32::try_from(log.size).unwrap_or(u32::MAX),
                    id: next,
                    num_logs: listed.len() as u16,
                    last_log_num: last,
                }))
            }
            Job::Sending { id, offset, remaining } => {
                self.job = Job::Idle;
                let log = listed.get(usize::from(id))?;
                let mut data = [0u8; LOG_DATA_LEN];
                let want = (remaining as usize).min(LOG_DATA_LEN);
                let n = store.read_at(log.utc_s, u64::from(offset), &mut data[..want]).ok()?;
                if n == LOG_DATA_LEN && remaining as usize > n {
                    self.job = Job::Sending {
                        id,
                        offset: offset + n as u32,
                        remaining: remaining - n as u32,
                    };
                }
                Some(MavMessage::LOG_DATA(LOG_DATA_DATA {
                    ofs: offset,
                    id,
                    count: n as u8,
                    data,
                }))
            }
        }
    }
}

#[cfg(test)]
#[path = "server_tests.rs"]
mod tests;
