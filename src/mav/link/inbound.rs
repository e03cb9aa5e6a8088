//! A datagram in: every frame through the signing check (with a key, only signed frames with
//! fresh timestamps pass, and HEARTBEAT-like ones unsigned), trusted frames make their sender a
//! peer, each message goes through [`ingest`] and its [`Action`] is carried out here or in
//! the module that owns it. SETUP_SIGNING is handled here too.

use std::hash::Hash;

use mavlink::dialects::common::MavMessage;
use mavlink::MavHeader;

use super::params::ParamList;
use super::port::{HeldForClients, Port, MAX_PEERS};
use super::{KeyToStore, LinkKind, LinkMachine, Now, ToVehicle, VehicleRequest, INFO, WARNING};
use crate::commander::{InputStream, ManualInputMode, Request};
use crate::mav::codec::{decode_datagram_checked, encode_v2, unsupported_command_ack, Inbound};
use crate::mav::ingest::{ingest, Action};
use crate::mav::signing::{SigningKey, Verdict};
use crate::mav::telemetry::status_text;

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// `from` sent a trusted frame on `link`: a peer now, if there is room for it.
    fn heard(&mut self, now: Now, link: LinkKind, from: A) {
        let evicted = self.port(link).and_then(|port| port.heard(from, now.wall_s));
        if let Some(gone) = evicted {
            self.forget_peers(link, &[gone]);
        }
    }

    /// Frees what was kept for the peers `gone` of `link`, and for any client of it that is
    /// not one of its targets (one the full peer table did not take): their shells and
    /// parameter lists.
    pub(super) fn forget_peers(&mut self, link: LinkKind, gone: &[A]) {
        if gone.is_empty() {
            return;
        }
        let targets = self.port(link).map(|p| p.targets()).unwrap_or_default();
        let kept = |l: LinkKind, a: &A| l != link || targets.contains(a);
        self.consoles.retain(|c| kept(c.link, &c.from));
        self.param_lists.retain(|l| kept(l.link, &l.to));
    }

    /// What the machine keeps for its clients now (bounded whatever they send).
    pub fn held_for_clients(&self) -> HeldForClients {
        HeldForClients {
            peers: self.ports.iter().map(Port::peer_count).sum(),
            shells: self.consoles.len(),
            param_lists: self.param_lists.len(),
        }
    }

    /// One datagram from `from` on `link`.
    pub fn handle_datagram(&mut self, now: Now, link: LinkKind, from: A, bytes: &[u8]) {
        let stamp = self.signing_now(now);
        let signing = &mut self.signing;
        let frames = decode_datagram_checked(bytes, |raw| match signing.check(raw, stamp) {
            Verdict::Dropped(_) => None,
            verdict => Some(verdict == Verdict::Trusted),
        });
        for (frame, trusted) in frames {
            match frame {
                // An unsigned HEARTBEAT while signing is on is only recorded: it neither
                // registers a peer nor counts as a ground station's liveness.
                Inbound::Message { header, message, .. } => {
                    self.record(header, &message);
                    if trusted {
                        self.heard(now, link, from);
                        let now_ns = (now.wall_s * 1e9) as i64;
                        let action = ingest(&self.identity, &header, &message, &self.snapshot.home, now_ns);
                        self.act(now, link, from, &header, action);
                    }
                }
                Inbound::UnknownCommand {
                    header,
                    command,
                    target_system,
                    target_component,
                } if trusted => {
                    self.heard(now, link, from);
                    if self.identity.accepts(&header, target_system, target_component) {
                        self.unsupported(now, link, from, &header, command);
                    }
                }
                Inbound::UnknownCommand { .. } | Inbound::Unparsable { .. } => {}
            }
        }
    }

    /// COMMAND_ACK UNSUPPORTED for a command id the dialect does not know (built from the raw id).
    fn unsupported(&mut self, now: Now, link: LinkKind, to: A, sender: &MavHeader, command: u16) {
        let (system, component) = (sender.system_id as u8, sender.component_id);
        self.send_frame(now, link, to, |ours| {
            unsupported_command_ack(ours, command, system, component)
        });
    }

    /// A received message for the tlog, re-encoded; SETUP_SIGNING never (it carries the key).
    fn record(&mut self, header: MavHeader, message: &MavMessage) {
        if self.record_received && !matches!(message, MavMessage::SETUP_SIGNING(_)) {
            let mut frame = Vec::with_capacity(300);
            encode_v2(header, message, &mut frame);
            self.received.push_back(frame);
        }
    }

    /// Carries out what [`ingest`] decided for one message from `from`.
    fn act(&mut self, now: Now, link: LinkKind, from: A, header: &MavHeader, action: Action) {
        match action {
            Action::Ignore => {}
            Action::GcsHeartbeat => {
                if let Some(port) = self.port(link) {
                    port.gcs_heard = Some((now.wall_s, now.sim_s));
                }
            }
            Action::Command { command, decision } => self.command(now, link, from, header, &command, decision),
            // Setpoints and SET_MODE get no answer: the next heartbeat shows the result.
            Action::Request(request) => {
                let stream = match request {
                    Request::OffboardSetpoint { .. } | Request::OffboardAttitude(_) => Some(InputStream::Offboard),
                    Request::ManualControl(_) if !self.flies_sticks_from(link) => return,
                    Request::ManualControl(_) => Some(InputStream::ManualControl),
                    _ => None,
                };
                self.to_vehicle.push_back(ToVehicle {
                    token: None,
                    request: VehicleRequest::Commander(request),
                });
                if let Some(stream) = stream {
                    self.heard_stream(stream, now);
                }
            }
            Action::Refuse(why) => self.send(now, link, from, &status_text(WARNING, &why)),
            Action::Reply(msg) => self.send(now, link, from, &msg),
            Action::DataStream {
                stream_id,
                rate_hz,
                start,
            } => {
                if let Some(port) = self.port(link) {
                    port.streams.request_data_stream(stream_id, rate_hz, start);
                }
            }
            Action::Ftp(payload) => self.ftp(now, link, from, header, &payload),
            Action::Log(request) => self.log_request(now, link, from, request),
            Action::Shell(msg) => self.shell(now, link, from, header, &msg),
            Action::ParamList => {
                self.param_lists.retain(|l| !(l.link == link && l.to == from));
                // One list per peer the link can have: beyond, the oldest request is dropped.
                if self.param_lists.iter().filter(|l| l.link == link).count() > MAX_PEERS {
                    if let Some(oldest) = self.param_lists.iter().position(|l| l.link == link) {
                        self.param_lists.remove(oldest);
                    }
                }
                self.param_lists.push(ParamList::new(link, from, now.wall_s));
            }
            Action::ParamRead { name, index } => self.param_read(now, link, from, header, &name, index),
            Action::ParamSet { name, value } => self.param_set(link, from, header, name, value),
            Action::Mission { ids, step } => self.mission(now, link, from, ids, step),
            Action::SetupSigning { key, initial_timestamp } => {
                self.setup_signing(now, link, from, key, initial_timestamp)
            }
        }
    }

    /// Whether MANUAL_CONTROL from `link` is flown (`COM_RC_IN_MODE`): never for "RC only" and
    /// "disabled" (this vehicle has no RC receiver); from the first link heard for "keep first";
    /// from any link otherwise.
    fn flies_sticks_from(&mut self, link: LinkKind) -> bool {
        match self.params.current().commander.manual.input_mode {
            ManualInputMode::RcOnly | ManualInputMode::Disabled => false,
            ManualInputMode::MavlinkOnly | ManualInputMode::Fallback => true,
            ManualInputMode::KeepFirst => *self.sticks_from.get_or_insert(link) == link,
        }
    }

    /// SETUP_SIGNING: refused while armed; otherwise the key (all zero: off) applies at once to
    /// every link, and is stored when there is a key file. It reached here only unsigned with
    /// no key set, or signed with the current key.
    fn setup_signing(&mut self, now: Now, link: LinkKind, from: A, key: SigningKey, initial_timestamp: u64) {
        if self.snapshot.armed {
            self.send(
                now,
                link,
                from,
                &status_text(WARNING, "SETUP_SIGNING refused: disarm first"),
            );
            return;
        }
        self.signing.set_key(key.clone(), initial_timestamp);
        let enabled = self.signing.enabled();
        if self.key_store {
            self.to_store.push_back(KeyToStore {
                key: enabled.then_some(key),
                timestamp: self.signing.timestamp(),
            });
            self.keys_in_store.push_back((link, from, enabled));
        } else {
            let state = if enabled { "Signing enabled" } else { "Signing disabled" };
            self.send(now, link, from, &status_text(INFO, &format!("{state} until restart")));
        }
    }
}
