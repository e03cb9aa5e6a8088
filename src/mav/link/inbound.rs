//! A datagram in: every frame through the signing check (with a key, only signed frames with
//! fresh timestamps pass, and HEARTBEAT-like ones unsigned), trusted frames make their sender a
//! peer, each message goes through [`ingest`] and its [`Action`] is handed to the part that
//! owns it. A new command is decided here with what the machine knows (the vehicle's state,
//! the link's streams, the metadata files) and answered by the command service.

use std::hash::Hash;

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionType, MavResult, COMMAND_LONG_DATA, MESSAGE_INTERVAL_DATA,
};
use mavlink::MavHeader;

use super::commands::{AckOf, Asker, Decided, Pending};
use super::effects::{Client, Effect};
use super::port::{HeldForClients, Port};
use super::{LinkKind, LinkMachine, Now, ToVehicle, VehicleRequest, CRITICAL, INFO, WARNING};
use crate::commander::{ManualInputMode, Outcome, Request};
use crate::mav::ardupilot::copter_ingest::{asked_mode, copter_ingest};
use crate::mav::ardupilot::copter_link_params::{LinkParams, LinkSet};
use crate::mav::ardupilot::copter_streams::CopterGroup;
use crate::mav::calibration;
use crate::mav::codec::{command_ack_frame, decode_datagram_checked, encode_v2, unsupported_command_ack, Inbound};
use crate::mav::duplicates::CommandKey;
use crate::mav::identity::Personality;
use crate::mav::ingest::{ingest, Action};
use crate::mav::param_encoding::Shown;
use crate::mav::services::autopilot_version;
use crate::mav::signing::Verdict;
use crate::mav::standard_modes::{available_modes, protocol_version};
use crate::mav::stream_messages::status_text;
use crate::mav::translate::{result_of, CommandDecision, OneShot};

