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
//! # Layout
//! - `mod.rs`: [`LinkMachine`], its inputs and outputs and the types they carry.
//! - `port.rs`: one link (GCS or API): remote, learned peers, sequence, rates, heartbeat
//!   schedule, duplicate cache, mission upload, ground-station liveness.
//! - `inbound.rs`: a datagram → frames → signing verdict → [`ingest`](super::ingest::ingest) →
//!   what to do; SETUP_SIGNING.
//! - `commands.rs`: COMMAND_LONG/INT, their one ACK, and the vehicle's answers.
//! - `params.rs`: PARAM_REQUEST_LIST pacing, PARAM_REQUEST_READ, PARAM_SET and its echo.
//! - `mission.rs`: the mission protocol against the stored plans (mission, fence, rally).
//! - `files.rs`: MAVLink FTP per link, burst pacing, component metadata.
//! - `param_upload.rs`: an uploaded `@PARAM/param.pck` applied as PARAM_SETs.
//! - `logs.rs`: the log protocol per link (list, download, erase of the log store's logs), paced.
//! - `console.rs`: the MAVLink shell (SERIAL_CONTROL) per client.
//! - `duties.rs`: what time brings: heartbeats, streams, link loss, retransmissions.

mod commands;
mod console;
mod duties;
mod files;
mod inbound;
mod logs;
mod mission;
mod param_upload;
mod params;
mod port;

use std::collections::{HashMap, VecDeque};
use std::hash::Hash;

use mavlink::dialects::common::{MavMessage, MavMissionType, MavSeverity, MISSION_ITEM_INT_DATA};
use mavlink::{MAVLinkV2MessageRaw, MavHeader};

use crate::commander::{Event, Outcome, Request};
use crate::params::{ParamError, ParamTable};
use crate::telemetry::Snapshot;

use super::codec::frame_message;
use super::logs::{LogStore, MemLogStore};
use super::metadata::MetadataFiles;
use super::mission_report::MissionReport;
use super::plan_store::PlanStore;
use super::signing::{Signing, SigningKey};
use super::streams::LinkKind;
use super::telemetry::Outgoing;
use super::translate::Identity;
use files::Files;
pub use logs::{LOG_MESSAGES_AT_ONCE, LOG_MESSAGE_PERIOD_S};
use params::ParamList;
use port::Port;
pub use port::{HeldForClients, MAX_PEERS, PEER_EVICT_S, PEER_TIMEOUT_S};

const INFO: MavSeverity = MavSeverity::MAV_SEVERITY_INFO;
const WARNING: MavSeverity = MavSeverity::MAV_SEVERITY_WARNING;
const CRITICAL: MavSeverity = MavSeverity::MAV_SEVERITY_CRITICAL;

/// The two clocks of one input [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Now {
    /// Wall time since the machine started [s].
    pub wall_s: f64,
    /// Simulated time of the vehicle [s].
    pub sim_s: f64,
}

impl Now {
    /// Wall time `wall_s` and simulated time `sim_s` [s].
    pub fn new(wall_s: f64, sim_s: f64) -> Self {
        Self { wall_s, sim_s }
    }
}

/// One datagram to send.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transmit<A> {
    /// The link whose socket sends it.
    pub link: LinkKind,
    /// Destination.
    pub to: A,
    /// One MAVLink 2 frame (signed when the vehicle has a key).
    pub bytes: Vec<u8>,
}

/// Names a request whose answer the machine waits for ([`LinkMachine::handle_reply`]).
pub type Token = u64;

/// What the link asks of the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub enum VehicleRequest {
    /// A commander request (commands, setpoints, modes, missions, link loss).
    Commander(Request),
    /// A parameter set.
    SetParam {
        /// Parameter name.
        name: String,
        /// New value.
        value: f64,
    },
}

