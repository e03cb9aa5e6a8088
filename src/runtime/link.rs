//! The link task of one vehicle (GCS and API): it only reads, feeds, drains and sleeps. Inputs
//! go into the vehicle's [`LinkMachine`] with the latest state and that state's clock; what the
//! machine decided leaves in its order (datagrams, requests to the tick thread, keys, tlog).
//! With `--link-loss`/`-delay`/`-duplicate` datagrams pass the vehicle's [`Impairments`] first.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::net::UdpSocket;
use tokio::sync::{mpsc, watch};

use crate::commander::Event;
use crate::mav::link::{LinkMachine, Now, Token, VehicleReply};
use crate::mav::streams::LinkKind;
use crate::telemetry::Snapshot;

use super::flight_log::LogSender;
use super::impairment::{Impairments, LinkCounts};
use super::scheduler::{ReplyTo, VehicleCommand};
use super::signing_store::SigningStore;
use super::sockets::{LinkSockets, MAX_DATAGRAM_BYTES};

/// A datagram of a link: the link, the client's address, the bytes.
pub type Datagram = (LinkKind, SocketAddr, Vec<u8>);

/// Datagrams read in a row once one has arrived, before the task looks at its other inputs.
const RECV_BATCH: usize = 256;

/// What the signing keeper reads of one vehicle: its signing timestamp and dropped frames.
#[derive(Debug, Default)]
pub struct SigningStatus {
    /// Latest signing timestamp [10 µs since 2015].
    pub timestamp: AtomicU64,
    /// Frames dropped by signing so far.
    pub dropped: AtomicU64,
}

/// Everything the link task of one vehicle talks to.
pub struct LinkIo {
    /// The GCS and API sockets.
    pub sockets: LinkSockets,
    /// Wall time zero of the machine's clock.
    pub start: Instant,
    /// Requests to the tick thread.
    pub vehicle: mpsc::Sender<VehicleCommand>,
    /// Where the tick thread answers (kept to hand out with each request).
    pub replies_to: mpsc::UnboundedSender<(Token, VehicleReply)>,
    /// The tick thread's answers.
    pub replies: mpsc::UnboundedReceiver<(Token, VehicleReply)>,
    /// Latest vehicle state (the machine keeps the `Arc`, shared, not a copy).
    pub snapshot: watch::Receiver<Arc<Snapshot>>,
    /// Commander events.
    pub events: mpsc::Receiver<Event>,
    /// The log writer's announcements ("[logger] ./log/…").
    pub notices: mpsc::Receiver<String>,
    /// Becomes true at shutdown.
    pub shutdown: watch::Receiver<bool>,
    /// The tlog of `--log DIR`, when there is one.
    pub log: Option<LogSender>,
    /// The `--signing-key` file, when there is one.
    pub store: Option<Arc<SigningStore>>,
    /// Published for the signing keeper.
    pub signing: Arc<SigningStatus>,
    /// The impaired links (`--link-loss` …), when there are some.
    pub impair: Option<Impairments<Datagram>>,
}

impl LinkIo {
    /// Hands the vehicle's latest state to `machine`; returns the clocks of a decision on it.
    fn sync(&self, machine: &mut LinkMachine<SocketAddr>) -> Now {
        machine.handle_state(Arc::clone(&self.snapshot.borrow()));
        self.now(machine)
    }

    /// The clocks of `machine` now: wall time since `start`, and the simulated time of the state
    /// it holds (never a newer one it has not been given).
    fn now(&self, machine: &LinkMachine<SocketAddr>) -> Now {
        Now {
            wall_s: self.start.elapsed().as_secs_f64(),
            sim_s: machine.state_time_s(),
        }
    }
}

