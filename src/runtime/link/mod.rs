//! One MAVLink UDP link (GCS or API): its own socket, the peers learned from valid frames, the
//! periodic telemetry, and the command path (decode → vehicle → COMMAND_ACK to the sender).
//! Runtime layer: wall-clock pacing of streams, sockets; the message maths is in `mav`.
//!
//! # Layout
//! - `mod.rs`: the socket loop, peers, heartbeat, link loss, signing, message dispatch.
//! - `commands.rs`: COMMAND_LONG/INT to the vehicle and their ACKs, PARAM_SET.
//! - `mission.rs`: the mission protocol against the vehicle's stored mission.

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::net::UdpSocket;
use tokio::sync::{broadcast, mpsc, oneshot, watch};

use crate::commander::{Event, FlightMode, Outcome, Request};
use crate::mav::codec::{decode_datagram_checked, encode_v2, frame_message, unsupported_command_ack, Inbound};
use crate::mav::duplicates::{CommandKey, DuplicateCache, Seen};
use crate::mav::ingest::{ingest, Action, MissionStep};
use crate::mav::mission_items::parse_mission;
use crate::mav::mission_xfer::{download_count, download_item, Completed, Ids, MissionTransfer};
use crate::mav::params::{param_error_unknown, param_value};
use crate::mav::services::autopilot_version;
use crate::mav::signing::{SigningKey, Verdict};
use crate::mav::streams::{LinkKind, StreamTable};
use crate::mav::telemetry::{message, mission_current, status_text};
use crate::mav::translate::{command_ack, heartbeat, result_of, CommandDecision, Identity, OneShot};
use crate::mav::{
    MAVLinkV2MessageRaw, MavCmd, MavHeader, MavMessage, MavMissionResult, MavResult, MavSeverity, COMMAND_LONG_DATA,
    MESSAGE_INTERVAL_DATA, MISSION_ITEM_INT_DATA, MISSION_ITEM_REACHED_DATA,
};
use crate::navigation::Mission;
use crate::params::{ParamError, ParamTable};
use crate::telemetry::Snapshot;

use super::flight_log::LogSender;
use super::scheduler::VehicleCommand;
use super::signing_store::{signing_now, SharedSigning, SigningStore};

mod commands;
mod mission;

use commands::{handle_command, set_param};
use mission::handle_mission;

/// Learned peers are forgotten after this much silence (mavlink.md §11.1).
const PEER_TIMEOUT: Duration = Duration::from_secs(10);
/// How often the link looks at what is due.
const POLL: Duration = Duration::from_millis(5);
/// The largest datagram read whole [bytes]: 29 MAVLink 2 frames of the largest size (280 bytes,
/// signed). The kernel cuts longer datagrams to this (PX4 reads 1,600 bytes), so a flood of
/// 64 KiB garbage costs no more to skip than a flood of small ones.
const MAX_DATAGRAM_BYTES: usize = 8_192;
/// Datagrams read in a row once one has arrived, before the link looks at its other duties.
const RECV_BATCH: usize = 256;
/// HEARTBEAT period (wall clock).
const HEARTBEAT_PERIOD: Duration = Duration::from_secs(1);

/// What a link shares with the rest of the process.
pub struct LinkContext {
    /// Our identity.
    pub identity: Identity,
    /// Requests to the vehicle.
    pub inbox: mpsc::Sender<VehicleCommand>,
    /// Latest vehicle state.
    pub snapshot: watch::Receiver<Snapshot>,
    /// Current parameter table.
    pub params: watch::Receiver<Arc<ParamTable>>,
    /// Announcements for every peer (STATUSTEXT).
    pub announcements: broadcast::Receiver<Event>,
    /// Becomes true at shutdown.
    pub shutdown: watch::Receiver<bool>,
    /// The stored mission as uploaded (for downloads), shared by the links; replaced only when
    /// an upload is accepted.
    pub mission_store: Arc<Mutex<Vec<MISSION_ITEM_INT_DATA>>>,
    /// The tlog of `--log DIR`, when logging.
    pub log: Option<LogSender>,
    /// GCS or API defaults for the stream rates.
    pub kind: LinkKind,
    /// The vehicle's signing state (shared by its links).
    pub signing: SharedSigning,
    /// Where SETUP_SIGNING stores the key (`--signing-key FILE`); `None`: memory only.
    pub signing_store: Option<Arc<SigningStore>>,
}