/// A request for the vehicle; with a token, the answer is expected through
/// [`LinkMachine::handle_reply`].
#[derive(Debug, Clone, PartialEq)]
pub struct ToVehicle {
    /// Present when the link waits for the answer.
    pub token: Option<Token>,
    /// What to do.
    pub request: VehicleRequest,
}

/// The vehicle's answer to a [`ToVehicle`] with a token.
#[derive(Debug, Clone, PartialEq)]
pub enum VehicleReply {
    /// The commander's answer.
    Outcome(Outcome),
    /// A parameter set's result and the table after it.
    Param {
        /// The parameter's index, or why the set was refused.
        result: Result<usize, ParamError>,
        /// The table as it now is.
        table: Box<ParamTable>,
    },
    /// The request could not be queued (the vehicle's inbox is full).
    Busy,
}

/// A key (or its removal) the runtime writes to the `--signing-key` file, with the timestamp;
/// the result comes back through [`LinkMachine::handle_stored`].
#[derive(Debug, Clone, PartialEq)]
pub struct KeyToStore {
    /// The new key; `None`: signing switched off (the file is removed).
    pub key: Option<SigningKey>,
    /// Signing timestamp at the change [10 µs since 2015].
    pub timestamp: u64,
}

/// How a machine starts.
#[derive(Debug)]
pub struct LinkConfig<A> {
    /// Our system and component ids and vehicle type.
    pub identity: Identity,
    /// The links and the remote each always sends telemetry to; the position is the link id
    /// of outgoing signatures (GCS 0, API 1 in the autopilot).
    pub links: Vec<(LinkKind, A)>,
    /// The vehicle's parameters at start.
    pub params: ParamTable,
    /// The vehicle's state at start.
    pub snapshot: Snapshot,
    /// Signing key and timestamp at start.
    pub signing: Signing,
    /// The wall clock at wall time 0, as a signing timestamp [10 µs since 2015]: the signing
    /// clock and SYSTEM_TIME are this plus wall time (0: no clock; SYSTEM_TIME then says 0).
    pub signing_epoch: u64,
    /// SETUP_SIGNING keys are kept (a key file): a change waits for [`LinkMachine::handle_stored`].
    pub key_store: bool,
    /// Received frames are handed out for the tlog ([`LinkMachine::poll_received`]).
    pub record_received: bool,
    /// The flight logs served by the log protocol and at `/fs/microsd/log` over FTP.
    pub logs: Box<dyn LogStore>,
}

impl<A> LinkConfig<A> {
    /// A vehicle with `identity` on `links`, `params` and `snapshot` at start; no signing key,
    /// no key file, received frames not recorded, no flight logs.
    pub fn new(identity: Identity, links: Vec<(LinkKind, A)>, params: ParamTable, snapshot: Snapshot) -> Self {
        Self {
            identity,
            links,
            params,
            snapshot,
            signing: Signing::new(None, 0),
            signing_epoch: 0,
            key_store: false,
            record_received: false,
            logs: Box::new(MemLogStore::default()),
        }
    }
}

/// What the machine waits for from the vehicle or the key file.
#[derive(Debug, Clone, PartialEq)]
enum Pending<A> {
    /// A command's ACK.
    Command(commands::Asker<A>),
    /// A PARAM_SET's echo.
    Param(params::ParamSet<A>),
    /// A shell's `param set`.
    Shell(console::ShellSet<A>),
    /// One parameter of a file uploaded over FTP.
    Upload(param_upload::UploadSet),
    /// A validated upload's MISSION_ACK (mission, fence or rally plan).
    Mission {
        link: LinkKind,
        mission_type: MavMissionType,
        items: Vec<MISSION_ITEM_INT_DATA>,
    },
}

