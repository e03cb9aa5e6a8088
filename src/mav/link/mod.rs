//! The MAVLink endpoint of one vehicle as a state machine without I/O, shaped like
//! quinn-proto: the runtime feeds it what happened (`handle_*`, each with the time) and drains
//! what it decided (`poll_*`), in the order it was decided. It never reads a clock, owns no
//! socket, spawns nothing and takes no lock; the fuzz target and the in-process tests drive the
//! same machine the binary ships, with virtual time.
//!
//! Two clocks are passed in ([`Now`]): wall time drives what peers time in wall seconds (peer
//! expiry, the 1 Hz wall heartbeat MAVSDK needs, retransmissions, parameter pacing, the
//! duplicate-command window, GCS silence); simulated time drives telemetry rates, the
//! simulated-time heartbeat and the simulated half of link loss, so that scripts pacing
//! themselves in simulated time see the same protocol at any speed-up.
//!
//! As quinn-proto's `Connection` is composed of the states that own their parts, the machine
//! is composed of one service per protocol, each owning its state: their methods take the
//! values they need (the wall time, the client, the parameter table or the state) and return
//! [`Effect`](effects::Effect)s, which the machine carries out in order. The machine keeps what
//! every part reads: the links, the vehicle's state and parameter table (shared with the
//! vehicle, never copied), and the output queues.
//!
//! # Layout
//! - `mod.rs`: [`LinkMachine`]: its parts, its `handle_*` and `poll_*`, sending.
//! - `boundary.rs`: its inputs, outputs and configuration ([`Now`], [`LinkConfig`],
//!   [`VehicleReply`], [`Transmit`], [`ToVehicle`], [`KeyToStore`], [`Said`]).
//! - `effects.rs`: what a part decided, as a value.
//! - `port.rs`: one link (GCS or API): remote, learned peers, sequence, rates, heartbeat
//!   schedule, ground-station liveness.
//! - `inbound.rs`: a datagram → frames → signing verdict → [`ingest`](super::ingest::ingest) →
//!   which part handles it; the decision on a new command.
//! - `commands.rs`: `CommandService`: duplicate commands, their one ACK, the awaited requests.
//! - `param_service.rs`: `ParamService`: PARAM_REQUEST_LIST pacing, PARAM_REQUEST_READ,
//!   PARAM_SET and its echo, changes announced, as PX4 or as ArduCopter speaks them.
//! - `param_upload.rs`: `Uploads`: an uploaded `@PARAM/param.pck` applied as PARAM_SETs.
//! - `plan_request.rs`: a complete upload as the commander request putting it in force.
//! - `mission.rs`: `PlanService`: the mission protocol against the stored plans (mission,
//!   fence, rally).
//! - `files.rs`: `Files`: MAVLink FTP per link, burst pacing, component metadata.
//! - `logs.rs`: `LogService`: the log protocol per link (list, download, erase), paced.
//! - `console.rs`: `Consoles`: the MAVLink shell (SERIAL_CONTROL) per client.
//! - `keys.rs`: `SigningKeys`: signing, SETUP_SIGNING and the key file's answers.
//! - `duties.rs`: what time brings: heartbeats, streams, link loss, retransmissions.

mod boundary;
mod commands;
mod console;
mod duties;
mod effects;
mod files;
mod inbound;
mod keys;
pub mod liveness;
mod logs;
mod mission;
mod param_service;
mod param_upload;
mod plan_request;
mod port;
mod rc_feed;

use std::collections::VecDeque;
use std::hash::Hash;
use std::sync::Arc;

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavMissionType, MavSeverity, MISSION_ITEM_INT_DATA};
use mavlink::{MAVLinkV2MessageRaw, MavHeader};

use crate::commander::{Event, Outcome};
use crate::params::{ParamError, ParamTable};
use crate::telemetry::Snapshot;

