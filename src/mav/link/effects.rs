//! What a part of the link decided, as a value: the protocol types (parameters, plans, files,
//! logs, shells, commands, signing keys) return these and [`LinkMachine`](super::LinkMachine)
//! carries them out in order: it frames and queues the messages, names the requests it will
//! wait for, and hands what one part decided for another to that part (an uploaded parameter
//! file from FTP to the parameters, its answer back to FTP).

use mavlink::dialects::ardupilotmega::MavMessage;

use super::boundary::{KeyToStore, VehicleRequest};
use super::commands::Pending;
use crate::mav::ardupilot::copter_link_params::LinkSet;
use crate::mav::ftp::{ErrorCode, ParamUpload, Payload};
use crate::mav::streams::LinkKind;

/// Where an answer goes: link, client address, client's MAVLink ids (system, component).
pub(super) type Client<A> = (LinkKind, A, (u8, u8));

/// One thing a part of the link decided.
#[derive(Debug, Clone, PartialEq)]
#[allow(clippy::large_enum_variant)] // carried out at once: boxing would allocate per message
pub(super) enum Effect<A> {
    /// A message to one client on a link; a STATUSTEXT is also noted for
    /// the flight log.
    To(LinkKind, A, MavMessage),
    /// A message to every target of every link (an announcement, not noted).
    Everyone(MavMessage),
    /// A request for the vehicle; with a [`Pending`], its answer is awaited as that.
    Ask(Option<Pending<A>>, VehicleRequest),
    /// A parameter file uploaded over FTP by a client, to apply (FTP → parameters).
    Upload(Client<A>, ParamUpload),
    /// The answer to an uploaded file's TerminateSession (parameters → FTP).
    UploadAnswer(Client<A>, Payload, Result<(), ErrorCode>),
    /// A key (or its removal) for the key file.
    Store(KeyToStore),
    /// A PARAM_SET of what the link holds (ArduCopter's `SRn_*`, `SYSID_THISMAV`) from a client
    /// on a link, parameter `index` of the view: carried out by the link, then announced.
    LinkSet((LinkKind, A), LinkSet, usize),
}

impl<A> Effect<A> {
    /// `msg` to `to` on `link`.
    pub fn send(link: LinkKind, to: A, msg: MavMessage) -> Self {
        Self::To(link, to, msg)
    }
}

/// What the tests of the link's parts share: a parameter table and readers of effects.
#[cfg(test)]
pub(super) mod testing {
    use mavlink::dialects::ardupilotmega::MavMessage;

    use super::Effect;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::mav::streams::LinkKind;
    use crate::params::{ParamTable, VehicleSettings};

    /// The table of a geometric controller with default gains.
    pub fn table() -> ParamTable {
        ParamTable::new(&VehicleSettings::new(
            ControllerKind::Geometric,
            ControllerGains::default(),
            None,
        ))
    }

    /// The messages to one client among `out`: (link, destination, message), in order.
    pub fn sent<A: Copy>(out: &[Effect<A>]) -> Vec<(LinkKind, A, MavMessage)> {
        out.iter()
            .filter_map(|e| match e {
                Effect::To(link, to, m) => Some((*link, *to, m.clone())),
                _ => None,
            })
            .collect()
    }

    /// The STATUSTEXTs among `out`, as text.
    pub fn texts<A: Copy>(out: &[Effect<A>]) -> Vec<String> {
        sent(out)
            .into_iter()
            .filter_map(|(_, _, m)| match m {
                MavMessage::STATUSTEXT(t) => {
                    let end = t.text.iter().position(|&b| b == 0).unwrap_or(t.text.len());
                    Some(String::from_utf8_lossy(&t.text[..end]).into_owned())
                }
                _ => None,
            })
            .collect()
    }

    /// The name of each PARAM_VALUE among `out`, in order.
    pub fn param_names<A: Copy>(out: &[Effect<A>]) -> Vec<String> {
        sent(out)
            .into_iter()
            .filter_map(|(_, _, m)| match m {
                MavMessage::PARAM_VALUE(p) => {
                    let end = p.param_id.iter().position(|&b| b == 0).unwrap_or(p.param_id.len());
                    Some(String::from_utf8_lossy(&p.param_id[..end]).into_owned())
                }
                _ => None,
            })
            .collect()
    }
}