/// The MAVLink endpoint of one vehicle over one or more links; `A` is a peer address.
#[derive(Debug)]
pub struct LinkMachine<A> {
    identity: Identity,
    ports: Vec<Port<A>>,
    signing: Signing,
    signing_epoch: u64,
    key_store: bool,
    record_received: bool,
    params: ParamTable,
    snapshot: Snapshot,
    /// The plans as uploaded, for downloads; each replaced only when the vehicle took an upload.
    plans: PlanStore,
    /// What MISSION_CURRENT remembers (PX4's mission mode and state).
    report: MissionReport,
    pending: HashMap<Token, Pending<A>>,
    next_token: Token,
    param_lists: Vec<ParamList<A>>,
    /// Parameters changed and not yet announced on every link.
    changed_params: params::ChangedParams,
    /// The files served over MAVLink FTP and the FTP server of each link.
    files: Files<A>,
    /// The MAVLink shells of the clients that use one.
    consoles: Vec<console::Console<A>>,
    /// Where to announce each stored key's result, oldest first.
    keys_in_store: VecDeque<(LinkKind, A, bool)>,
    /// Wall time of the latest message of each [`InputStream`](crate::commander::InputStream) while it is alive in wall time [s].
    stream_heard_wall_s: [Option<f64>; 2],
    /// The link whose sticks are flown (`COM_RC_IN_MODE` 3 keeps the first).
    sticks_from: Option<LinkKind>,
    next_duty_s: f64,
    transmits: VecDeque<Transmit<A>>,
    to_vehicle: VecDeque<ToVehicle>,
    to_store: VecDeque<KeyToStore>,
    received: VecDeque<Vec<u8>>,
    /// The STATUSTEXTs said to one client, for the flight log (kept when logging).
    said: VecDeque<Said>,
}

