//! COMMAND_LONG / COMMAND_INT and the requests the link waits for: [`CommandService`] owns the
//! duplicate check of each link (information requests bypass the cache and are answered every
//! time), exactly one COMMAND_ACK to the sender, the messages a request asked for right after
//! its ACK, a STATUSTEXT with the reason of a refusal, the `[cal]` STATUSTEXTs of a calibration
//! after its ACK; and the tokens naming every request whose answer the link awaits
//! ([`Pending`]: a command's ACK, a PARAM_SET's echo, a shell's `param set`, an uploaded
//! parameter, a plan upload).

use std::collections::HashMap;

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavMissionType, MavResult, MISSION_ITEM_INT_DATA};
use mavlink::MavHeader;

use super::boundary::{Token, VehicleRequest};
use super::console::ShellSet;
use super::effects::Effect;
use super::param_service::ParamSet;
use super::param_upload::UploadSet;
use super::{LinkKind, WARNING};
use crate::commander::{Outcome, Request};
use crate::mav::duplicates::{CommandKey, DuplicateCache, Seen};
use crate::mav::stream_messages::status_text;
use crate::mav::translate::{command_ack, result_of};

/// What the machine waits for from the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Pending<A> {
    /// A command's ACK.
    Command(Asker<A>),
    /// ArduCopter's ACK of a SET_MODE message, to this client (link, address, MAVLink ids).
    SetMode(super::effects::Client<A>),
    /// A PARAM_SET's echo.
    Param(ParamSet<A>),
    /// A shell's `param set`.
    Shell(ShellSet<A>),
    /// One parameter of a file uploaded over FTP.
    Upload(UploadSet),
    /// A validated upload's MISSION_ACK (mission, fence or rally plan).
    Mission {
        /// The link of the upload.
        link: LinkKind,
        /// Mission, fence or rally.
        mission_type: MavMissionType,
        /// The plan as uploaded.
        items: Vec<MISSION_ITEM_INT_DATA>,
    },
}

/// What an ACK reports.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum AckOf {
    /// A result decided by the link.
    Result(MavResult),
    /// The vehicle's answer (a refusal also gets a STATUSTEXT with its reason).
    Outcome(Outcome),
}

/// A new command as decided with what the link knows (the vehicle's state, the streams).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Decided {
    /// Answered at once: the ACK, then these messages to the sender.
    Answer(AckOf, Vec<MavMessage>),
    /// For the vehicle: the ACK waits for its outcome.
    Execute(Request),
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

/// The commands of every link and the requests awaited from the vehicle.
#[derive(Debug)]
pub(super) struct CommandService<A> {
    /// The duplicate-command cache of each link.
    duplicates: Vec<(LinkKind, DuplicateCache)>,
    /// The requests whose answer is awaited.
    pending: HashMap<Token, Pending<A>>,
    next_token: Token,
}

impl<A: Copy> CommandService<A> {
    /// No command seen yet on `links`.
    pub fn new(links: &[LinkKind]) -> Self {
        Self {
            duplicates: links.iter().map(|l| (*l, DuplicateCache::default())).collect(),
            pending: HashMap::new(),
            next_token: 0,
        }
    }

    /// A fresh token for a request whose answer is awaited as `pending`.
    pub fn expect(&mut self, pending: Pending<A>) -> Token {
        let token = self.next_token;
        self.next_token += 1;
        self.pending.insert(token, pending);
        token
    }

    /// What `token` named, once (`None`: unknown or already answered).
    pub fn take(&mut self, token: Token) -> Option<Pending<A>> {
        self.pending.remove(&token)
    }

    fn cache(&mut self, link: LinkKind) -> Option<&mut DuplicateCache> {
        self.duplicates.iter_mut().find(|(l, _)| *l == link).map(|(_, c)| c)
    }

    /// The duplicate check of `asker`'s command at wall time `wall_s` [s]: `Ok` for a new one
    /// (to decide), `Err` with what a repeat gets (its remembered ACK, or nothing while it is in
    /// progress or on a link without a cache).
    pub fn check(&mut self, wall_s: f64, asker: &Asker<A>) -> Result<(), Vec<Effect<A>>> {
        let Some(cache) = self.cache(asker.link) else {
            return Err(Vec::new());
        };
        match cache.check(asker.key, wall_s) {
            Seen::InProgress => Err(Vec::new()),
            Seen::Answered(result) => Err(vec![Effect::send(
                asker.link,
                asker.to,
                command_ack(&asker.header, asker.command, result),
            )]),
            Seen::New => Ok(()),
        }
    }