/// Serves the links of one vehicle until shutdown; returns what the impairment did.
pub async fn serve(mut machine: LinkMachine<SocketAddr>, mut io: LinkIo) -> Vec<LinkCounts> {
    let mut impair = io.impair.take();
    // Nothing is said before the vehicle's first tick: its state is what telemetry reports.
    tokio::select! {
        _ = io.shutdown.changed() => return Vec::new(),
        _ = io.snapshot.changed() => {}
    }
    let (mut gcs_buf, mut api_buf) = (vec![0u8; MAX_DATAGRAM_BYTES], vec![0u8; MAX_DATAGRAM_BYTES]);
    loop {
        let wake_s = impair
            .as_ref()
            .and_then(Impairments::next_due_s)
            .unwrap_or(f64::INFINITY);
        let deadline = io.start + Duration::from_secs_f64(machine.poll_timeout().min(wake_s).max(0.0));
        let [(gcs_kind, gcs), (api_kind, api)] = &io.sockets.0;
        tokio::select! {
            _ = io.shutdown.changed() => break,
            Ok((n, from)) = gcs.recv_from(&mut gcs_buf) => {
                io.sync(&mut machine);
                read_burst(&mut machine, &io, &mut impair, (*gcs_kind, gcs), &mut gcs_buf, (n, from));
            }
            Ok((n, from)) = api.recv_from(&mut api_buf) => {
                io.sync(&mut machine);
                read_burst(&mut machine, &io, &mut impair, (*api_kind, api), &mut api_buf, (n, from));
            }
            Some((token, reply)) = io.replies.recv() => {
                let now = io.sync(&mut machine);
                machine.handle_reply(now, token, reply);
            }
            Some(event) = io.events.recv() => {
                let now = io.sync(&mut machine);
                machine.handle_event(now, event);
            }
            Some(text) = io.notices.recv() => machine.handle_notice(io.now(&machine), &text),
            _ = tokio::time::sleep_until(deadline.into()) => {}
        }
        // Duties are checked against the wall clock after every input, not only when the
        // timer fires: under a flood the task never parks, and tokio's timer then advances late.
        let mut now = io.now(&machine);
        if now.wall_s >= machine.poll_timeout() {
            now = io.sync(&mut machine);
            machine.handle_timeout(now);
        }
        if let Some(imp) = &mut impair {
            let (to_vehicle, from_vehicle) = imp.due(now.wall_s);
            for (link, from, bytes) in to_vehicle {
                machine.handle_datagram(now, link, from, &bytes);
            }
            for (link, to, bytes) in from_vehicle {
                send(&io, link, to, &bytes).await;
            }
        }
        drain(&mut machine, &io, &mut impair).await;
        // After every send, so the timestamp persisted at shutdown is never behind a frame sent.
        io.signing
            .timestamp
            .store(machine.signing_timestamp(), Ordering::Relaxed);
        io.signing.dropped.store(machine.signing_dropped(), Ordering::Relaxed);
    }
    impair.map(|imp| imp.counts()).unwrap_or_default()
}

/// Feeds the datagram that woke the task and, under a burst, what is already queued on the
/// same socket (bounded, so that telemetry stays on time); a flood then costs the decoding only.
fn read_burst(
    machine: &mut LinkMachine<SocketAddr>,
    io: &LinkIo,
    impair: &mut Option<Impairments<Datagram>>,
    (link, socket): (LinkKind, &UdpSocket),
    buf: &mut [u8],
    first: (usize, SocketAddr),
) {
    let mut feed = |n: usize, from: SocketAddr, buf: &[u8]| {
        let now = io.now(machine);
        match impair {
            None => machine.handle_datagram(now, link, from, &buf[..n]),
            Some(imp) => {
                for (link, from, bytes) in imp.offer(now.wall_s, link, true, (link, from, buf[..n].to_vec())) {
                    machine.handle_datagram(now, link, from, &bytes);
                }
            }
        }
    };
    feed(first.0, first.1, buf);
    for _ in 0..RECV_BATCH {
        let Ok((n, from)) = socket.try_recv_from(buf) else {
            break;
        };
        feed(n, from, buf);
    }
}

/// Sends `bytes` to `to` on `link` (a failure is only traced: UDP may lose it anyway).
async fn send(io: &LinkIo, link: LinkKind, to: SocketAddr, bytes: &[u8]) {
    if let Err(e) = io.sockets.socket(link).send_to(bytes, to).await {
        tracing::debug!("send to {to}: {e}");
    }
}

/// Carries out everything the machine decided, in order, until it has nothing more.
async fn drain(machine: &mut LinkMachine<SocketAddr>, io: &LinkIo, impair: &mut Option<Impairments<Datagram>>) {
    loop {
        if let Some(log) = &io.log {
            std::iter::from_fn(|| machine.poll_received()).for_each(|frame| log.frame(&frame));
            std::iter::from_fn(|| machine.poll_said()).for_each(|s| log.logged_string(s.severity, s.t_s, &s.text));
        }
        while let Some(t) = machine.poll_transmit() {
            if let Some(log) = &io.log {
                log.frame(&t.bytes);
            }
            match impair {
                None => send(io, t.link, t.to, &t.bytes).await,
                Some(imp) => {
                    for (link, to, bytes) in imp.offer(io.now(machine).wall_s, t.link, false, (t.link, t.to, t.bytes)) {
                        send(io, link, to, &bytes).await;
                    }
                }
            }
        }
        let mut more = false;
        while let Some(ask) = machine.poll_vehicle() {
            let token = ask.token;
            let reply = token.map(|token| ReplyTo {
                token,
                to: io.replies_to.clone(),
            });
            if io
                .vehicle
                .try_send(VehicleCommand {
                    request: ask.request,
                    reply,
                })
                .is_err()
            {
                // A full inbox: a command is answered TEMPORARILY_REJECTED at once; a setpoint
                // is dropped, the next one replaces it.
                if let Some(token) = token {
                    machine.handle_reply(io.now(machine), token, VehicleReply::Busy);
                    more = true;
                }
            }
        }
        while let Some(key) = machine.poll_store() {
            let result = match &io.store {
                Some(store) => store
                    .save_key(key.key.as_ref())
                    .and_then(|()| store.save_timestamp(key.timestamp))
                    .map_err(|e| {
                        tracing::warn!("signing key file: {e}");
                        e.to_string()
                    }),
                None => Err("no key file".into()),
            };
            machine.handle_stored(io.now(machine), result);
            more = true;
        }
        if !more {
            break;
        }
    }
}