/// A STATUSTEXT the link said to a client (a refusal, a calibration step, a signing change), for
/// the flight log; the commander's announcements to everyone are logged by the recorder.
#[derive(Debug, Clone, PartialEq)]
pub struct Said {
    /// Simulated time of the vehicle's latest tick [s].
    pub t_s: f64,
    /// MAV_SEVERITY (0 emergency … 7 debug).
    pub severity: u8,
    /// The text.
    pub text: String,
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
            .map(|(id, (kind, remote))| Port::new(*kind, *remote, id as u8))
            .collect();
        let kinds: Vec<LinkKind> = config.links.iter().map(|(kind, _)| *kind).collect();
        let files = Files::new(&config.params, metadata, &kinds, config.logs);
        Self {
            identity: config.identity,
            ports,
            signing: config.signing,
            signing_epoch: config.signing_epoch,
            key_store: config.key_store,
            record_received: config.record_received,
            params: config.params,
            snapshot: config.snapshot,
            plans: PlanStore::default(),
            report: MissionReport::default(),
            pending: HashMap::new(),
            next_token: 0,
            param_lists: Vec::new(),
            changed_params: params::ChangedParams::default(),
            files,
            consoles: Vec::new(),
            keys_in_store: VecDeque::new(),
            stream_heard_wall_s: [None; 2],
            sticks_from: None,
            next_duty_s: 0.0,
            transmits: VecDeque::new(),
            to_vehicle: VecDeque::new(),
            to_store: VecDeque::new(),
            received: VecDeque::new(),
            said: VecDeque::new(),
        }
    }

    /// The vehicle's latest state (telemetry, home, armed state for SETUP_SIGNING).
    pub fn handle_state(&mut self, snapshot: Snapshot) {
        self.report.handle_state(&snapshot, self.plans.ids());
        self.snapshot = snapshot;
    }

    /// A commander event, announced to every target of every link.
    pub fn handle_event(&mut self, now: Now, event: Event) {
        let msg = self.announcement(&event);
        self.broadcast(now, &msg);
    }

    /// A notice of the runtime (the logger's "[logger] ./log/…" when a flight log begins),
    /// announced as an information STATUSTEXT to every target of every link.
    pub fn handle_notice(&mut self, now: Now, text: &str) {
        self.broadcast(now, &super::telemetry::status_text(INFO, text));
    }

    /// The vehicle's answer to the request `token` named.
    pub fn handle_reply(&mut self, now: Now, token: Token, reply: VehicleReply) {
        match self.pending.remove(&token) {
            Some(Pending::Command(asker)) => {
                let outcome = match reply {
                    VehicleReply::Outcome(outcome) => outcome,
                    _ => Outcome::TemporarilyRejected("Vehicle busy".into()),
                };
                self.answer(now, asker, commands::AckOf::Outcome(&outcome));
            }
            Some(Pending::Param(set)) => self.param_set_done(now, set, reply),
            Some(Pending::Shell(set)) => self.shell_set_done(now, set, reply),
            Some(Pending::Upload(set)) => self.upload_set_done(now, set, reply),
            Some(Pending::Mission {
                link,
                mission_type,
                items,
            }) => self.mission_taken(now, link, mission_type, items, reply),
            None => {}
        }
    }

    /// The key file's answer to the oldest [`KeyToStore`].
    pub fn handle_stored(&mut self, now: Now, result: Result<(), String>) {
        if let Some((link, to, enabled)) = self.keys_in_store.pop_front() {
            let state = if enabled { "Signing enabled" } else { "Signing disabled" };
            let (severity, text) = match result {
                Ok(()) => (INFO, format!("{state}; key stored")),
                Err(_) => (WARNING, format!("{state}; key file not written")),
            };
            self.send(now, link, to, &super::telemetry::status_text(severity, &text));
        }
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
        self.param_lists
            .iter()
            .map(|l| l.next_s)
            .fold(self.next_duty_s, f64::min)
            .min(self.files.next_due_s().unwrap_or(f64::INFINITY))
            .min(self.changed_params.due_s.unwrap_or(f64::INFINITY))
    }

    /// The signing timestamp to persist [10 µs since 2015].
    pub fn signing_timestamp(&self) -> u64 {
        self.signing.timestamp()
    }

    /// Simulated time of the vehicle state the machine holds [s] (the clock its `Now` must use).
    pub fn state_time_s(&self) -> f64 {
        self.snapshot.t_s
    }

    /// Frames signing dropped so far (unsigned, wrongly signed or replayed).
    pub fn signing_dropped(&self) -> u64 {
        self.signing.dropped().total()
    }

    /// The mission as last uploaded.
    pub fn stored_mission(&self) -> &[MISSION_ITEM_INT_DATA] {
        self.plans.items(MavMissionType::MAV_MISSION_TYPE_MISSION)
    }

    /// Plan `mission_type` (mission, fence or rally) as last uploaded.
    pub fn stored_plan(&self, mission_type: MavMissionType) -> &[MISSION_ITEM_INT_DATA] {
        self.plans.items(mission_type)
    }

    /// A fresh token for a request whose answer is awaited.
    fn expect(&mut self, pending: Pending<A>) -> Token {
        let token = self.next_token;
        self.next_token += 1;
        self.pending.insert(token, pending);
        token
    }

    fn port(&mut self, link: LinkKind) -> Option<&mut Port<A>> {
        self.ports.iter_mut().find(|p| p.kind == link)
    }

    /// The signing clock at `now` [10 µs since 2015].
    fn signing_now(&self, now: Now) -> u64 {
        self.signing_epoch + (now.wall_s.max(0.0) * 1e5) as u64
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

    /// Queues a stream's `out` to `to` on `link`: a common message as [`Self::send`] does, a
    /// foreign one framed by hand (docs/mavlink.md §13.5).
    fn send_outgoing(&mut self, now: Now, link: LinkKind, to: A, out: &Outgoing) {
        match out {
            Outgoing::Message(msg) => self.send(now, link, to, msg),
            Outgoing::Foreign(m) => self.send_frame(now, link, to, |header| m.frame(header)),
        }
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
        if self.signing.enabled() {
            let stamp = self.signing_now(now);
            self.signing.seal(&mut frame, link_id, stamp);
        }
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