use super::ardupilot::copter_failsafes::CopterFailsafes;
use super::ardupilot::copter_modes::ModeShown;
use super::ardupilot::copter_texts::{copter_announces, copter_outcome, ArmedNotices, PreArmNotices};
use super::codec::frame_message;
use super::ftp::Vfs;
use super::identity::Personality;
use super::metadata::MetadataFiles;
use super::streams::LinkKind;
use super::translate::Identity;
pub use boundary::{KeyToStore, LinkConfig, Now, Said, ToVehicle, Token, Transmit, VehicleReply, VehicleRequest};
use commands::{AckOf, CommandService, Pending};
use console::Consoles;
use effects::Effect;
use files::Files;
use keys::SigningKeys;
use liveness::StreamLiveness;
use logs::LogService;
pub use logs::{LOG_MESSAGES_AT_ONCE, LOG_MESSAGE_PERIOD_S};
use mission::PlanService;
use param_service::ParamService;
use port::Port;
pub use port::{HeldForClients, MAX_PEERS, PEER_EVICT_S, PEER_TIMEOUT_S};
use rc_feed::RcFeed;

const INFO: MavSeverity = MavSeverity::MAV_SEVERITY_INFO;
const WARNING: MavSeverity = MavSeverity::MAV_SEVERITY_WARNING;
const CRITICAL: MavSeverity = MavSeverity::MAV_SEVERITY_CRITICAL;

/// The MAVLink endpoint of one vehicle over one or more links; `A` is a peer address.
#[derive(Debug)]
pub struct LinkMachine<A> {
    identity: Identity,
    ports: Vec<Port<A>>,
    record_received: bool,
    /// The vehicle's parameter table as its owner last published it (shared, not copied).
    params: Arc<ParamTable>,
    /// The vehicle's latest state as the state channel carries it (shared, not copied).
    snapshot: Arc<Snapshot>,
    /// Signing, SETUP_SIGNING and the key file.
    keys: SigningKeys<A>,
    /// Duplicate commands, ACKs, and the requests awaited from the vehicle.
    commands: CommandService<A>,
    /// The parameter protocol: lists, changes to announce, uploaded parameter files.
    parameters: ParamService<A>,
    /// The stored plans and the mission protocol.
    plans: PlanService<A>,
    /// The files served over MAVLink FTP and the FTP server of each link.
    files: Files<A>,
    /// The log protocol of each link.
    logs: LogService<A>,
    /// The MAVLink shells of the clients that use one.
    consoles: Consoles<A>,
    /// When the offboard setpoints and the sticks were last heard.
    streams: StreamLiveness,
    /// The Copter mode number the HEARTBEAT shows (the ArduCopter personality).
    mode_shown: ModeShown,
    /// "Arming motors" / "Disarming motors" (the ArduCopter personality).
    armed_notices: ArmedNotices,
    /// "PreArm: …" every 30 s while a check fails (the ArduCopter personality).
    prearm_notices: PreArmNotices,
    /// Copter's failsafe texts and whether one is active (the ArduCopter personality).
    copter_failsafes: CopterFailsafes,
    /// The link whose sticks are flown (`COM_RC_IN_MODE` 3 keeps the first).
    sticks_from: Option<LinkKind>,
    /// The RC receiver and the boot mode (the ArduCopter personality).
    rc: RcFeed,
    next_duty_s: f64,
    transmits: VecDeque<Transmit<A>>,
    to_vehicle: VecDeque<ToVehicle>,
    to_store: VecDeque<KeyToStore>,
    received: VecDeque<Vec<u8>>,
    /// The STATUSTEXTs said to one client, for the flight log (kept when logging).
    said: VecDeque<Said>,
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// A machine as `config` describes it; its first duties are due at once.
    pub fn new(config: LinkConfig<A>) -> Self {
        Self::with_metadata(config, None)
    }