impl LinkContext {
    /// The same vehicle's context for a link of `kind`, with its own announcement receiver.
    pub fn with_kind(&self, kind: LinkKind) -> Self {
        Self {
            identity: self.identity,
            inbox: self.inbox.clone(),
            snapshot: self.snapshot.clone(),
            params: self.params.clone(),
            announcements: self.announcements.resubscribe(),
            shutdown: self.shutdown.clone(),
            mission_store: self.mission_store.clone(),
            log: self.log.clone(),
            kind,
            signing: self.signing.clone(),
            signing_store: self.signing_store.clone(),
        }
    }
}

/// Sends frames to peers with a per-link sequence counter; remembers recent command results.
struct Sender {
    socket: Arc<UdpSocket>,
    identity: Identity,
    sequence: AtomicU8,
    /// Shared by the receive loop and the ACK tasks; held for a hash-map update only.
    duplicates: Mutex<DuplicateCache>,
    /// The link's telemetry targets as of the last poll (for PARAM_VALUE echoes).
    targets: Mutex<Vec<SocketAddr>>,
    start: Instant,
    log: Option<LogSender>,
    /// Stream rates; changed by commands handled in spawned tasks, read by the loop.
    streams: Mutex<StreamTable>,
    /// Last HEARTBEAT from a ground station (type GCS) on this link: wall time and simulated
    /// time [s].
    last_gcs_heartbeat: Mutex<Option<(Instant, f64)>>,
    /// The vehicle's signing state: outgoing frames are sealed with it.
    signing: SharedSigning,
    /// Signature link id of this link's outgoing frames (GCS 0, API 1).
    link_id: u8,
}

