//! A minimal MAVLink ground station for the benchmarks: one UDP socket that sends commands with
//! the crate's codec and drains telemetry on a thread of its own (runtime layer).
//!
//! Commands are retransmitted as MAVSDK does ([`COMMAND_ATTEMPTS`] sends, each waited for in
//! turn), because an ACK can be lost: with a hundred vehicles streaming telemetry to this one
//! socket the kernel drops datagrams once its receive buffer is full. The socket asks for a
//! large buffer, and waiting decodes and throws away unrelated telemetry as fast as it comes.
//!
//! The client speaks raw MAVLink ([`MavMessage`], [`MavCmd`], [`MavResult`]): it is a ground
//! station, and the tests send and match arbitrary messages through it. What a ground station
//! sends and how an ACK is matched are [`crate::mav::gcs`]'s; this file only moves datagrams.

use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::mav::codec::{decode_datagram, encode_v2, Inbound};
use crate::mav::gcs::{ack_result, command_long, gcs_header, is_autopilot_heartbeat};
use crate::mav::{MavCmd, MavHeader, MavMessage, MavResult};

/// Sends of one command before [`BenchClient::command`] gives up: the first and two
/// retransmissions, with the same content (MAVSDK's default).
pub const COMMAND_ATTEMPTS: usize = 3;

/// Receive buffer asked for [bytes]; the kernel caps it at `net.core.rmem_max`.
const RECV_BUFFER_BYTES: usize = 4 << 20;

/// A GCS socket on an ephemeral loopback port.
pub struct BenchClient {
    socket: UdpSocket,
    sequence: u8,
}

impl BenchClient {
    /// Binds 127.0.0.1:0 with a large receive buffer (best effort).
    pub fn bind() -> std::io::Result<Self> {
        let addr = SocketAddr::from(([127, 0, 0, 1], 0));
        let socket = socket2::Socket::new(socket2::Domain::IPV4, socket2::Type::DGRAM, None)?;
        // Best effort: the kernel caps it at net.core.rmem_max.
        let _ = socket.set_recv_buffer_size(RECV_BUFFER_BYTES);
        socket.bind(&addr.into())?;
        let socket: UdpSocket = socket.into();
        socket.set_read_timeout(Some(Duration::from_millis(50)))?;
        Ok(Self { socket, sequence: 0 })
    }

    /// The bound address (where the vehicles send telemetry).
    pub fn local_addr(&self) -> std::io::Result<SocketAddr> {
        self.socket.local_addr()
    }

    /// `message` from the ground station (255, 190) to `to`, sequence numbers counting up.
    pub fn send(&mut self, message: &MavMessage, to: SocketAddr) {
        let mut buf = Vec::with_capacity(64);
        self.sequence = self.sequence.wrapping_add(1);
        encode_v2(gcs_header(self.sequence), message, &mut buf);
        self.send_bytes(&buf, to);
    }

    /// `bytes` as one datagram to `to` (send errors are ignored, as UDP loses datagrams anyway).
    pub fn send_bytes(&self, bytes: &[u8], to: SocketAddr) {
        let _ = self.socket.send_to(bytes, to);
    }

    /// The first received message that `pick` accepts within `timeout`, or `None`.
    pub fn wait<T>(&self, timeout: Duration, mut pick: impl FnMut(&MavHeader, &MavMessage) -> Option<T>) -> Option<T> {
        let start = Instant::now();
        let mut buf = [0u8; 2048];
        while start.elapsed() < timeout {
            let Ok((n, _)) = self.socket.recv_from(&mut buf) else {
                continue;
            };
            for frame in decode_datagram(&buf[..n]) {
                if let Inbound::Message { header, message, .. } = frame {
                    if let Some(t) = pick(&header, &message) {
                        return Some(t);
                    }
                }
            }
        }
        None
    }

    /// Throws away every datagram already queued (so the next one received is current).
    pub fn discard_queued(&self) {
        if self.socket.set_nonblocking(true).is_ok() {
            let mut buf = [0u8; 2048];
            while self.socket.recv_from(&mut buf).is_ok() {}
            let _ = self.socket.set_nonblocking(false);
        }
    }

    /// A GCS heartbeat to `to` (registers this socket as a peer).
    pub fn heartbeat(&mut self, to: SocketAddr) {
        self.send(&MavMessage::HEARTBEAT(Default::default()), to);
    }

    /// COMMAND_LONG `command` with `params` to system `sysid` (component 1) at `to`, sent up to
    /// [`COMMAND_ATTEMPTS`] times, each send waited for `timeout`; the ACK's result and the time
    /// from the first send, or `None` when no send was answered.
    pub fn command(
        &mut self,
        to: SocketAddr,
        sysid: u8,
        command: MavCmd,
        params: [f32; 7],
        timeout: Duration,
    ) -> Option<(MavResult, Duration)> {
        self.command_tries(to, (sysid, 1), command, params, timeout, COMMAND_ATTEMPTS)
            .0
    }

    /// COMMAND_LONG `command` with `params` to `target` (system, component) at `to`, sent up to
    /// `attempts` times with the same content until an ACK for it arrives, each send waited for
    /// `timeout`. Returns the ACK's result and the time from the first send (or `None`), and how
    /// many sends it took. An ACK counts when it names `command` and comes from the target system
    /// (any system for a broadcast, target system 0).
    pub fn command_tries(
        &mut self,
        to: SocketAddr,
        target: (u8, u8),
        command: MavCmd,
        params: [f32; 7],
        timeout: Duration,
        attempts: usize,
    ) -> (Option<(MavResult, Duration)>, usize) {
        let message = MavMessage::COMMAND_LONG(command_long(target, command, params));
        let first = Instant::now();
        let attempts = attempts.max(1);
        for sends in 1..=attempts {
            self.send(&message, to);
            let ack = self.wait(timeout, |header, message| {
                ack_result(header, message, command, target.0).map(|result| (result, first.elapsed()))
            });
            if ack.is_some() {
                return (ack, sends);
            }
        }
        (None, attempts)
    }

    /// Waits for the first HEARTBEAT from an autopilot; when it arrived.
    pub fn first_heartbeat(&self, timeout: Duration) -> Option<Instant> {
        self.wait(timeout, |header, message| {
            is_autopilot_heartbeat(header, message).then(Instant::now)
        })
    }

    /// Reads and counts every datagram on a thread until the returned drain is stopped.
    pub fn drain(self) -> std::io::Result<Drain> {
        let stop = Arc::new(AtomicBool::new(false));
        let received = Arc::new(AtomicU64::new(0));
        let (flag, count) = (stop.clone(), received.clone());
        let socket = self.socket;
        let thread = std::thread::Builder::new().name("bench-gcs".into()).spawn(move || {
            let mut buf = [0u8; 2048];
            while !flag.load(Ordering::Relaxed) {
                if socket.recv_from(&mut buf).is_ok() {
                    count.fetch_add(1, Ordering::Relaxed);
                }
            }
        })?;
        Ok(Drain {
            stop,
            received,
            thread: Some(thread),
        })
    }
}

/// A GCS that reads everything it is sent.
pub struct Drain {
    stop: Arc<AtomicBool>,
    received: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
}

impl Drain {
    /// Datagrams received so far.
    pub fn received(&self) -> u64 {
        self.received.load(Ordering::Relaxed)
    }
}

impl Drop for Drain {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
