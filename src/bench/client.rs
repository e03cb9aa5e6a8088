//! A minimal MAVLink ground station for the benchmarks: one UDP socket that sends commands with
//! the crate's codec and drains telemetry on a thread of its own (runtime layer).

use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::mav::codec::{decode_datagram, encode_v2, Inbound};
use crate::mav::{MavCmd, MavHeader, MavMessage, MavResult, COMMAND_LONG_DATA, HEARTBEAT_DATA};

/// A GCS socket on an ephemeral loopback port.
pub struct BenchClient {
    socket: UdpSocket,
    sequence: u8,
}

impl BenchClient {
    /// Binds 127.0.0.1:0.
    pub fn bind() -> std::io::Result<Self> {
        let socket = UdpSocket::bind("127.0.0.1:0")?;
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
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: self.sequence,
        };
        encode_v2(header, message, &mut buf);
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
        self.send(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), to);
    }

    /// COMMAND_LONG `command` with `params` to system `sysid` at `to`; the ACK's result and the
    /// round-trip time, or `None` after `timeout`.
    pub fn command(
        &mut self,
        to: SocketAddr,
        sysid: u8,
        command: MavCmd,
        params: [f32; 7],
        timeout: Duration,
    ) -> Option<(MavResult, Duration)> {
        let [param1, param2, param3, param4, param5, param6, param7] = params;
        let sent = Instant::now();
        self.send(
            &MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
                param1,
                param2,
                param3,
                param4,
                param5,
                param6,
                param7,
                command,
                target_system: sysid,
                target_component: 1,
                confirmation: 0,
            }),
            to,
        );
        self.wait(timeout, |header, message| match message {
            MavMessage::COMMAND_ACK(ack) if ack.command == command && header.system_id == u32::from(sysid) => {
                Some((ack.result, sent.elapsed()))
            }
            _ => None,
        })
    }

    /// Waits for the first HEARTBEAT from an autopilot; when it arrived.
    pub fn first_heartbeat(&self, timeout: Duration) -> Option<Instant> {
        self.wait(timeout, |header, message| {
            (header.component_id == 1 && matches!(message, MavMessage::HEARTBEAT(_))).then(Instant::now)
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