impl Sender {
    /// Wall time since the link started [s]: the clock of protocol duties (retransmissions,
    /// the duplicate-command window).
    fn wall_s(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    fn header(&self) -> MavHeader {
        MavHeader {
            system_id: u32::from(self.identity.system_id),
            component_id: self.identity.component_id,
            sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
        }
    }

    async fn send(&self, msg: &MavMessage, to: SocketAddr) {
        let frame = self.seal(frame_message(self.header(), msg));
        if let Some(log) = &self.log {
            log.frame(frame.raw_bytes());
        }
        if let Err(e) = self.socket.send_to(frame.raw_bytes(), to).await {
            tracing::debug!("send to {to}: {e}");
        }
    }

    /// `frame` signed when the vehicle has a key (mavlink.md §10), as it is otherwise.
    fn seal(&self, mut frame: MAVLinkV2MessageRaw) -> MAVLinkV2MessageRaw {
        if let Ok(mut signing) = self.signing.lock() {
            if signing.enabled() {
                signing.seal(&mut frame, self.link_id, signing_now());
            }
        }
        frame
    }
}

/// Runs the link on `socket` until shutdown; `remote` always gets telemetry.
pub async fn run_link(socket: UdpSocket, remote: SocketAddr, mut ctx: LinkContext) {
    let sender = Arc::new(Sender {
        socket: Arc::new(socket),
        identity: ctx.identity,
        sequence: AtomicU8::new(0),
        duplicates: Mutex::new(DuplicateCache::default()),
        targets: Mutex::new(vec![remote]),
        start: Instant::now(),
        log: ctx.log.clone(),
        streams: Mutex::new(StreamTable::new(ctx.kind)),
        last_gcs_heartbeat: Mutex::new(None),
        signing: ctx.signing.clone(),
        link_id: match ctx.kind {
            LinkKind::Gcs => 0,
            LinkKind::Api => 1,
        },
    });
    let mut peers: HashMap<SocketAddr, Instant> = HashMap::new();
    let start = Instant::now();
    let mut next_heartbeat = start;
    let mut next_heartbeat_sim_s = 0.0;
    let mut last_state: Option<(bool, FlightMode)> = None;
    let mut transfer = MissionTransfer::<SocketAddr>::default();
    let mut link_lost = false;
    let mut buf = vec![0u8; MAX_DATAGRAM_BYTES];
    let mut poll = tokio::time::interval(POLL);
    loop {
        tokio::select! {
            _ = ctx.shutdown.changed() => break,
            received = sender.socket.recv_from(&mut buf) => {
                let Ok((n, from)) = received else { continue };
                handle_datagram(&buf[..n], from, &sender, &ctx, &mut peers, &mut transfer);
                // Under a burst, read what is queued without going round the select (a flood
                // then costs the decoding only); the batch is bounded so telemetry stays on time.
                for _ in 0..RECV_BATCH {
                    let Ok((n, from)) = sender.socket.try_recv_from(&mut buf) else { break };
                    handle_datagram(&buf[..n], from, &sender, &ctx, &mut peers, &mut transfer);
                }
            }
            event = ctx.announcements.recv() => {
                if let Ok(event) = event {
                    let msg = match event {
                        Event::MissionItemReached(seq) => MavMessage::MISSION_ITEM_REACHED(MISSION_ITEM_REACHED_DATA { seq }),
                        Event::MissionCurrent(seq) => mission_current(&ctx.snapshot.borrow(), seq),
                        Event::Failsafe(text) => status_text(MavSeverity::MAV_SEVERITY_CRITICAL, &text),
                        other => status_text(MavSeverity::MAV_SEVERITY_INFO, &other.describe()),
                    };
                    for to in targets(remote, &mut peers) {
                        sender.send(&msg, to).await;
                    }
                }
            }
            _ = poll.tick() => {
                let now = Instant::now();
                if let Ok(mut t) = sender.targets.lock() {
                    *t = targets(remote, &mut peers);
                }
                for (to, msg) in transfer.tick(sender.wall_s()) {
                    sender.send(&msg, to).await;
                }
                if ctx.kind == LinkKind::Gcs {
                    check_link_loss(&sender, &ctx, &mut link_lost, remote, &mut peers).await;
                }
                let snap = *ctx.snapshot.borrow();
                let state = (snap.armed, snap.mode);
                // At least 1 Hz in wall time (MAVSDK drops a silent link after 3 s) and 1 Hz in
                // simulated time (scripts pacing themselves in simulated time see the same rate at
                // any speed-up), plus one right after arm, disarm or a mode change (mavlink.md §1).
                if now >= next_heartbeat
                    || snap.t_s >= next_heartbeat_sim_s
                    || last_state.is_some_and(|s| s != state)
                {
                    next_heartbeat = now + HEARTBEAT_PERIOD;
                    next_heartbeat_sim_s = snap.t_s + HEARTBEAT_PERIOD.as_secs_f64();
                    last_state = Some(state);
                    let hb = heartbeat(&ctx.identity, snap.armed, snap.mode);
                    for to in targets(remote, &mut peers) {
                        sender.send(&hb, to).await;
                    }
                }
                // Stream rates count simulated time; each stream goes out at most once per poll,
                // which caps it at 200 Hz wall when simulated time runs fast.
                let due = sender.streams.lock().map(|mut t| t.due(snap.t_s)).unwrap_or_default();
                for stream in due {
                    if let Some(msg) = message(stream, &snap) {
                        for to in targets(remote, &mut peers) {
                            sender.send(&msg, to).await;
                        }
                    }
                }
            }
        }
    }
}

/// The configured remote and every live learned peer (expired ones are dropped).
fn targets(remote: SocketAddr, peers: &mut HashMap<SocketAddr, Instant>) -> Vec<SocketAddr> {
    let now = Instant::now();
    peers.retain(|_, seen| now.duration_since(*seen) < PEER_TIMEOUT);
    let mut out = vec![remote];
    out.extend(peers.keys().filter(|p| **p != remote));
    out
}

fn handle_datagram(
    data: &[u8],
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
    peers: &mut HashMap<SocketAddr, Instant>,
    transfer: &mut MissionTransfer<SocketAddr>,
) {
    // With a key, only signed frames with fresh timestamps pass, and HEARTBEAT-like ones unsigned
    // (mavlink.md §10); only a trusted frame makes its sender a peer.
    let frames = match sender.signing.lock() {
        Ok(mut signing) => {
            let now = signing_now();
            decode_datagram_checked(data, |raw| match signing.check(raw, now) {
                Verdict::Dropped(_) => None,
                verdict => Some(verdict == Verdict::Trusted),
            })
        }
        Err(_) => Vec::new(),
    };
    for (frame, trusted) in frames {
        match frame {
            // An unsigned HEARTBEAT while signing is on is only logged: it neither registers a
            // peer nor counts as a ground station's liveness.
            Inbound::Message { header, message, .. } if !trusted => {
                log_received(sender, header, &message);
            }
            Inbound::Message { header, message, .. } => {
                peers.insert(from, Instant::now());
                log_received(sender, header, &message);
                let origin = ctx.snapshot.borrow().home;
                let now_ns = i64::try_from(sender.start.elapsed().as_nanos()).unwrap_or(i64::MAX);
                let action = ingest(&ctx.identity, &header, &message, &origin, now_ns);
                handle_action(&header, action, from, sender, ctx, transfer);
            }
            Inbound::UnknownCommand {
                header,
                command,
                target_system,
                target_component,
            } => {
                peers.insert(from, Instant::now());
                if trusted && ctx.identity.accepts(&header, target_system, target_component) {
                    let ack = sender.seal(unsupported_command_ack(
                        sender.header(),
                        command,
                        header.system_id as u8,
                        header.component_id,
                    ));
                    let socket = sender.socket.clone();
                    tokio::spawn(async move {
                        let _ = socket.send_to(ack.raw_bytes(), from).await;
                    });
                }
            }
            Inbound::Unparsable { message_id } => tracing::debug!("unparsable message {message_id} from {from}"),
        }
    }
}

/// Writes a received message to the tlog, re-encoded; SETUP_SIGNING never (it carries the key).
fn log_received(sender: &Sender, header: MavHeader, message: &MavMessage) {
    if let Some(log) = &sender.log {
        if !matches!(message, MavMessage::SETUP_SIGNING(_)) {
            let mut frame = Vec::with_capacity(300);
            encode_v2(header, message, &mut frame);
            log.frame(&frame);
        }
    }
}

/// SETUP_SIGNING (mavlink.md §10): refused while armed; otherwise the key (all zero: off) takes
/// effect at once for both links and is stored in the `--signing-key` file. It reached here
/// only unsigned with no key set, or signed with the current key.
fn setup_signing(key: SigningKey, initial_timestamp: u64, ctx: &LinkContext) -> (MavSeverity, String) {
    if ctx.snapshot.borrow().armed {
        return (
            MavSeverity::MAV_SEVERITY_WARNING,
            "SETUP_SIGNING refused: disarm first".into(),
        );
    }
    let Ok(mut signing) = ctx.signing.lock() else {
        return (MavSeverity::MAV_SEVERITY_ERROR, "SETUP_SIGNING failed".into());
    };
    signing.set_key(key.clone(), initial_timestamp);
    let enabled = signing.enabled();
    let timestamp = signing.timestamp();
    drop(signing);
    let stored = ctx.signing_store.as_ref().map(|store| {
        store
            .save_key(enabled.then_some(&key))
            .and_then(|()| store.save_timestamp(timestamp))
    });
    let state = if enabled { "Signing enabled" } else { "Signing disabled" };
    match stored {
        Some(Err(e)) => {
            tracing::warn!("signing key file: {e}");
            (
                MavSeverity::MAV_SEVERITY_WARNING,
                format!("{state}; key file not written"),
            )
        }
        Some(Ok(())) => (MavSeverity::MAV_SEVERITY_INFO, format!("{state}; key stored")),
        None => (MavSeverity::MAV_SEVERITY_INFO, format!("{state} until restart")),
    }
}

/// Performs what [`ingest`] decided for one message from `from`.
fn handle_action(
    header: &MavHeader,
    action: Action,
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
    transfer: &mut MissionTransfer<SocketAddr>,
) {
    let reply = |msg: MavMessage| {
        let s = sender.clone();
        tokio::spawn(async move { s.send(&msg, from).await });
    };
    match action {
        Action::Ignore => {}
        Action::GcsHeartbeat => {
            if let Ok(mut last) = sender.last_gcs_heartbeat.lock() {
                *last = Some((Instant::now(), ctx.snapshot.borrow().t_s));
            }
        }
        Action::Command { command, decision } => handle_command(header, &command, decision, from, sender, ctx),
        // Setpoints stream at 20 Hz or more: a full queue drops one, the next replaces it;
        // SET_MODE has no ACK, the next heartbeat shows the result.
        Action::Request(request) => {
            let _ = ctx.inbox.try_send(VehicleCommand::Request { request, reply: None });
        }
        Action::Refuse(why) => reply(status_text(MavSeverity::MAV_SEVERITY_WARNING, &why)),
        Action::Reply(msg) => reply(*msg),
        Action::DataStream {
            stream_id,
            rate_hz,
            start,
        } => {
            if let Ok(mut t) = sender.streams.lock() {
                t.request_data_stream(stream_id, rate_hz, start);
            }
        }
        Action::ParamList => {
            let table = ctx.params.borrow().clone();
            let s = sender.clone();
            tokio::spawn(async move {
                // Paced at one per millisecond at most (mavlink.md §8.1).
                for i in 0..table.len() {
                    if let Some(msg) = param_value(&table, i) {
                        s.send(&msg, from).await;
                    }
                    tokio::time::sleep(Duration::from_millis(1)).await;
                }
            });
        }
        Action::ParamRead { name, index } => {
            let table = ctx.params.borrow().clone();
            match index
                .or_else(|| table.index_of(&name))
                .and_then(|i| param_value(&table, i))
            {
                Some(msg) => reply(msg),
                None => reply(param_error_unknown(header, &name)),
            }
        }
        Action::ParamSet { name, value } => set_param(name, value, *header, from, sender, ctx),
        Action::Mission { ids, step } => handle_mission(ids, step, from, sender, ctx, transfer),
        Action::SetupSigning { key, initial_timestamp } => {
            let (severity, text) = setup_signing(key, initial_timestamp, ctx);
            reply(status_text(severity, &text));
        }
    }
}

/// GCS link loss (mavlink.md §11.2): after a GCS heartbeat was seen, `COM_DL_LOSS_T` seconds of
/// silence in simulated time *and* in wall time run `NAV_DLL_ACT` once per loss. A ground
/// station pacing itself in simulated time sees the same failsafe at any speed-up; one sending
/// in wall time does not trip it just because simulated time runs faster.
async fn check_link_loss(
    sender: &Arc<Sender>,
    ctx: &LinkContext,
    lost: &mut bool,
    remote: SocketAddr,
    peers: &mut HashMap<SocketAddr, Instant>,
) {
    let Some((last_wall, last_sim_s)) = sender.last_gcs_heartbeat.lock().ok().and_then(|l| *l) else {
        return;
    };
    let settings = ctx.params.borrow().settings().commander;
    let now_sim_s = ctx.snapshot.borrow().t_s;
    let silent =
        last_wall.elapsed().as_secs_f64() >= settings.link_loss_s && now_sim_s - last_sim_s >= settings.link_loss_s;
    if !silent {
        *lost = false;
        return;
    }
    if *lost || settings.link_loss_action == crate::commander::LinkLossAction::Disabled {
        return;
    }
    *lost = true;
    let (tx, rx) = oneshot::channel();
    let queued = ctx.inbox.try_send(VehicleCommand::Request {
        request: Request::GcsLinkLost,
        reply: Some(tx),
    });
    if queued.is_ok() {
        if let Ok(Outcome::TemporarilyRejected(what)) = rx.await {
            let msg = status_text(MavSeverity::MAV_SEVERITY_CRITICAL, &what);
            for to in targets(remote, peers) {
                sender.send(&msg, to).await;
            }
        }
    }
}
