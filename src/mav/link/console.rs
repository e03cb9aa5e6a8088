//! The MAVLink shell on the links: one line buffer per client (link and address); what is typed
//! is echoed at once, each line run by [`shell::run`] against the latest snapshot and parameter
//! table, the answer and the prompt sent back in SERIAL_CONTROL replies to the client's ids;
//! `param set` goes to the vehicle as a PARAM_SET does and is answered (with the PARAM_VALUE to
//! the link's peers), then prompted, when the vehicle replies.

use std::hash::Hash;

use mavlink::dialects::common::{SerialControlFlag, SERIAL_CONTROL_DATA};
use mavlink::MavHeader;

use super::port::MAX_PEERS;
use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleReply, VehicleRequest};
use crate::mav::params::param_value;
use crate::mav::shell::{self, frames, param_set_text, Context, LineBuffer, ShellOutcome, Typed, PROMPT};
use crate::params::ParamTable;

/// One client's shell.
#[derive(Debug)]
pub(super) struct Console<A> {
    pub(super) link: LinkKind,
    pub(super) from: A,
    input: LineBuffer,
}

/// A `param set` typed in a shell, waiting for the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ShellSet<A> {
    link: LinkKind,
    to: A,
    ids: (u8, u8),
    name: String,
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// SERIAL_CONTROL for the shell from `from`: without RESPOND the client is done (the shell
    /// closes, as PX4's does); otherwise its bytes are typed (and echoed) and every complete line
    /// answered.
    pub(super) fn shell(&mut self, now: Now, link: LinkKind, from: A, sender: &MavHeader, msg: &SERIAL_CONTROL_DATA) {
        let ids = (sender.system_id as u8, sender.component_id);
        let at = self.consoles.iter().position(|c| c.link == link && c.from == from);
        if !msg.flags.contains(SerialControlFlag::SERIAL_CONTROL_FLAG_RESPOND) {
            if let Some(k) = at {
                self.consoles.remove(k);
            }
            return;
        }
        let k = at.unwrap_or_else(|| {
            // One shell per peer the link can have: a new client closes the oldest one beyond.
            if self.consoles.iter().filter(|c| c.link == link).count() > MAX_PEERS {
                if let Some(oldest) = self.consoles.iter().position(|c| c.link == link) {
                    self.consoles.remove(oldest);
                }
            }
            self.consoles.push(Console {
                link,
                from,
                input: LineBuffer::default(),
            });
            self.consoles.len() - 1
        });
        let count = usize::from(msg.count).min(msg.data.len());
        let typed = self.consoles[k].input.push(&msg.data[..count]);
        // The echo and the answers of one frame go out together.
        let mut said = String::new();
        for t in typed {
            let line = match t {
                Typed::Echo(echo) => {
                    said += &echo;
                    continue;
                }
                Typed::Line(line) => line,
            };
            let ctx = Context {
                params: &self.params,
                snapshot: &self.snapshot,
            };
            match shell::run(&line, ctx) {
                ShellOutcome::Text(text) => said += &format!("\n{text}{PROMPT}"),
                ShellOutcome::SetParam { name, value } => {
                    said.push('\n');
                    self.type_out(now, link, from, ids, &std::mem::take(&mut said));
                    let token = self.expect(Pending::Shell(ShellSet {
                        link,
                        to: from,
                        ids,
                        name: name.clone(),
                    }));
                    self.to_vehicle.push_back(ToVehicle {
                        token: Some(token),
                        request: VehicleRequest::SetParam { name, value },
                    });
                }
            }
        }
        self.type_out(now, link, from, ids, &said);
    }

    /// The vehicle's answer to a shell's `param set`.
    pub(super) fn shell_set_done(&mut self, now: Now, set: ShellSet<A>, reply: VehicleReply) {
        let ShellSet { link, to, ids, name } = set;
        let before: ParamTable = self.params.clone();
        let result = match reply {
            VehicleReply::Param { result, table } => {
                self.take_table(*table);
                result.map_err(|e| e.to_string())
            }
            _ => Err("vehicle busy, try again".to_string()),
        };
        if let Ok(index) = result {
            if let Some(msg) = param_value(&self.params, index) {
                for target in self.port(link).map(|p| p.targets()).unwrap_or_default() {
                    self.send(now, link, target, &msg);
                }
            }
        }
        let text = param_set_text(&before, &self.params, &name, result.map(|_| ()));
        self.type_out(now, link, to, ids, &format!("{text}{PROMPT}"));
    }

    fn type_out(&mut self, now: Now, link: LinkKind, to: A, ids: (u8, u8), text: &str) {
        for msg in frames(ids, text) {
            self.send(now, link, to, &msg);
        }
    }
}
