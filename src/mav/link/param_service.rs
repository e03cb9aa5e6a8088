//! The parameter protocol of the link: PARAM_REQUEST_LIST streamed at one PARAM_VALUE per
//! millisecond of wall time at most, PX4's `_HASH_CHECK` first (a PARAM_SET of `_HASH_CHECK`
//! stops the list: the ground station loaded its cached copy), PARAM_REQUEST_READ by index or
//! name (`_HASH_CHECK` included), and PARAM_SET: the
//! vehicle applies it at its next tick, then every peer of the link gets the resulting
//! PARAM_VALUE (the unchanged value when refused, with a STATUSTEXT saying why) and an
//! unknown name gets PARAM_ERROR. As PX4 does, a changed parameter is sent again 5 ms later to
//! every peer of every link, so that every ground station and every client plugin that did not
//! ask (MAVSDK's Failure plugin follows `SYS_FAILURE_EN` that way) learns the new value.
//!
//! A vehicle presented as ArduCopter speaks it as ArduCopter does (docs/ardupilot.md §5.1),
//! through [`CopterParamView`]: Copter's banner (STATUSTEXTs) instead of the hash before a list;
//! Copter's names, units and plain numeric values; a read by name answered with index −1; a set
//! echoed once to every peer of every link with index −1; an unknown name (a PX4 name Copter
//! shows otherwise, `_HASH_CHECK`) answered with nothing; a value the setting cannot take
//! refused as PX4's are, in Copter's unit, before the vehicle is asked.
//!
//! [`ParamService`] owns the lists being streamed, the changes not yet announced and the
//! parameter files being applied; it reads the table it is handed (the vehicle's, shared).

use mavlink::dialects::ardupilotmega::MavMessage;
use mavlink::MavHeader;

use super::boundary::VehicleRequest;
use super::commands::Pending;
use super::effects::{Client, Effect};
use super::param_upload::{UploadSet, Uploads};
use super::port::MAX_PEERS;
use super::{LinkKind, INFO, WARNING};
use crate::mav::ardupilot::copter_link_params::LinkParams;
use crate::mav::ardupilot::copter_param_face::{banner, CopterParamView, CopterSet};
use crate::mav::ftp::ParamUpload;
use crate::mav::identity::{Identity, Personality};
use crate::mav::param_encoding::{hash_check, param_error_unknown, param_value, Shown, HASH_CHECK};
use crate::mav::stream_messages::status_text;
use crate::params::{ParamError, ParamTable};

/// Wall time between two PARAM_VALUEs of a list [s].
pub const PARAM_LIST_PERIOD_S: f64 = 1e-3;
/// Wall time from a change to its PARAM_VALUE on every link [s] (PX4's 5 ms).
pub const PARAM_CHANGE_DELAY_S: f64 = 5e-3;

/// Parameters changed since their last announcement to every link.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct ChangedParams {
    /// Indices of the changed parameters, each once.
    indices: Vec<usize>,
    /// Wall time the announcement is due [s], while there is one to make.
    pub due_s: Option<f64>,
}

impl ChangedParams {
    /// Parameter `index` changed at wall time `now_s` [s].
    pub fn changed(&mut self, index: usize, now_s: f64) {
        if !self.indices.contains(&index) {
            self.indices.push(index);
        }
        self.due_s.get_or_insert(now_s + PARAM_CHANGE_DELAY_S);
    }

    /// The indices to announce at `now_s` [s], if due.
    pub fn take_due(&mut self, now_s: f64) -> Vec<usize> {
        match self.due_s {
            Some(due) if due <= now_s => {
                self.due_s = None;
                std::mem::take(&mut self.indices)
            }
            _ => Vec::new(),
        }
    }
}

/// A PARAM_REQUEST_LIST being answered.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ParamList<A> {
    pub link: LinkKind,
    pub to: A,
    /// What goes first is still to be sent: PX4's `_HASH_CHECK`, ArduCopter's banner.
    opening: bool,
    /// Index of the next parameter.
    next: usize,
    /// Wall time the next one is due [s].
    pub next_s: f64,
}

impl<A> ParamList<A> {
    /// A list for `to` on `link`, its first value due at `now_s`.
    pub fn new(link: LinkKind, to: A, now_s: f64) -> Self {
        Self {
            link,
            to,
            opening: true,
            next: 0,
            next_s: now_s,
        }
    }
}