    /// [`LinkMachine::new`] with the component metadata files of `config.params` built by the
    /// caller (`None`: built here), for a caller that starts many machines with one parameter
    /// table: compressing them is the costly part of a start.
    pub fn with_metadata(config: LinkConfig<A>, metadata: Option<MetadataFiles>) -> Self {
        let ports = config
            .links
            .iter()
            .enumerate()
            .map(|(id, (kind, remote))| Port::new(*kind, *remote, id as u8, config.identity.personality))
            .collect();
        let kinds: Vec<LinkKind> = config.links.iter().map(|(kind, _)| *kind).collect();
        let personality = config.identity.personality;
        let files = Files::new(&config.params, metadata, &kinds, config.logs, personality);
        Self {
            identity: config.identity,
            ports,
            record_received: config.record_received,
            params: config.params,
            snapshot: config.snapshot,
            keys: SigningKeys::new(config.signing, config.signing_epoch, config.key_store),
            commands: CommandService::new(&kinds),
            parameters: ParamService::new(&config.identity),
            plans: PlanService::new(&kinds, config.identity.personality),
            files,
            logs: LogService::new(&kinds),
            consoles: Consoles::default(),
            streams: StreamLiveness::default(),
            sticks_from: None,
            rc: RcFeed::new(),
            mode_shown: ModeShown::default(),
            armed_notices: ArmedNotices::default(),
            prearm_notices: PreArmNotices::default(),
            copter_failsafes: CopterFailsafes::default(),
            next_duty_s: 0.0,
            transmits: VecDeque::new(),
            to_vehicle: VecDeque::new(),
            to_store: VecDeque::new(),
            received: VecDeque::new(),
            said: VecDeque::new(),
        }
    }

    /// The vehicle's latest state (telemetry, home, armed state for SETUP_SIGNING), as the
    /// state channel carries it: an `Arc` is kept as it is, shared, not copied.
    pub fn handle_state(&mut self, snapshot: impl Into<Arc<Snapshot>>) {
        let snapshot = snapshot.into();
        self.plans.handle_state(&snapshot);
        if self.identity.personality == Personality::ArduPilot {
            self.mode_shown.handle_state(&snapshot);
            self.mode_shown.handle_return_item(self.plans.at_return_item(&snapshot));
        }
        self.snapshot = snapshot;
    }

    /// A commander event, announced to every target of every link (a vehicle presented as
    /// ArduCopter says its failsafes in Copter's words, and not what Copter does not say).
    pub fn handle_event(&mut self, now: Now, event: Event) {
        if self.identity.personality == Personality::ArduPilot {
            if let Some(said) = self.copter_failsafes.handle_event(&event, &self.snapshot) {
                for (severity, text) in said {
                    self.broadcast(now, &super::stream_messages::status_text(severity, &text));
                }
                return;
            }
            if !copter_announces(&event) {
                return;
            }
        }
        let msg = self.announcement(&event);
        self.broadcast(now, &msg);
    }

    /// A notice of the runtime (the logger's "[logger] ./log/…" when a flight log begins),
    /// announced as an information STATUSTEXT to every target of every link (not by a vehicle
    /// presented as ArduCopter, which says nothing of its logs).
    pub fn handle_notice(&mut self, now: Now, text: &str) {
        if self.identity.personality == Personality::ArduPilot {
            return; // ArduCopter says nothing of its logs.
        }
        self.broadcast(now, &super::stream_messages::status_text(INFO, text));
    }

