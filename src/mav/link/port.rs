//! One link of the vehicle (GCS or API): the remote that always gets telemetry, the peers
//! learned from trusted frames, the outgoing sequence number, the telemetry rates, the
//! heartbeat schedule and the ground station's liveness (the per-link state of the protocols
//! is owned by their services: duplicate commands, mission uploads, FTP, logs).

use std::collections::HashMap;
use std::hash::Hash;

use crate::commander::FlightMode;
use crate::mav::identity::Personality;
use crate::mav::streams::{LinkKind, StreamTable};

/// Learned peers are forgotten after this much wall-clock silence [s].
pub const PEER_TIMEOUT_S: f64 = 10.0;
/// Most peers a link learns besides its remote (each one gets the link's telemetry).
pub const MAX_PEERS: usize = 8;
/// A full table makes room for a new peer by forgetting the one silent longest, if it has been
/// silent this long [s]; a peer that keeps talking (a ground station's 1 Hz HEARTBEAT) is never
/// pushed out by addresses that write once.
pub const PEER_EVICT_S: f64 = 2.0;

/// What a link machine keeps for its clients, all of it bounded ([`MAX_PEERS`] per link).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeldForClients {
    /// Learned peers, over every link (the configured remotes not counted).
    pub peers: usize,
    /// Open MAVLink shells.
    pub shells: usize,
    /// Parameter lists being sent.
    pub param_lists: usize,
}

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
    /// Wall and simulated time of the next due heartbeat [s].
    pub next_heartbeat: (f64, f64),
    /// Armed state, mode and Copter mode number (ArduCopter personality) of the last heartbeat.
    pub last_state: Option<(bool, FlightMode, u8)>,
    /// Wall and simulated time of the last ground-station HEARTBEAT on this link [s].
    pub gcs_heard: Option<(f64, f64)>,
    /// The link-loss action ran for the current silence.
    pub link_lost: bool,
}

impl<A: Copy + Eq + Hash> Port<A> {
    /// A `kind` link to `remote` with signature link id `link_id`, its telemetry rates those of
    /// a vehicle presenting itself as `personality`.
    pub fn new(kind: LinkKind, remote: A, link_id: u8, personality: Personality) -> Self {
        Self {
            kind,
            remote,
            link_id,
            peers: HashMap::new(),
            sequence: 0,
            streams: StreamTable::new(kind, personality),
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

    /// `from` sent a trusted frame at `wall_s`: it becomes (or stays) a peer when there is room
    /// ([`MAX_PEERS`], [`PEER_EVICT_S`]); returns the peer forgotten to make room.
    pub fn heard(&mut self, from: A, wall_s: f64) -> Option<A> {
        if from == self.remote {
            return None;
        }
        if let Some(seen) = self.peers.get_mut(&from) {
            *seen = wall_s;
            return None;
        }
        let mut evicted = None;
        if self.peers.len() >= MAX_PEERS {
            let (stalest, seen) = self
                .peers
                .iter()
                .min_by(|a, b| a.1.total_cmp(b.1))
                .map(|(p, t)| (*p, *t))?;
            if wall_s - seen < PEER_EVICT_S {
                return None;
            }
            self.peers.remove(&stalest);
            evicted = Some(stalest);
        }
        self.peers.insert(from, wall_s);
        evicted
    }

    /// Forgets the peers silent for [`PEER_TIMEOUT_S`] at `wall_s`; returns them.
    pub fn expire(&mut self, wall_s: f64) -> Vec<A> {
        let gone: Vec<A> = self
            .peers
            .iter()
            .filter(|(_, seen)| wall_s - **seen >= PEER_TIMEOUT_S)
            .map(|(p, _)| *p)
            .collect();
        for p in &gone {
            self.peers.remove(p);
        }
        gone
    }

    /// Learned peers (the remote not counted).
    pub fn peer_count(&self) -> usize {
        self.peers.len()
    }

    /// The remote and every peer.
    pub fn targets(&self) -> Vec<A> {
        let mut out = vec![self.remote];
        out.extend(self.peers.keys());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sorted(mut v: Vec<u16>) -> Vec<u16> {
        v.sort_unstable();
        v
    }

    #[test]
    fn peers_expire_and_the_remote_stays() {
        let mut port = Port::new(LinkKind::Gcs, 1u16, 0, Personality::Px4);
        port.heard(2, 0.0);
        port.heard(1, 0.0);
        assert!(port.expire(5.0).is_empty());
        assert_eq!(sorted(port.targets()), vec![1, 2]);
        port.heard(3, 6.0);
        assert_eq!(port.expire(12.0), vec![2], "peer 2 silent for 12 s is forgotten");
        assert_eq!(sorted(port.targets()), vec![1, 3]);
        assert_eq!(port.expire(20.0), vec![3]);
        assert_eq!(port.targets(), vec![1]);
    }

    #[test]
    fn the_peer_table_is_bounded_and_keeps_peers_that_keep_talking() {
        let mut port = Port::new(LinkKind::Gcs, 0u16, 0, Personality::Px4);
        // A ground station with a 1 Hz heartbeat, then 5 000 addresses writing once each.
        port.heard(1, 0.0);
        let mut evicted = Vec::new();
        for k in 0..5_000u16 {
            let t = f64::from(k) * 1e-3;
            if f64::from(k) % 1000.0 == 0.0 {
                port.heard(1, t);
            }
            evicted.extend(port.heard(100 + k, t));
            assert!(port.targets().len() <= 1 + MAX_PEERS);
        }
        assert!(port.targets().contains(&1), "the talking peer stays");
        assert!(!evicted.contains(&1));
        // Once-writers silent for PEER_EVICT_S made room for later ones.
        assert!(!evicted.is_empty());
        assert_eq!(port.targets().len(), 1 + MAX_PEERS);
    }

    #[test]
    fn sequence_wraps() {
        let mut port = Port::new(LinkKind::Api, 0u8, 1, Personality::Px4);
        for k in 0..=255u8 {
            assert_eq!(port.next_sequence(), k);
        }
        assert_eq!(port.next_sequence(), 0);
    }
}