    /// What a new command decided as `decided` brings at wall time `wall_s` [s].
    pub fn decide(&mut self, wall_s: f64, asker: Asker<A>, decided: Decided) -> Vec<Effect<A>> {
        match decided {
            Decided::Answer(ack, then) => {
                let (link, to) = (asker.link, asker.to);
                let mut out = self.answer(wall_s, asker, ack);
                out.extend(then.into_iter().map(|m| Effect::To(link, to, m)));
                out
            }
            Decided::Execute(request) => {
                vec![Effect::Ask(
                    Some(Pending::Command(asker)),
                    VehicleRequest::Commander(request),
                )]
            }
        }
    }

    /// COMMAND_ACK to the asker (its result remembered for retransmissions at wall time
    /// `wall_s` [s]), and a STATUSTEXT with the reason of a refusal.
    pub fn answer(&mut self, wall_s: f64, asker: Asker<A>, ack: AckOf) -> Vec<Effect<A>> {
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
        if let Some(cache) = self.cache(link) {
            cache.answered(key, result, wall_s);
        }
        let mut out = vec![Effect::send(link, to, command_ack(&header, command, result))];
        if let AckOf::Outcome(
            Outcome::TemporarilyRejected(why) | Outcome::Denied(why) | Outcome::Unsupported(why) | Outcome::Failed(why),
        ) = ack
        {
            out.push(Effect::send(link, to, status_text(WARNING, &why)));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use mavlink::dialects::ardupilotmega::{MavMessage, COMMAND_LONG_DATA};

    use super::*;
    use crate::mav::gcs::gcs_header;

    fn asker(command: MavCmd) -> Asker<u16> {
        let header = gcs_header(0);
        let cmd = COMMAND_LONG_DATA {
            command,
            target_system: 1,
            ..Default::default()
        };
        Asker {
            link: LinkKind::Gcs,
            to: 7,
            header,
            command,
            key: CommandKey::new(&header, &cmd),
        }
    }

    fn acks(out: &[Effect<u16>]) -> Vec<MavResult> {
        out.iter()
            .filter_map(|e| match e {
                Effect::To(_, 7, MavMessage::COMMAND_ACK(a)) => Some(a.result),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_repeat_gets_the_remembered_ack_and_a_refusal_says_why() {
        let mut c = CommandService::new(&[LinkKind::Gcs]);
        let arm = asker(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM);
        assert_eq!(c.check(0.0, &arm), Ok(()));
        assert_eq!(c.check(0.1, &arm), Err(Vec::new()), "in progress: nothing yet");
        let out = c.answer(0.2, arm, AckOf::Result(MavResult::MAV_RESULT_ACCEPTED));
        assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
        let repeat = c.check(0.3, &arm).unwrap_err();
        assert_eq!(acks(&repeat), vec![MavResult::MAV_RESULT_ACCEPTED]);

        let land = asker(MavCmd::MAV_CMD_NAV_LAND);
        assert_eq!(c.check(0.0, &land), Ok(()));
        let out = c.answer(0.0, land, AckOf::Outcome(Outcome::Denied("not armed".into())));
        assert_eq!(out.len(), 2, "ACK, then the reason");
        assert_eq!(c.check(0.1, &land), Ok(()), "a refusal is not remembered");
        let other_link = Asker {
            link: LinkKind::Api,
            ..land
        };
        assert_eq!(c.check(0.1, &other_link), Err(Vec::new()), "no cache, no answer");
    }

    #[test]
    fn tokens_name_each_awaited_request_once() {
        let mut c = CommandService::new(&[LinkKind::Gcs]);
        let arm = asker(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM);
        let out = c.decide(0.0, arm, Decided::Execute(Request::Disarm { force: false }));
        let Some(Effect::Ask(Some(pending), _)) = out.into_iter().next() else {
            panic!("the command goes to the vehicle");
        };
        let (a, b) = (c.expect(pending.clone()), c.expect(pending.clone()));
        assert_eq!((a, b), (0, 1));
        assert_eq!(c.take(a), Some(pending));
        assert_eq!(c.take(a), None);
        assert!(c.take(b).is_some());
    }
}