    /// The vehicle's answer to the request `token` named.
    pub fn handle_reply(&mut self, now: Now, token: Token, reply: VehicleReply) {
        let effects = match self.commands.take(token) {
            Some(Pending::Command(asker)) => {
                let outcome = match reply {
                    VehicleReply::Outcome(outcome) => outcome,
                    _ => Outcome::TemporarilyRejected("Vehicle busy".into()),
                };
                let outcome = match self.identity.personality {
                    Personality::Px4 => outcome,
                    Personality::ArduPilot => {
                        let shown = self.mode_shown.shown(&self.snapshot);
                        copter_outcome(asker.command, (self.mode_shown.asked(), shown), outcome)
                    }
                };
                self.commands.answer(now.wall_s, asker, AckOf::Outcome(outcome))
            }
            Some(Pending::SetMode(client)) => {
                let outcome = match reply {
                    VehicleReply::Outcome(outcome) => outcome,
                    _ => Outcome::TemporarilyRejected("Vehicle busy".into()),
                };
                let shown = self.mode_shown.shown(&self.snapshot);
                let asked = (self.mode_shown.asked(), shown);
                let outcome = copter_outcome(MavCmd::MAV_CMD_DO_SET_MODE, asked, outcome);
                self.answer_set_mode(now, client, AckOf::Outcome(outcome));
                Vec::new()
            }
            Some(Pending::Param(set)) => {
                let result = self.take_table(reply);
                let targets = self.targets(set.link());
                let held = self.link_params();
                self.parameters
                    .set_done(now.wall_s, set, result, (&self.params, &held), targets)
            }
            Some(Pending::Shell(set)) => {
                let before = Arc::clone(&self.params);
                let result = match self.take_table(reply) {
                    Some(result) => result.map_err(|e| e.to_string()),
                    None => Err("vehicle busy, try again".to_string()),
                };
                let targets = self.targets(set.link());
                let held = self.link_params();
                self.consoles.set_done(set, result, &before, self.shown(&held), targets)
            }
            Some(Pending::Upload(set)) => {
                let result = self.take_table(reply).unwrap_or_else(|| {
                    Err(ParamError::Invalid {
                        name: set.name.clone(),
                        reason: "vehicle busy".into(),
                    })
                });
                self.parameters.upload_set_done(now.wall_s, set, result)
            }
            Some(Pending::Mission {
                link,
                mission_type,
                items,
            }) => {
                let taken = !matches!(reply, VehicleReply::Busy);
                self.plans.taken(link, mission_type, items, taken)
            }
            None => Vec::new(),
        };
        self.carry_out(now, effects);
    }

    /// The key file's answer to the oldest [`KeyToStore`].
    pub fn handle_stored(&mut self, now: Now, result: Result<(), String>) {
        let effects = self.keys.stored(result);
        self.carry_out(now, effects);
    }

    /// The next datagram to send.
    pub fn poll_transmit(&mut self) -> Option<Transmit<A>> {
        self.transmits.pop_front()
    }

    /// The next request for the vehicle.
    pub fn poll_vehicle(&mut self) -> Option<ToVehicle> {
        self.to_vehicle.pop_front()
    }

    /// The next STATUSTEXT said to one client, for the flight log (only while logging).
    pub fn poll_said(&mut self) -> Option<Said> {
        self.said.pop_front()
    }

    /// The next key to write to the key file.
    pub fn poll_store(&mut self) -> Option<KeyToStore> {
        self.to_store.pop_front()
    }

    /// The next received frame for the tlog (re-encoded; SETUP_SIGNING never, it carries the key).
    pub fn poll_received(&mut self) -> Option<Vec<u8>> {
        self.received.pop_front()
    }

    /// Wall time at which [`handle_timeout`](Self::handle_timeout) next has work [s].
    pub fn poll_timeout(&self) -> f64 {
        [
            self.parameters.next_due_s(),
            self.files.next_due_s(),
            self.logs.next_due_s(),
        ]
        .into_iter()
        .flatten()
        .fold(self.next_duty_s, f64::min)
    }

    /// The signing timestamp to persist [10 µs since 2015].
    pub fn signing_timestamp(&self) -> u64 {
        self.keys.timestamp()
    }

    /// Simulated time of the vehicle state the machine holds [s] (the clock its `Now` must use).
    pub fn state_time_s(&self) -> f64 {
        self.snapshot.t_s
    }

    /// Frames signing dropped so far (unsigned, wrongly signed or replayed).
    pub fn signing_dropped(&self) -> u64 {
        self.keys.dropped()
    }

    /// The mission as last uploaded.
    pub fn stored_mission(&self) -> &[MISSION_ITEM_INT_DATA] {
        self.plans.items(MavMissionType::MAV_MISSION_TYPE_MISSION)
    }

    /// Plan `mission_type` (mission, fence or rally) as last uploaded.
    pub fn stored_plan(&self, mission_type: MavMissionType) -> &[MISSION_ITEM_INT_DATA] {
        self.plans.items(mission_type)
    }

