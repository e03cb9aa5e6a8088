//! One MAVLink UDP link (GCS or API): its own socket, the peers learned from valid frames, the
//! periodic telemetry, and the command path (decode → vehicle → COMMAND_ACK to the sender).
//! Runtime layer: wall-clock pacing of streams, sockets; the message maths is in `mav`.

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::net::UdpSocket;
use tokio::sync::{broadcast, mpsc, oneshot, watch};

use crate::commander::{Event, FlightMode, Outcome, Request};
use crate::mav::codec::{decode_datagram, encode_v2, unsupported_command_ack, Inbound};
use crate::mav::telemetry::{message, status_text, GCS_STREAMS};
use crate::mav::translate::{
    command_ack, decode_command, decode_set_mode, heartbeat, result_of, CommandDecision, Identity,
};
use crate::mav::{MavHeader, MavMessage, MavSeverity};
use crate::telemetry::Snapshot;

use super::scheduler::VehicleCommand;

/// Learned peers are forgotten after this much silence (mavlink.md §11.1).
const PEER_TIMEOUT: Duration = Duration::from_secs(10);
/// How often the link looks at what is due.
const POLL: Duration = Duration::from_millis(5);
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
    /// Announcements for every peer (STATUSTEXT).
    pub announcements: broadcast::Receiver<Event>,
    /// Becomes true at shutdown.
    pub shutdown: watch::Receiver<bool>,
}

/// Sends frames to peers with a per-link sequence counter.
struct Sender {
    socket: Arc<UdpSocket>,
    identity: Identity,
    sequence: AtomicU8,
}

impl Sender {
    fn header(&self) -> MavHeader {
        MavHeader {
            system_id: u32::from(self.identity.system_id),
            component_id: self.identity.component_id,
            sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
        }
    }

    async fn send(&self, msg: &MavMessage, to: SocketAddr) {
        let mut buf = Vec::with_capacity(300);
        encode_v2(self.header(), msg, &mut buf);
        if let Err(e) = self.socket.send_to(&buf, to).await {
            tracing::debug!("send to {to}: {e}");
        }
    }
}

