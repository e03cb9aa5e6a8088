//! The MAVLink shell on the links: one line buffer per client (link and address); what is typed
//! is echoed at once, each line run by [`shell::run`] against the latest snapshot and parameter
//! table, the answer and the prompt sent back in SERIAL_CONTROL replies to the client's ids;
//! `param set` goes to the vehicle as a PARAM_SET does and is answered (with the PARAM_VALUE to
//! the link's peers), then prompted, when the vehicle replies.
//!
//! [`Consoles`] owns the shells; it reads the table and the state it is handed.

use mavlink::dialects::ardupilotmega::{SerialControlFlag, SERIAL_CONTROL_DATA};

use super::boundary::VehicleRequest;
use super::commands::Pending;
use super::effects::Effect;
use super::port::MAX_PEERS;
use super::LinkKind;
use crate::mav::param_encoding::Shown;
use crate::mav::shell::{self, frames, param_set_text, Context, LineBuffer, ShellOutcome, Typed, PROMPT};
use crate::params::ParamTable;
use crate::telemetry::Snapshot;

/// One client's shell.
#[derive(Debug)]
struct Console<A> {
    link: LinkKind,
    from: A,
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

impl<A> ShellSet<A> {
    /// The link of the shell.
    pub fn link(&self) -> LinkKind {
        self.link
    }
}

/// The MAVLink shells of the clients that use one.
#[derive(Debug)]
pub(super) struct Consoles<A> {
    shells: Vec<Console<A>>,
}

impl<A> Default for Consoles<A> {
    /// No shell yet.
    fn default() -> Self {
        Self { shells: Vec::new() }
    }
}

impl<A: Copy + PartialEq> Consoles<A> {
    /// Open shells.
    pub fn count(&self) -> usize {
        self.shells.len()
    }

    /// Closes the shells of `link`'s clients that are not among its `targets`.
    pub fn keep_clients(&mut self, link: LinkKind, targets: &[A]) {
        self.shells.retain(|c| c.link != link || targets.contains(&c.from));
    }

    /// SERIAL_CONTROL for the shell from `from` (MAVLink ids `ids`) on `link`: without RESPOND
    /// the client is done (the shell closes, as PX4's does); otherwise its bytes are typed (and
    /// echoed) and every complete line answered against `params` and `snapshot`.
    pub fn serial(
        &mut self,
        (link, from, ids): (LinkKind, A, (u8, u8)),
        msg: &SERIAL_CONTROL_DATA,
        params: &ParamTable,
        snapshot: &Snapshot,
    ) -> Vec<Effect<A>> {
        let at = self.shells.iter().position(|c| c.link == link && c.from == from);
        if !msg.flags.contains(SerialControlFlag::SERIAL_CONTROL_FLAG_RESPOND) {
            if let Some(k) = at {
                self.shells.remove(k);
            }
            return Vec::new();
        }
        let k = at.unwrap_or_else(|| {
            // One shell per peer the link can have: a new client closes the oldest one beyond.
            if self.shells.iter().filter(|c| c.link == link).count() > MAX_PEERS {
                if let Some(oldest) = self.shells.iter().position(|c| c.link == link) {
                    self.shells.remove(oldest);
                }
            }
            self.shells.push(Console {
                link,
                from,
                input: LineBuffer::default(),
            });
            self.shells.len() - 1
        });
        let count = usize::from(msg.count).min(msg.data.len());
        let typed = self.shells[k].input.push(&msg.data[..count]);
        let mut out = Vec::new();
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
            match shell::run(&line, Context { params, snapshot }) {
                ShellOutcome::Text(text) => said += &format!("\n{text}{PROMPT}"),
                ShellOutcome::SetParam { name, value } => {
                    said.push('\n');
                    out.extend(type_out(link, from, ids, &std::mem::take(&mut said)));
                    let set = ShellSet {
                        link,
                        to: from,
                        ids,
                        name: name.clone(),
                    };
                    out.push(Effect::Ask(
                        Some(Pending::Shell(set)),
                        VehicleRequest::SetParam { name, value },
                    ));
                }
            }
        }
        out.extend(type_out(link, from, ids, &said));
        out
    }

