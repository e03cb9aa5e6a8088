//! The log protocol on every link: one [`LogServer`] per link (PX4 runs one per MAVLink
//! instance) over the vehicle's log store, its LOG_ENTRY and LOG_DATA sent to the client that
//! asked (they carry no target), paced at one message per [`LOG_MESSAGE_PERIOD_S`] of wall time:
//! 4 000 messages/s, 360 kB/s of log data, which MAVProxy reads without losing one (a 5 MB log,
//! two downloads at once on a 2-core machine; at 10 000/s it lost a fifth, and each of its gap
//! requests replaces the previous one, as on PX4). PX4 sends as fast as its link's data rate
//! allows. A late wake-up sends at most [`LOG_MESSAGES_AT_ONCE`] and does not catch up beyond. LOG_ERASE deletes the store's logs (the store keeps the one being written) and
//! every link's list.

use std::hash::Hash;

use super::{LinkKind, LinkMachine, Now};
use crate::mav::logs::{LogRequest, LogServer};

/// Wall time between two log messages to one client [s].
pub const LOG_MESSAGE_PERIOD_S: f64 = 2.5e-4;
/// Most log messages sent to one client in one wake-up.
pub const LOG_MESSAGES_AT_ONCE: usize = 50;

/// The log server of one link and where its messages go.
#[derive(Debug)]
pub(super) struct LogLink<A> {
    link: LinkKind,
    server: LogServer,
    /// The client of the request in progress.
    client: Option<A>,
    /// Wall time the next message is due [s].
    next_s: f64,
}

impl<A> LogLink<A> {
    /// An idle log server on `link`.
    pub fn new(link: LinkKind) -> Self {
        Self {
            link,
            server: LogServer::default(),
            client: None,
            next_s: 0.0,
        }
    }

    /// Wall time the next message is due [s], while one remains.
    pub fn due_s(&self) -> Option<f64> {
        self.server.busy().then_some(self.next_s)
    }
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// One log protocol request from `from` on `link`; its first message goes out at once.
    pub(super) fn log_request(&mut self, now: Now, link: LinkKind, from: A, request: LogRequest) {
        let files = &mut self.files;
        if request == LogRequest::Erase {
            for log_link in &mut files.logs {
                log_link.server.forget();
            }
            // PX4 answers nothing, whatever happened; a file that could not go stays listed.
            let _ = files.fs.logs.erase();
            return;
        }
        let Some(log_link) = files.logs.iter_mut().find(|l| l.link == link) else {
            return;
        };
        log_link.server.handle(files.fs.logs.as_mut(), request);
        log_link.client = Some(from);
        log_link.next_s = now.wall_s;
        self.stream_logs(now);
    }

    /// The log messages due by `now`.
    pub(super) fn stream_logs(&mut self, now: Now) {
        for k in 0..self.files.logs.len() {
            let mut messages = Vec::new();
            let files = &mut self.files;
            let log_link = &mut files.logs[k];
            while log_link.server.busy() && log_link.next_s <= now.wall_s && messages.len() < LOG_MESSAGES_AT_ONCE {
                match log_link.server.next_message(files.fs.logs.as_mut()) {
                    Some(message) => messages.push(message),
                    None => break,
                }
                log_link.next_s += LOG_MESSAGE_PERIOD_S;
            }
            if log_link.next_s < now.wall_s {
                log_link.next_s = now.wall_s + LOG_MESSAGE_PERIOD_S;
            }
            let (link, client) = (log_link.link, log_link.client);
            if let Some(to) = client {
                for message in &messages {
                    self.send(now, link, to, message);
                }
            }
        }
    }
}