/// Runs the link on `socket` until shutdown; `remote` always gets telemetry.
pub async fn run_link(socket: UdpSocket, remote: SocketAddr, mut ctx: LinkContext) {
    let sender = Arc::new(Sender {
        socket: Arc::new(socket),
        identity: ctx.identity,
        sequence: AtomicU8::new(0),
    });
    let mut peers: HashMap<SocketAddr, Instant> = HashMap::new();
    let start = Instant::now();
    let mut next_heartbeat = start;
    let mut next_stream: Vec<Instant> = GCS_STREAMS.iter().map(|_| start).collect();
    let mut last_state: Option<(bool, FlightMode)> = None;
    let mut buf = vec![0u8; 65_536];
    let mut poll = tokio::time::interval(POLL);
    loop {
        tokio::select! {
            _ = ctx.shutdown.changed() => break,
            received = sender.socket.recv_from(&mut buf) => {
                let Ok((n, from)) = received else { continue };
                handle_datagram(&buf[..n], from, &sender, &ctx, &mut peers);
            }
            event = ctx.announcements.recv() => {
                if let Ok(event) = event {
                    let text = match event {
                        Event::Disarmed(why) => format!("Disarmed: {why}"),
                        Event::ModeChanged(mode) => format!("Mode {}", mode.name()),
                        Event::Landed => "Landing detected".to_string(),
                    };
                    let msg = status_text(MavSeverity::MAV_SEVERITY_INFO, &text);
                    for to in targets(remote, &mut peers) {
                        sender.send(&msg, to).await;
                    }
                }
            }
            _ = poll.tick() => {
                let now = Instant::now();
                let snap = *ctx.snapshot.borrow();
                let state = (snap.armed, snap.mode);
                // One extra heartbeat right after arm, disarm or a mode change (mavlink.md §1).
                if now >= next_heartbeat || last_state.is_some_and(|s| s != state) {
                    next_heartbeat = now + HEARTBEAT_PERIOD;
                    last_state = Some(state);
                    let hb = heartbeat(&ctx.identity, snap.armed, snap.mode);
                    for to in targets(remote, &mut peers) {
                        sender.send(&hb, to).await;
                    }
                }
                for ((stream, period), due) in GCS_STREAMS.iter().zip(next_stream.iter_mut()) {
                    if now >= *due {
                        *due = now + Duration::from_secs_f64(*period);
                        let msg = message(*stream, &snap);
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
) {
    for frame in decode_datagram(data) {
        match frame {
            Inbound::Message { header, message, .. } => {
                peers.insert(from, Instant::now());
                handle_message(&header, &message, from, sender, ctx);
            }
            Inbound::UnknownCommand {
                header,
                command,
                target_system,
                target_component,
            } => {
                peers.insert(from, Instant::now());
                if ctx.identity.accepts(&header, target_system, target_component) {
                    let bytes =
                        unsupported_command_ack(sender.header(), command, header.system_id as u8, header.component_id);
                    let socket = sender.socket.clone();
                    tokio::spawn(async move {
                        let _ = socket.send_to(&bytes, from).await;
                    });
                }
            }
            Inbound::Unparsable { message_id } => tracing::debug!("unparsable message {message_id} from {from}"),
        }
    }
}

fn handle_message(header: &MavHeader, message: &MavMessage, from: SocketAddr, sender: &Arc<Sender>, ctx: &LinkContext) {
    match message {
        MavMessage::COMMAND_LONG(cmd) => {
            let home_amsl = ctx.snapshot.borrow().home.alt_amsl_m;
            let decision = decode_command(&ctx.identity, header, cmd, home_amsl);
            let command = cmd.command;
            let header = *header;
            match decision {
                CommandDecision::NotForUs => {}
                CommandDecision::Unsupported => {
                    let s = sender.clone();
                    tokio::spawn(async move {
                        let ack = command_ack(&header, command, crate::mav::MavResult::MAV_RESULT_UNSUPPORTED);
                        s.send(&ack, from).await;
                    });
                }
                CommandDecision::Refuse(outcome) => {
                    let s = sender.clone();
                    tokio::spawn(async move { answer(&s, &header, command, &outcome, from).await });
                }
                CommandDecision::Execute(request) => execute(request, header, command, from, sender, ctx),
            }
        }
        other => {
            if let Some(mode) = decode_set_mode(&ctx.identity, other) {
                // SET_MODE has no ACK; the next heartbeat shows the result.
                let _ = ctx.inbox.try_send(VehicleCommand {
                    request: Request::SetMode(mode),
                    reply: None,
                });
            }
        }
    }
}

/// Sends `request` to the vehicle and answers the sender with its outcome.
fn execute(
    request: Request,
    header: MavHeader,
    command: crate::mav::MavCmd,
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
) {
    let (tx, rx) = oneshot::channel();
    let s = sender.clone();
    if ctx
        .inbox
        .try_send(VehicleCommand {
            request,
            reply: Some(tx),
        })
        .is_err()
    {
        tokio::spawn(async move {
            let busy = Outcome::TemporarilyRejected("Vehicle busy".into());
            answer(&s, &header, command, &busy, from).await;
        });
        return;
    }
    tokio::spawn(async move {
        let outcome = rx
            .await
            .unwrap_or(Outcome::TemporarilyRejected("Vehicle stopped".into()));
        answer(&s, &header, command, &outcome, from).await;
    });
}

/// COMMAND_ACK to the sender, and a STATUSTEXT with the reason of a refusal.
async fn answer(sender: &Sender, header: &MavHeader, command: crate::mav::MavCmd, outcome: &Outcome, to: SocketAddr) {
    sender.send(&command_ack(header, command, result_of(outcome)), to).await;
    if let Outcome::TemporarilyRejected(why) | Outcome::Denied(why) = outcome {
        sender
            .send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, why), to)
            .await;
    }
}