/// SET_MODE's message id: ArduCopter's ACK of the message names it as the command.
const SET_MODE_ID: u16 = 11;

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
        self.consoles.keep_clients(link, &targets);
        self.parameters.keep_clients(link, &targets);
    }

    /// What the machine keeps for its clients now (bounded whatever they send).
    pub fn held_for_clients(&self) -> HeldForClients {
        HeldForClients {
            peers: self.ports.iter().map(Port::peer_count).sum(),
            shells: self.consoles.count(),
            param_lists: self.parameters.list_count(),
        }
    }

    /// One datagram from `from` on `link`.
    pub fn handle_datagram(&mut self, now: Now, link: LinkKind, from: A, bytes: &[u8]) {
        let stamp = self.keys.now(now.wall_s);
        let keys = &mut self.keys;
        let frames = decode_datagram_checked(bytes, |raw| match keys.check(raw, stamp) {
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
                        let action = self.ingest_as_personality(now, &header, &message);
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

    /// What the vehicle's personality does with `message`: ArduCopter's face decides first the
    /// messages Copter reads its own way (and notes the mode a ground station asks for, which
    /// the HEARTBEAT shows while the commander flies it); the rest as [`ingest`] decides.
    fn ingest_as_personality(&mut self, now: Now, header: &MavHeader, message: &MavMessage) -> Action {
        let now_ns = (now.wall_s * 1e9) as i64;
        if self.identity.personality == Personality::ArduPilot {
            if let Some(number) = asked_mode(&self.identity, header, message) {
                self.mode_shown.handle_asked(number);
            }
            let mission = self.plans.items(MavMissionType::MAV_MISSION_TYPE_MISSION);
            let throttle = self.rc.throttle(now.sim_s, &self.snapshot);
            if let Some(action) = copter_ingest(&self.identity, header, message, &self.snapshot, mission, throttle) {
                return action;
            }
        }
        ingest(&self.identity, header, message, &self.snapshot.home, now_ns)
    }

    /// COMMAND_ACK UNSUPPORTED for a command id the dialect does not know (built from the raw id).
    fn unsupported(&mut self, now: Now, link: LinkKind, to: A, sender: &MavHeader, command: u16) {
        let (system, component) = (sender.system_id as u8, sender.component_id);
        self.send_frame(now, link, to, |ours| {
            unsupported_command_ack(ours, command, system, component)
        });
    }

    /// ArduCopter's answer to a SET_MODE message from `client` (`GCS_MAVLINK::handle_set_mode`):
    /// the reason of a refusal (a STATUSTEXT warning, "Mode change to … failed: …"), then a
    /// COMMAND_ACK whose command is the message id, 11.
    pub(super) fn answer_set_mode(&mut self, now: Now, (link, to, ids): Client<A>, ack: AckOf) {
        let result = match &ack {
            AckOf::Result(r) => *r,
            AckOf::Outcome(o) => result_of(o),
        };
        if let AckOf::Outcome(
            Outcome::TemporarilyRejected(why) | Outcome::Denied(why) | Outcome::Unsupported(why) | Outcome::Failed(why),
        ) = &ack
        {
            self.send(now, link, to, &status_text(WARNING, why));
        }
        self.send_frame(now, link, to, |ours| command_ack_frame(ours, SET_MODE_ID, result, ids));
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
        let ids = (header.system_id as u8, header.component_id);
        let effects = match action {
            Action::Ignore => Vec::new(),
            Action::GcsHeartbeat => {
                if let Some(port) = self.port(link) {
                    port.gcs_heard = Some((now.wall_s, now.sim_s));
                }
                Vec::new()
            }
            Action::Command { command, decision } => return self.command(now, link, from, header, &command, decision),
            // Setpoints and SET_MODE get no answer: the next heartbeat shows the result.
            Action::Request(request) => {
                if matches!(request, Request::ManualControl(_)) && !self.flies_sticks_from(link) {
                    return;
                }
                if let (Request::ManualControl(sticks), Personality::ArduPilot) = (&request, self.identity.personality)
                {
                    // ArduCopter reads MANUAL_CONTROL as overrides of its stick channels.
                    let request = self.rc.handle_sticks(*sticks, now.sim_s, &self.snapshot);
                    return self.ask_commander(now, [request]);
                }
                let stream = request.input_stream();
                self.to_vehicle.push_back(ToVehicle {
                    token: None,
                    request: VehicleRequest::Commander(request),
                });
                if let Some(stream) = stream {
                    self.streams.heard(stream, now.wall_s, now.sim_s);
                }
                Vec::new()
            }
            Action::SetModeMessage(decision) => match self.decide(now, link, decision) {
                Decided::Answer(ack, then) => {
                    self.answer_set_mode(now, (link, from, ids), ack);
                    then.into_iter().map(|m| Effect::send(link, from, m)).collect()
                }
                Decided::Execute(request) => vec![Effect::Ask(
                    Some(Pending::SetMode((link, from, ids))),
                    VehicleRequest::Commander(request),
                )],
            },
            Action::RcOverride(o) => {
                let request = self.rc.handle_override(&o, now.sim_s, &self.snapshot);
                return self.ask_commander(now, [request]);
            }
            Action::Refuse(why) => return self.send(now, link, from, &status_text(WARNING, &why)),
            Action::Reply(msg) => return self.send(now, link, from, &msg),
            Action::DataStream {
                stream_id,
                rate_hz,
                start,
            } => {
                if let Some(port) = self.port(link) {
                    port.streams.request_data_stream(stream_id, rate_hz, start);
                }
                // ArduCopter's `@PARAM/param.pck` shows the group rates (SRn_*).
                self.files.params_changed();
                Vec::new()
            }
            Action::Ftp(payload) => {
                let held = self.link_params();
                let shown = Shown {
                    personality: self.identity.personality,
                    table: &self.params,
                    link: &held,
                };
                self.files.ftp(now.wall_s, (link, from, ids), &payload, shown)
            }
            Action::Log(request) => {
                let store = self.files.log_store();
                self.logs.request(now.wall_s, link, from, request, store)
            }
            Action::Shell(msg) => self
                .consoles
                .serial((link, from, ids), &msg, &self.params, &self.snapshot),
            Action::ParamList => {
                self.parameters.request_list(link, from, now.wall_s);
                Vec::new()
            }
            Action::ParamRead { name, index } => {
                let held = self.link_params();
                self.parameters
                    .read((link, from, header), &name, index, (&self.params, &held))
            }
            Action::ParamSet { name, value } => {
                let held = self.link_params();
                self.parameters
                    .set((link, from, header), name, value, (&self.params, &held))
            }
            Action::Mission { ids, step } => self.plans.step(now.wall_s, (link, from, ids), step, &self.snapshot),
            Action::SetupSigning { key, initial_timestamp } => {
                self.keys
                    .setup((link, from), key, initial_timestamp, self.snapshot.armed)
            }
        };
        self.carry_out(now, effects);
    }

    /// One command from `from` (a COMMAND_INT arrives as its COMMAND_LONG equivalent): a
    /// repeat gets what the command service remembers, a new one is decided.
    fn command(
        &mut self,
        now: Now,
        link: LinkKind,
        from: A,
        header: &MavHeader,
        cmd: &COMMAND_LONG_DATA,
        decision: CommandDecision,
    ) {
        if decision == CommandDecision::NotForUs {
            return;
        }
        let asker = Asker {
            link,
            to: from,
            header: *header,
            command: cmd.command,
            key: CommandKey::new(header, cmd),
        };
        let effects = match self.commands.check(now.wall_s, &asker) {
            Err(repeat) => repeat,
            Ok(()) => {
                let decided = self.decide(now, link, decision);
                self.commands.decide(now.wall_s, asker, decided)
            }
        };
        self.carry_out(now, effects);
    }

    /// A new command's decision completed with what the machine knows: the vehicle's state, the
    /// messages a request asks for, the link's streams.
    fn decide(&mut self, now: Now, link: LinkKind, decision: CommandDecision) -> Decided {
        let accepted = AckOf::Result(MavResult::MAV_RESULT_ACCEPTED);
        let denied = AckOf::Result(MavResult::MAV_RESULT_DENIED);
        let unsupported = AckOf::Result(MavResult::MAV_RESULT_UNSUPPORTED);
        let common = |m: MavMessage| vec![m];
        match decision {
            CommandDecision::NotForUs | CommandDecision::Unsupported => Decided::Answer(unsupported, Vec::new()),
            CommandDecision::NotSimulated(why) => Decided::Answer(unsupported, common(status_text(WARNING, &why))),
            CommandDecision::Calibrate(calibration) => match calibration::run(calibration, self.snapshot.armed) {
                Err(refusal) => Decided::Answer(AckOf::Outcome(refusal), Vec::new()),
                Ok(texts) => {
                    let said = texts.into_iter().map(|t| {
                        let severity = if t.critical { CRITICAL } else { INFO };
                        status_text(severity, &t.text)
                    });
                    Decided::Answer(accepted, said.collect())
                }
            },
            CommandDecision::Refuse(outcome) => Decided::Answer(AckOf::Outcome(outcome), Vec::new()),
            CommandDecision::Reply(OneShot::TelemetryStream(stream))
                if !self.port(link).is_some_and(|p| p.streams.offers(stream)) =>
            {
                // ArduPilot's own messages on a PX4-faced link: refused as any unknown message.
                let why = format!("Message {} not available", stream.message_id());
                Decided::Answer(AckOf::Outcome(Outcome::Denied(why)), Vec::new())
            }
            CommandDecision::Critical(why) => Decided::Answer(
                AckOf::Result(MavResult::MAV_RESULT_FAILED),
                common(status_text(CRITICAL, &why)),
            ),
            CommandDecision::Reply(one_shot) => {
                let msgs = match one_shot {
                    OneShot::AutopilotVersion => Some(common(autopilot_version(&self.identity))),
                    OneShot::ProtocolVersion => Some(common(protocol_version())),
                    OneShot::ComponentMetadata => Some(common(self.files.component_metadata(now.wall_s))),
                    OneShot::ComponentInformation => Some(common(self.files.component_information(now.wall_s))),
                    OneShot::AvailableModes(index) => available_modes(index).map(|ms| ms.into_iter().collect()),
                    OneShot::TelemetryStream(stream) => self.stream_message(now, stream).map(|m| vec![m]),
                };
                match msgs {
                    Some(msgs) => Decided::Answer(accepted, msgs),
                    // PX4 denies a request it sent nothing for (a mode index beyond the last).
                    None if matches!(one_shot, OneShot::AvailableModes(_)) => Decided::Answer(denied, Vec::new()),
                    None => Decided::Answer(accepted, Vec::new()),
                }
            }
            CommandDecision::SetMessageInterval {
                message_id,
                interval_us,
            } => {
                let set = self.port(link).map(|p| p.streams.set_interval(message_id, interval_us));
                let ack = if matches!(set, Some(Ok(()))) { accepted } else { denied };
                Decided::Answer(ack, Vec::new())
            }
            CommandDecision::GetMessageInterval { message_id } => {
                match self.port(link).and_then(|p| p.streams.interval_us(message_id)) {
                    Some(interval_us) => {
                        let msg = MavMessage::MESSAGE_INTERVAL(MESSAGE_INTERVAL_DATA {
                            interval_us,
                            message_id: message_id as u16,
                        });
                        Decided::Answer(accepted, common(msg))
                    }
                    None => Decided::Answer(denied, Vec::new()),
                }
            }
            CommandDecision::Execute(request) => Decided::Execute(request),
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

    /// What the link holds that ArduCopter shows as parameters, read from it: the system id and
    /// each link's group rates, SR0 the first link.
    pub(super) fn link_params(&self) -> LinkParams {
        LinkParams {
            system_id: self.identity.system_id,
            stream_rates: self
                .ports
                .iter()
                .map(|p| CopterGroup::ALL.map(|g| p.streams.group_rate(g)))
                .collect(),
        }
    }

    /// The parameters as the vehicle shows them, `held` what the link holds.
    pub(super) fn shown<'a>(&'a self, held: &'a LinkParams) -> Shown<'a> {
        Shown {
            personality: self.identity.personality,
            table: &self.params,
            link: held,
        }
    }

    /// A PARAM_SET of what the link holds from `to` on `link` (parameter `index`): carried out,
    /// then the value announced as ArduCopter announces a change (docs/ardupilot.md §5.2).
    pub(super) fn link_set(&mut self, now: Now, (link, to): (LinkKind, A), change: LinkSet, index: usize) {
        if let LinkSet::StreamRate {
            link: n,
            group,
            rate_hz,
        } = change
        {
            if let Some(port) = self.ports.get_mut(n) {
                port.streams.set_group_rate(group, rate_hz);
            }
            self.files.params_changed();
        }
        let held = self.link_params();
        if let Some(msg) = self.shown(&held).announced_value(index) {
            if !self.targets(link).contains(&to) {
                self.send(now, link, to, &msg);
            }
            self.broadcast(now, &msg);
        }
    }
}