/// A PARAM_SET waiting for the vehicle: who sent it, where the answer goes, and the name.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ParamSet<A> {
    link: LinkKind,
    to: A,
    header: MavHeader,
    name: String,
}

impl<A> ParamSet<A> {
    /// The link the set came from.
    pub fn link(&self) -> LinkKind {
        self.link
    }
}

/// The parameter protocol of every link: lists, changes to announce, uploaded files.
#[derive(Debug)]
pub(super) struct ParamService<A> {
    /// The PARAM_REQUEST_LISTs being answered.
    lists: Vec<ParamList<A>>,
    /// Parameters changed and not yet announced on every link.
    changed: ChangedParams,
    /// The parameter files uploaded over FTP and being applied.
    uploads: Uploads<A>,
    /// The autopilot whose protocol is spoken.
    personality: Personality,
    /// What ArduCopter says before a list (nothing for PX4).
    banner: Vec<String>,
}

impl<A> Default for ParamService<A> {
    /// PX4's.
    fn default() -> Self {
        Self {
            lists: Vec::new(),
            changed: ChangedParams::default(),
            uploads: Uploads::default(),
            personality: Personality::Px4,
            banner: Vec::new(),
        }
    }
}

impl<A> ParamService<A> {
    /// The protocol of the autopilot `identity` presents (its banner from the vehicle type).
    pub fn new(identity: &Identity) -> Self {
        let banner = match identity.personality {
            Personality::Px4 => Vec::new(),
            Personality::ArduPilot => banner(identity.mav_type).to_vec(),
        };
        Self {
            personality: identity.personality,
            banner,
            ..Self::default()
        }
    }
}

impl<A: Copy + PartialEq> ParamService<A> {
    /// The parameters as this personality shows them: `params`, and what the link holds, `link`.
    fn shown<'a>(&self, params: &'a ParamTable, link: &'a LinkParams) -> Shown<'a> {
        Shown {
            personality: self.personality,
            table: params,
            link,
        }
    }

    /// Parameter lists being sent.
    pub fn list_count(&self) -> usize {
        self.lists.len()
    }

    /// Wall time the next list value or change announcement is due [s].
    pub fn next_due_s(&self) -> Option<f64> {
        self.lists
            .iter()
            .map(|l| l.next_s)
            .chain(self.changed.due_s)
            .reduce(f64::min)
    }

    /// Forgets the lists of `link`'s clients that are not among its `targets`.
    pub fn keep_clients(&mut self, link: LinkKind, targets: &[A]) {
        self.lists.retain(|l| l.link != link || targets.contains(&l.to));
    }

    /// PARAM_REQUEST_LIST from `from` on `link` at wall time `wall_s` [s]: its list starts
    /// again; one list per peer the link can have, beyond which the oldest request is dropped.
    pub fn request_list(&mut self, link: LinkKind, from: A, wall_s: f64) {
        self.lists.retain(|l| !(l.link == link && l.to == from));
        if self.lists.iter().filter(|l| l.link == link).count() > MAX_PEERS {
            if let Some(oldest) = self.lists.iter().position(|l| l.link == link) {
                self.lists.remove(oldest);
            }
        }
        self.lists.push(ParamList::new(link, from, wall_s));
    }

    /// Whether a list is being answered or a change is waiting to be announced: what
    /// [`Self::stream_lists`] and [`Self::announce_changed`] may have to send.
    pub fn has_work(&self) -> bool {
        !self.lists.is_empty() || self.changed.due_s.is_some()
    }

    /// The changed parameters' PARAM_VALUEs of `params` (and `link`, what the link holds) to
    /// every peer of every link, once due at wall time `wall_s` [s].
    pub fn announce_changed(&mut self, wall_s: f64, params: &ParamTable, link: &LinkParams) -> Vec<Effect<A>> {
        let shown = self.shown(params, link);
        let due = self.changed.take_due(wall_s);
        due.into_iter()
            .filter_map(|index| shown.announced_value(index))
            .map(Effect::Everyone)
            .collect()
    }