    /// The vehicle's answer to a shell's `param set`: `result`, the table `before` and the
    /// parameters `after` it as the vehicle shows them (the shell itself speaks the settings'
    /// own names; the announcement is the personality's), and the `targets` of the shell's link
    /// (which get the new PARAM_VALUE).
    pub fn set_done(
        &self,
        set: ShellSet<A>,
        result: Result<usize, String>,
        before: &ParamTable,
        after: Shown<'_>,
        targets: Vec<A>,
    ) -> Vec<Effect<A>> {
        let ShellSet { link, to, ids, name } = set;
        let mut out = Vec::new();
        if let Ok(index) = result {
            if let Some(msg) = after.announced_value(index) {
                out.extend(targets.into_iter().map(|t| Effect::send(link, t, msg.clone())));
            }
        }
        let text = param_set_text(before, after.table, &name, result.map(|_| ()));
        out.extend(type_out(link, to, ids, &format!("{text}{PROMPT}")));
        out
    }
}

/// `text` to `to` on `link` as SERIAL_CONTROL replies to the client's `ids`.
fn type_out<A: Copy>(link: LinkKind, to: A, ids: (u8, u8), text: &str) -> Vec<Effect<A>> {
    frames(ids, text)
        .into_iter()
        .map(|msg| Effect::send(link, to, msg))
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::mav::ardupilot::copter_link_params::LinkParams;
    use crate::mav::identity::Personality;
    use mavlink::dialects::ardupilotmega::{MavMessage, SerialControlDev};

    use super::*;
    use crate::guidance::Home;
    use crate::mav::link::effects::testing::{param_names, sent, table};

    const GCS: LinkKind = LinkKind::Gcs;

    fn typed(text: &str, respond: bool) -> SERIAL_CONTROL_DATA {
        let mut data = [0u8; 70];
        data[..text.len()].copy_from_slice(text.as_bytes());
        let mut flags = SerialControlFlag::SERIAL_CONTROL_FLAG_EXCLUSIVE;
        if respond {
            flags |= SerialControlFlag::SERIAL_CONTROL_FLAG_RESPOND;
        }
        SERIAL_CONTROL_DATA {
            device: SerialControlDev::SERIAL_CONTROL_DEV_SHELL,
            flags,
            count: text.len() as u8,
            data,
            ..Default::default()
        }
    }

    fn said(out: &[Effect<u16>]) -> String {
        sent(out)
            .into_iter()
            .filter_map(|(_, _, m)| match m {
                MavMessage::SERIAL_CONTROL(r) => {
                    Some(String::from_utf8_lossy(&r.data[..r.count as usize]).into_owned())
                }
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_line_is_echoed_and_answered_and_a_set_waits_for_the_vehicle() {
        let (params, snapshot) = (table(), Snapshot::initial(Home::default()));
        let mut c = Consoles::default();
        let out = c.serial(
            (GCS, 5u16, (255, 190)),
            &typed("param show MIS_TAKEOFF_ALT\n", true),
            &params,
            &snapshot,
        );
        assert!(said(&out).contains("MIS_TAKEOFF_ALT"), "{}", said(&out));
        assert_eq!(c.count(), 1);
        let out = c.serial(
            (GCS, 5, (255, 190)),
            &typed("param set MIS_TAKEOFF_ALT 4.5\n", true),
            &params,
            &snapshot,
        );
        let Some(Effect::Ask(Some(Pending::Shell(set)), VehicleRequest::SetParam { value, .. })) =
            out.iter().find(|e| matches!(e, Effect::Ask(..)))
        else {
            panic!("{out:?}");
        };
        assert_eq!(*value, 4.5);
        let mut after = table();
        let index = after.set("MIS_TAKEOFF_ALT", 4.5, 1e-3).map_err(|e| e.to_string());
        let held = LinkParams::default();
        let shown = Shown {
            personality: Personality::Px4,
            table: &after,
            link: &held,
        };
        let done = c.set_done(set.clone(), index, &params, shown, vec![5, 6]);
        assert_eq!(param_names(&done), vec!["MIS_TAKEOFF_ALT"; 2], "to the link's targets");
        assert_eq!(said(&done), "MIS_TAKEOFF_ALT: curr: 2.5000 -> new: 4.5000\npxh> ");
    }

    #[test]
    fn a_client_without_respond_closes_its_shell_and_forgotten_clients_lose_theirs() {
        let (params, snapshot) = (table(), Snapshot::initial(Home::default()));
        let mut c = Consoles::default();
        c.serial((GCS, 5u16, (255, 190)), &typed("\n", true), &params, &snapshot);
        c.serial((GCS, 6, (255, 190)), &typed("\n", true), &params, &snapshot);
        assert!(c
            .serial((GCS, 5, (255, 190)), &typed("", false), &params, &snapshot)
            .is_empty());
        assert_eq!(c.count(), 1);
        c.keep_clients(GCS, &[5]);
        assert_eq!(c.count(), 0);
    }
}
