//! COMMAND_LONG / COMMAND_INT: the duplicate check (information requests bypass the cache and
//! are answered every time), the decision, exactly one COMMAND_ACK to the sender, the message
//! a request asked for right after its ACK, a STATUSTEXT with the reason of a refusal, and the
//! `[cal]` STATUSTEXTs of a calibration after its ACK.

use std::hash::Hash;

use mavlink::dialects::common::{MavCmd, MavMessage, MavResult, COMMAND_LONG_DATA, MESSAGE_INTERVAL_DATA};
use mavlink::MavHeader;

use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleRequest, CRITICAL, INFO, WARNING};
use crate::commander::Outcome;
use crate::mav::calibration;
use crate::mav::duplicates::{CommandKey, Seen};
use crate::mav::modes::{available_modes, protocol_version};
use crate::mav::services::autopilot_version;
use crate::mav::telemetry::{status_text, Outgoing};
use crate::mav::translate::{command_ack, result_of, CommandDecision, OneShot};

/// What an ACK reports.
pub(super) enum AckOf<'a> {
    /// A result decided by the link.
    Result(MavResult),
    /// The vehicle's answer (a refusal also gets a STATUSTEXT with its reason).
    Outcome(&'a Outcome),
}

/// Who sent a command and what it was: where its ACK goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Asker<A> {
    pub link: LinkKind,
    pub to: A,
    pub header: MavHeader,
    pub command: MavCmd,
    pub key: CommandKey,
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// One command from `from` (a COMMAND_INT arrives as its COMMAND_LONG equivalent).
    pub(super) fn command(
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
        let Some(port) = self.port(link) else {
            return;
        };
        match port.duplicates.check(asker.key, now.wall_s) {
            Seen::InProgress => {}
            Seen::Answered(result) => self.send(now, link, from, &command_ack(header, cmd.command, result)),
            Seen::New => self.new_command(now, asker, decision),
        }
    }

    fn new_command(&mut self, now: Now, asker: Asker<A>, decision: CommandDecision) {
        let (link, from) = (asker.link, asker.to);
        let accepted = AckOf::Result(MavResult::MAV_RESULT_ACCEPTED);
        let denied = AckOf::Result(MavResult::MAV_RESULT_DENIED);
        match decision {
            CommandDecision::NotForUs => {}
            CommandDecision::Unsupported => {
                let unsupported = AckOf::Result(MavResult::MAV_RESULT_UNSUPPORTED);
                self.answer(now, asker, unsupported);
            }
            CommandDecision::NotSimulated(why) => {
                self.answer(now, asker, AckOf::Result(MavResult::MAV_RESULT_UNSUPPORTED));
                self.send(now, link, from, &status_text(WARNING, &why));
            }
            CommandDecision::Calibrate(calibration) => match calibration::run(calibration, self.snapshot.armed) {
                Err(refusal) => self.answer(now, asker, AckOf::Outcome(&refusal)),
                Ok(texts) => {
                    self.answer(now, asker, accepted);
                    for t in texts {
                        let severity = if t.critical { CRITICAL } else { INFO };
                        self.send(now, link, from, &status_text(severity, &t.text));
                    }
                }
            },
            CommandDecision::Refuse(outcome) => self.answer(now, asker, AckOf::Outcome(&outcome)),
            CommandDecision::Reply(one_shot) => {
                let common = |m: MavMessage| vec![Outgoing::Message(m)];
                let msgs = match one_shot {
                    OneShot::AutopilotVersion => Some(common(autopilot_version(&self.identity))),
                    OneShot::ProtocolVersion => Some(common(protocol_version())),
                    OneShot::ComponentMetadata => Some(common(self.component_metadata(now))),
                    OneShot::ComponentInformation => Some(common(self.component_information(now))),
                    OneShot::AvailableModes(index) => {
                        available_modes(index).map(|ms| ms.into_iter().map(Outgoing::Message).collect())
                    }
                    OneShot::TelemetryStream(stream) => self.stream_message(now, stream).map(|m| vec![m]),
                };
                match msgs {
                    Some(msgs) => {
                        self.answer(now, asker, accepted);
                        for msg in msgs {
                            self.send_outgoing(now, link, from, &msg);
                        }
                    }
                    // PX4 denies a request it sent nothing for (a mode index beyond the last).
                    None if matches!(one_shot, OneShot::AvailableModes(_)) => self.answer(now, asker, denied),
                    None => self.answer(now, asker, accepted),
                }
            }
            CommandDecision::SetMessageInterval {
                message_id,
                interval_us,
            } => {
                let set = self.port(link).map(|p| p.streams.set_interval(message_id, interval_us));
                let ack = if matches!(set, Some(Ok(()))) { accepted } else { denied };
                self.answer(now, asker, ack);
            }
            CommandDecision::GetMessageInterval { message_id } => {
                match self.port(link).and_then(|p| p.streams.interval_us(message_id)) {
                    Some(interval_us) => {
                        self.answer(now, asker, accepted);
                        let msg = MavMessage::MESSAGE_INTERVAL(MESSAGE_INTERVAL_DATA {
                            interval_us,
                            message_id: message_id as u16,
                        });
                        self.send(now, link, from, &msg);
                    }
                    None => self.answer(now, asker, denied),
                }
            }
            CommandDecision::Execute(request) => {
                let token = self.expect(Pending::Command(asker));
                self.to_vehicle.push_back(ToVehicle {
                    token: Some(token),
                    request: VehicleRequest::Commander(request),
                });
            }
        }
    }

    /// COMMAND_ACK to `to` (its result remembered for retransmissions), and a STATUSTEXT with
    /// the reason of a refusal.
    pub(super) fn answer(&mut self, now: Now, asker: Asker<A>, ack: AckOf) {
        let Asker {
            link,
            to,
            header,
            command,
            key,
        } = asker;
        let result = match &ack {
            AckOf::Result(r) => *r,
            AckOf::Outcome(o) => result_of(o),
        };
        if let Some(port) = self.port(link) {
            port.duplicates.answered(key, result, now.wall_s);
        }
        self.send(now, link, to, &command_ack(&header, command, result));
        if let AckOf::Outcome(
            Outcome::TemporarilyRejected(why) | Outcome::Denied(why) | Outcome::Unsupported(why) | Outcome::Failed(why),
        ) = ack
        {
            self.send(now, link, to, &status_text(WARNING, why));
        }
    }
}