    /// The PARAM_VALUEs of `params` (and `link`, what the link holds) of every list that are due
    /// by wall time `wall_s` [s].
    pub fn stream_lists(&mut self, wall_s: f64, params: &ParamTable, link: &LinkParams) -> Vec<Effect<A>> {
        let shown = self.shown(params, link);
        let mut out = Vec::new();
        for list in &mut self.lists {
            while list.next_s <= wall_s {
                if std::mem::take(&mut list.opening) {
                    match self.personality {
                        Personality::Px4 => out.push(Effect::send(list.link, list.to, hash_check(params))),
                        Personality::ArduPilot => out.extend(
                            self.banner
                                .iter()
                                .map(|text| Effect::send(list.link, list.to, status_text(INFO, text))),
                        ),
                    }
                } else {
                    let Some(msg) = shown.param_value(list.next) else {
                        break;
                    };
                    list.next += 1;
                    out.push(Effect::send(list.link, list.to, msg));
                }
                list.next_s += PARAM_LIST_PERIOD_S;
            }
        }
        let count = shown.len();
        self.lists.retain(|l| l.opening || l.next < count);
        out
    }

    /// PARAM_REQUEST_READ of `params` (and `held`, what the link holds) from `to` on `link`: by
    /// `index`, or by `name` without one.
    pub fn read(
        &self,
        (link, to, header): (LinkKind, A, &MavHeader),
        name: &str,
        index: Option<usize>,
        (params, held): (&ParamTable, &LinkParams),
    ) -> Vec<Effect<A>> {
        if self.personality == Personality::ArduPilot {
            let view = CopterParamView::new(params, held);
            let found = match index {
                Some(i) => view.param_value(i, i as u16),
                None => view.index_of(name).and_then(|i| view.param_value(i, u16::MAX)),
            };
            return found.into_iter().map(|msg| Effect::send(link, to, msg)).collect();
        }
        let found = match index {
            None if name == HASH_CHECK => Some(hash_check(params)),
            _ => index
                .or_else(|| params.index_of(name))
                .and_then(|i| param_value(params, i)),
        };
        vec![Effect::send(
            link,
            to,
            found.unwrap_or_else(|| param_error_unknown(header, name)),
        )]
    }

    /// PARAM_SET from `to` on `link`, `params` the table as it is and `held` what the link
    /// holds: asks the vehicle, which answers at its next tick; `_HASH_CHECK`, whatever its
    /// value, stops the lists streaming to the sender and is not answered (as PX4 does).
    /// ArduCopter asks for the setting behind a Copter name, asks the link to change what it
    /// holds (`SRn_*`), refuses a value the setting cannot take at once and ignores a name it
    /// does not have.
    pub fn set(
        &mut self,
        (link, to, header): (LinkKind, A, &MavHeader),
        name: String,
        value: f64,
        (params, held): (&ParamTable, &LinkParams),
    ) -> Vec<Effect<A>> {
        let ask = |setting: String, value: f64| {
            let set = ParamSet {
                link,
                to,
                header: *header,
                name: name.clone(),
            };
            vec![Effect::Ask(
                Some(Pending::Param(set)),
                VehicleRequest::SetParam { name: setting, value },
            )]
        };
        match self.personality {
            Personality::Px4 if name == HASH_CHECK => {
                self.lists.retain(|l| !(l.link == link && l.to == to));
                Vec::new()
            }
            Personality::Px4 => ask(name.clone(), value),
            Personality::ArduPilot => {
                let view = CopterParamView::new(params, held);
                match view.setting_for(&name, value) {
                    None => Vec::new(),
                    Some(Ok(CopterSet::Setting(setting, value))) => ask(setting.to_string(), value),
                    Some(Ok(CopterSet::Link(change))) => {
                        let index = view.index_of(&name).unwrap_or(usize::MAX);
                        vec![Effect::LinkSet((link, to), change, index)]
                    }
                    Some(Err(why)) => {
                        let current = view.index_of(&name).and_then(|i| view.param_value(i, u16::MAX));
                        let mut out: Vec<Effect<A>> = current.map(|m| Effect::send(link, to, m)).into_iter().collect();
                        out.push(Effect::send(link, to, status_text(WARNING, &why)));
                        out
                    }
                }
            }
        }
    }

