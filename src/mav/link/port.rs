//! One link of the vehicle (GCS or API): the remote that always gets telemetry, the peers
//! learned from trusted frames, the outgoing sequence number, the telemetry rates, the
//! heartbeat schedule, the duplicate-command cache, the mission upload in progress and the
//! ground station's liveness.

use std::collections::HashMap;
use std::hash::Hash;

use crate::commander::FlightMode;
use crate::mav::duplicates::DuplicateCache;
use crate::mav::mission_xfer::MissionTransfer;
use crate::mav::streams::{LinkKind, StreamTable};

/// Learned peers are forgotten after this much wall-clock silence [s].
pub const PEER_TIMEOUT_S: f64 = 10.0;

/// The state of one link.
#[derive(Debug)]
pub(super) struct Port<A> {
    pub kind: LinkKind,
    pub remote: A,
    /// Signature link id of outgoing frames.
    pub link_id: u8,
    /// Learned peers and the wall time they were last heard [s].
    peers: HashMap<A, f64>,
    sequence: u8,
    pub streams: StreamTable,
    pub duplicates: DuplicateCache,
    pub transfer: MissionTransfer<A>,
    /// Wall and simulated time of the next due heartbeat [s].
    pub next_heartbeat: (f64, f64),
    /// Armed state and mode of the last heartbeat.
    pub last_state: Option<(bool, FlightMode)>,
    /// Wall and simulated time of the last ground-station HEARTBEAT on this link [s].
    pub gcs_heard: Option<(f64, f64)>,
    /// The link-loss action ran for the current silence.
    pub link_lost: bool,
}

impl<A: Copy + Eq + Hash> Port<A> {
    pub fn new(kind: LinkKind, remote: A, link_id: u8) -> Self {
        Self {
            kind,
            remote,
            link_id,
            peers: HashMap::new(),
            sequence: 0,
            streams: StreamTable::new(kind),
            duplicates: DuplicateCache::default(),
            transfer: MissionTransfer::default(),
            next_heartbeat: (0.0, 0.0),
            last_state: None,
            gcs_heard: None,
            link_lost: false,
        }
    }

    /// The sequence number of the next outgoing frame.
    pub fn next_sequence(&mut self) -> u8 {
        let s = self.sequence;
        self.sequence = s.wrapping_add(1);
        s
    }

    /// `from` sent a trusted frame at `wall_s`.
    pub fn heard(&mut self, from: A, wall_s: f64) {
        self.peers.insert(from, wall_s);
    }

    /// The remote and every peer heard within [`PEER_TIMEOUT_S`] (older ones are forgotten).
    pub fn targets(&mut self, wall_s: f64) -> Vec<A> {
        self.peers.retain(|_, seen| wall_s - *seen < PEER_TIMEOUT_S);
        let mut out = vec![self.remote];
        out.extend(self.peers.keys().filter(|p| **p != self.remote));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peers_expire_and_the_remote_stays() {
        let mut port = Port::new(LinkKind::Gcs, 1u16, 0);
        port.heard(2, 0.0);
        port.heard(1, 0.0);
        let mut t = port.targets(5.0);
        t.sort_unstable();
        assert_eq!(t, vec![1, 2]);
        port.heard(3, 6.0);
        let mut t = port.targets(12.0);
        t.sort_unstable();
        assert_eq!(t, vec![1, 3], "peer 2 silent for 12 s is forgotten");
        assert_eq!(port.targets(20.0), vec![1]);
    }

    #[test]
    fn sequence_wraps() {
        let mut port = Port::new(LinkKind::Api, 0u8, 1);
        for k in 0..=255u8 {
            assert_eq!(port.next_sequence(), k);
        }
        assert_eq!(port.next_sequence(), 0);
    }
}