    /// The files served over MAVLink FTP from memory (metadata, scratch area).
    pub fn files(&self) -> &Vfs {
        self.files.vfs()
    }

    /// The result a parameter reply carries (`None`: the vehicle was busy); the table it
    /// carries becomes the link's, shared with the vehicle (`@PARAM/param.pck` packs it).
    fn take_table(&mut self, reply: VehicleReply) -> Option<Result<usize, ParamError>> {
        match reply {
            VehicleReply::Param { result, table } => {
                self.params = table;
                self.files.params_changed();
                Some(result)
            }
            _ => None,
        }
    }

    fn port(&mut self, link: LinkKind) -> Option<&mut Port<A>> {
        self.ports.iter_mut().find(|p| p.kind == link)
    }

    /// The remote and the peers of `link`.
    fn targets(&self, link: LinkKind) -> Vec<A> {
        self.ports
            .iter()
            .find(|p| p.kind == link)
            .map(|p| p.targets())
            .unwrap_or_default()
    }

    /// Carries out what a part decided, in order: messages queued, requests for the vehicle
    /// named and queued, what one part decided for another handed to it.
    fn carry_out(&mut self, now: Now, effects: Vec<Effect<A>>) {
        for effect in effects {
            match effect {
                Effect::To(link, to, out) => self.send(now, link, to, &out),
                Effect::Everyone(msg) => self.broadcast(now, &msg),
                Effect::Ask(pending, request) => {
                    let token = pending.map(|p| self.commands.expect(p));
                    self.to_vehicle.push_back(ToVehicle { token, request });
                }
                Effect::Upload(client, upload) => {
                    let held = self.link_params();
                    let more = self.parameters.start_upload(client, upload, (&self.params, &held));
                    self.carry_out(now, more);
                }
                Effect::UploadAnswer(client, request, result) => {
                    let more = self.files.answer_upload(client, &request, result);
                    self.carry_out(now, more);
                }
                Effect::Store(key) => self.to_store.push_back(key),
                Effect::LinkSet((link, to), change, index) => self.link_set(now, (link, to), change, index),
            }
        }
    }

    /// Queues `msg` to `to` on `link`.
    fn send(&mut self, now: Now, link: LinkKind, to: A, msg: &MavMessage) {
        if let (MavMessage::STATUSTEXT(t), true) = (msg, self.record_received) {
            let end = t.text.iter().position(|&b| b == 0).unwrap_or(t.text.len());
            self.said.push_back(Said {
                t_s: self.snapshot.t_s,
                severity: t.severity as u8,
                text: String::from_utf8_lossy(&t.text[..end]).into_owned(),
            });
        }
        self.send_unlogged(now, link, to, msg);
    }

    /// [`Self::send`] without noting a STATUSTEXT for the flight log.
    fn send_unlogged(&mut self, now: Now, link: LinkKind, to: A, msg: &MavMessage) {
        self.send_frame(now, link, to, |header| frame_message(header, msg));
    }

    /// Queues the frame `build` makes from our header to `to` on `link`: the link's next
    /// sequence number, sealed when signing.
    fn send_frame(&mut self, now: Now, link: LinkKind, to: A, build: impl FnOnce(MavHeader) -> MAVLinkV2MessageRaw) {
        let Some(port) = self.ports.iter_mut().find(|p| p.kind == link) else {
            return;
        };
        let header = MavHeader {
            system_id: u32::from(self.identity.system_id),
            component_id: self.identity.component_id,
            sequence: port.next_sequence(),
        };
        let link_id = port.link_id;
        let mut frame = build(header);
        self.keys.seal(&mut frame, link_id, now.wall_s);
        self.transmits.push_back(Transmit {
            link,
            to,
            bytes: frame.raw_bytes().to_vec(),
        });
    }

    /// `msg` to every target of every link.
    fn broadcast(&mut self, now: Now, msg: &MavMessage) {
        for k in 0..self.ports.len() {
            let link = self.ports[k].kind;
            for to in self.ports[k].targets() {
                self.send_unlogged(now, link, to, msg);
            }
        }
    }
}
