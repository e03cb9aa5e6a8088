//! The log protocol on every link: one [`LogServer`] per link (PX4 runs one per MAVLink
//! instance) over the vehicle's log store, its LOG_ENTRY and LOG_DATA sent to the client that
//! asked (they carry no target), paced at one message per [`LOG_MESSAGE_PERIOD_S`] of wall time:
//! 4 000 messages/s, 360 kB/s of log data, which MAVProxy reads without losing one (a 5 MB log,
//! two downloads at once on a 2-core machine; at 10 000/s it lost a fifth, and each of its gap
//! requests replaces the previous one, as on PX4). PX4 sends as fast as its link's data rate
//! allows. A late wake-up sends at most [`LOG_MESSAGES_AT_ONCE`] and does not catch up beyond. LOG_ERASE deletes the store's logs (the store keeps the one being written) and
//! every link's list.
//!
//! [`LogService`] owns the log server of each link; the logs are read from the store it is
//! handed.

use mavlink::dialects::ardupilotmega::MavMessage;

use super::effects::Effect;
use super::LinkKind;
use crate::mav::logs::{LogRequest, LogServer, LogStore};

/// Wall time between two log messages to one client [s].
pub const LOG_MESSAGE_PERIOD_S: f64 = 2.5e-4;
/// Most log messages sent to one client in one wake-up.
pub const LOG_MESSAGES_AT_ONCE: usize = 50;

/// The log server of one link and where its messages go.
#[derive(Debug)]
struct LogLink<A> {
    link: LinkKind,
    server: LogServer,
    /// The client of the request in progress.
    client: Option<A>,
    /// Wall time the next message is due [s].
    next_s: f64,
}

impl<A> LogLink<A> {
    /// Wall time the next message is due [s], while one remains.
    fn due_s(&self) -> Option<f64> {
        self.server.busy().then_some(self.next_s)
    }
}

/// The log protocol of every link.
#[derive(Debug)]
pub(super) struct LogService<A> {
    links: Vec<LogLink<A>>,
}

impl<A: Copy> LogService<A> {
    /// An idle log server on each of `links`.
    pub fn new(links: &[LinkKind]) -> Self {
        let links = links
            .iter()
            .map(|link| LogLink {
                link: *link,
                server: LogServer::default(),
                client: None,
                next_s: 0.0,
            })
            .collect();
        Self { links }
    }

    /// Wall time the next log message of any link is due [s].
    pub fn next_due_s(&self) -> Option<f64> {
        self.links.iter().filter_map(LogLink::due_s).reduce(f64::min)
    }

    /// One log protocol request from `from` on `link` at wall time `wall_s` [s] about the logs
    /// of `store`; the first message goes out at once (with what else is due).
    pub fn request(
        &mut self,
        wall_s: f64,
        link: LinkKind,
        from: A,
        request: LogRequest,
        store: &mut dyn LogStore,
    ) -> Vec<Effect<A>> {
        if request == LogRequest::Erase {
            for log_link in &mut self.links {
                log_link.server.forget();
            }
            // PX4 answers nothing, whatever happened; a file that could not go stays listed.
            let _ = store.erase();
            return Vec::new();
        }
        let Some(log_link) = self.links.iter_mut().find(|l| l.link == link) else {
            return Vec::new();
        };
        log_link.server.handle(store, request);
        log_link.client = Some(from);
        log_link.next_s = wall_s;
        self.stream(wall_s, store)
    }

    /// The log messages of `store` due by wall time `wall_s` [s].
    pub fn stream(&mut self, wall_s: f64, store: &mut dyn LogStore) -> Vec<Effect<A>> {
        let mut out = Vec::new();
        for log_link in &mut self.links {
            let mut messages: Vec<MavMessage> = Vec::new();
            while log_link.server.busy() && log_link.next_s <= wall_s && messages.len() < LOG_MESSAGES_AT_ONCE {
                match log_link.server.next_message(store) {
                    Some(message) => messages.push(message),
                    None => break,
                }
                log_link.next_s += LOG_MESSAGE_PERIOD_S;
            }
            if log_link.next_s < wall_s {
                log_link.next_s = wall_s + LOG_MESSAGE_PERIOD_S;
            }
            if let Some(to) = log_link.client {
                out.extend(messages.into_iter().map(|m| Effect::send(log_link.link, to, m)));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::link::effects::testing::sent;
    use crate::mav::logs::MemLogStore;

    fn entries(out: &[Effect<u16>]) -> Vec<(LinkKind, u16, u16)> {
        sent(out)
            .into_iter()
            .filter_map(|(link, to, m)| match m {
                MavMessage::LOG_ENTRY(e) => Some((link, to, e.num_logs)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_list_goes_to_its_client_paced_and_erase_forgets_the_logs() {
        let mut store = MemLogStore::from_iter([(10, vec![1]), (20, vec![2]), (30, vec![3])]);
        let mut l = LogService::new(&[LinkKind::Gcs, LinkKind::Api]);
        let all = LogRequest::List { start: 0, end: 0xFFFF };
        let first = l.request(1.0, LinkKind::Api, 9u16, all, &mut store);
        assert_eq!(entries(&first), vec![(LinkKind::Api, 9, 3)], "the first at once");
        assert_eq!(l.next_due_s(), Some(1.0 + LOG_MESSAGE_PERIOD_S));
        assert!(l.stream(1.0, &mut store).is_empty());
        let rest = l.stream(1.1, &mut store);
        assert_eq!(entries(&rest).len(), 2);
        assert_eq!(l.next_due_s(), None);
        assert!(l
            .request(2.0, LinkKind::Gcs, 9, LogRequest::Erase, &mut store)
            .is_empty());
        let after = l.request(3.0, LinkKind::Gcs, 9, all, &mut store);
        assert!(entries(&after).iter().all(|e| e.2 == 0), "{after:?}");
    }
}