    /// The vehicle's answer to `set` at wall time `wall_s` [s] (`None`: it was busy), with the
    /// table `params` after it (and `held`, what the link holds) and the `targets` of the set's
    /// link.
    pub fn set_done(
        &mut self,
        wall_s: f64,
        set: ParamSet<A>,
        result: Option<Result<usize, ParamError>>,
        (params, held): (&ParamTable, &LinkParams),
        mut targets: Vec<A>,
    ) -> Vec<Effect<A>> {
        if self.personality == Personality::ArduPilot {
            return copter_set_done(set, result, CopterParamView::new(params, held), &targets);
        }
        let ParamSet { link, to, header, name } = set;
        let mut out = Vec::new();
        match result {
            Some(Ok(index)) => {
                self.changed.changed(index, wall_s);
                if let Some(msg) = param_value(params, index) {
                    if !targets.contains(&to) {
                        targets.push(to);
                    }
                    out.extend(targets.into_iter().map(|t| Effect::send(link, t, msg.clone())));
                }
            }
            Some(Err(ParamError::Unknown(..))) => {
                out.push(Effect::send(link, to, param_error_unknown(&header, &name)));
                let text = format!("Unknown parameter {name}");
                out.push(Effect::send(link, to, status_text(WARNING, &text)));
            }
            refused => {
                if let Some(msg) = params.index_of(&name).and_then(|i| param_value(params, i)) {
                    out.push(Effect::send(link, to, msg));
                }
                let why = match refused {
                    Some(Err(e)) => e.to_string(),
                    _ => "Vehicle busy".to_string(),
                };
                out.push(Effect::send(link, to, status_text(WARNING, &why)));
            }
        }
        out
    }

    /// A parameter file `client` uploaded, `params` the table as it is (and `held`, what the
    /// link holds): refused when malformed, else its parameters asked of the vehicle
    /// (ArduCopter's names as their settings; what the link holds is skipped as unknown: it is
    /// set by PARAM_SET only).
    pub fn start_upload(
        &mut self,
        client: Client<A>,
        upload: ParamUpload,
        (params, held): (&ParamTable, &LinkParams),
    ) -> Vec<Effect<A>> {
        match self.personality {
            Personality::Px4 => self
                .uploads
                .start(client, upload, |name, value| Ok((name.to_string(), value))),
            Personality::ArduPilot => {
                let view = CopterParamView::new(params, held);
                self.uploads
                    .start(client, upload, |name, value| match view.setting_for(name, value) {
                        None => Err(ParamError::Unknown(name.to_string(), String::new())),
                        Some(Ok(CopterSet::Setting(setting, value))) => Ok((setting.to_string(), value)),
                        // What the link holds is skipped (set by PARAM_SET only).
                        Some(Ok(CopterSet::Link(_))) => Err(ParamError::Unknown(name.to_string(), String::new())),
                        Some(Err(reason)) => Err(ParamError::Invalid {
                            name: name.to_string(),
                            reason,
                        }),
                    })
            }
        }
    }

    /// The vehicle's answer to one parameter of an upload at wall time `wall_s` [s]; a set one
    /// is announced as a PARAM_SET's is.
    pub fn upload_set_done(
        &mut self,
        wall_s: f64,
        set: UploadSet,
        result: Result<usize, ParamError>,
    ) -> Vec<Effect<A>> {
        if let Ok(index) = result {
            self.changed.changed(index, wall_s);
        }
        self.uploads.set_done(set, result)
    }
}

/// The vehicle's answer to an ArduCopter PARAM_SET (docs/ardupilot.md §5.1): the new value to
/// every peer of every link (and the sender) once, index −1; a refusal as PX4's, named by the
/// Copter name; an unknown name nothing.
fn copter_set_done<A: Copy + PartialEq>(
    set: ParamSet<A>,
    result: Option<Result<usize, ParamError>>,
    view: CopterParamView<'_>,
    targets: &[A],
) -> Vec<Effect<A>> {
    let ParamSet { link, to, name, .. } = set;
    let value = |index: usize| -> Option<MavMessage> { view.param_value(index, u16::MAX) };
    let mut out = Vec::new();
    match result {
        Some(Ok(index)) => {
            if let Some(msg) = value(index) {
                if !targets.contains(&to) {
                    out.push(Effect::send(link, to, msg.clone()));
                }
                out.push(Effect::Everyone(msg));
            }
        }
        Some(Err(ParamError::Unknown(..))) => {}
        refused => {
            if let Some(msg) = view.index_of(&name).and_then(value) {
                out.push(Effect::send(link, to, msg));
            }
            let why = match refused {
                Some(Err(ParamError::Invalid { reason, .. })) => format!("{name}: {reason}"),
                Some(Err(e)) => e.to_string(),
                _ => "Vehicle busy".to_string(),
            };
            out.push(Effect::send(link, to, status_text(WARNING, &why)));
        }
    }
    out
}

#[cfg(test)]
#[path = "param_service_tests.rs"]
mod tests;
