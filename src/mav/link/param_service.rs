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
//! [`ParamService`] owns the lists being streamed, the changes not yet announced and the
//! parameter files being applied; it reads the table it is handed (the vehicle's, shared).

use mavlink::MavHeader;

use super::boundary::VehicleRequest;
use super::commands::Pending;
use super::effects::{Client, Effect};
use super::param_upload::{UploadSet, Uploads};
use super::port::MAX_PEERS;
use super::{LinkKind, WARNING};
use crate::mav::ftp::ParamUpload;
use crate::mav::param_encoding::{hash_check, param_error_unknown, param_value, HASH_CHECK};
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
    /// The `_HASH_CHECK` is still to be sent (it goes first).
    hash_pending: bool,
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
            hash_pending: true,
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
}

impl<A> Default for ParamService<A> {
    fn default() -> Self {
        Self {
            lists: Vec::new(),
            changed: ChangedParams::default(),
            uploads: Uploads::default(),
        }
    }
}

impl<A: Copy + PartialEq> ParamService<A> {
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

    /// The changed parameters' PARAM_VALUEs of `params` to every peer of every link, once due
    /// at wall time `wall_s` [s].
    pub fn announce_changed(&mut self, wall_s: f64, params: &ParamTable) -> Vec<Effect<A>> {
        let due = self.changed.take_due(wall_s);
        due.into_iter()
            .filter_map(|index| param_value(params, index))
            .map(Effect::Everyone)
            .collect()
    }

    /// The PARAM_VALUEs of `params` of every list that are due by wall time `wall_s` [s].
    pub fn stream_lists(&mut self, wall_s: f64, params: &ParamTable) -> Vec<Effect<A>> {
        let mut out = Vec::new();
        for list in &mut self.lists {
            while list.next_s <= wall_s {
                let msg = if std::mem::take(&mut list.hash_pending) {
                    hash_check(params)
                } else {
                    let Some(msg) = param_value(params, list.next) else {
                        break;
                    };
                    list.next += 1;
                    msg
                };
                out.push(Effect::send(list.link, list.to, msg));
                list.next_s += PARAM_LIST_PERIOD_S;
            }
        }
        self.lists.retain(|l| l.hash_pending || l.next < params.len());
        out
    }

    /// PARAM_REQUEST_READ of `params` from `to` on `link`: by `index`, or by `name` without one.
    pub fn read(
        &self,
        (link, to, header): (LinkKind, A, &MavHeader),
        name: &str,
        index: Option<usize>,
        params: &ParamTable,
    ) -> Vec<Effect<A>> {
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

    /// PARAM_SET from `to` on `link`: asks the vehicle, which answers at its next tick;
    /// `_HASH_CHECK`, whatever its value, stops the lists streaming to the sender and is not
    /// answered (as PX4 does).
    pub fn set(&mut self, link: LinkKind, to: A, header: &MavHeader, name: String, value: f64) -> Vec<Effect<A>> {
        if name == HASH_CHECK {
            self.lists.retain(|l| !(l.link == link && l.to == to));
            return Vec::new();
        }
        let set = ParamSet {
            link,
            to,
            header: *header,
            name: name.clone(),
        };
        vec![Effect::Ask(
            Some(Pending::Param(set)),
            VehicleRequest::SetParam { name, value },
        )]
    }

    /// The vehicle's answer to `set` at wall time `wall_s` [s] (`None`: it was busy), with the
    /// table `params` after it and the `targets` of the set's link.
    pub fn set_done(
        &mut self,
        wall_s: f64,
        set: ParamSet<A>,
        result: Option<Result<usize, ParamError>>,
        params: &ParamTable,
        mut targets: Vec<A>,
    ) -> Vec<Effect<A>> {
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

    /// A parameter file `client` uploaded: refused when malformed, else its parameters asked of
    /// the vehicle.
    pub fn start_upload(&mut self, client: Client<A>, upload: ParamUpload) -> Vec<Effect<A>> {
        self.uploads.start(client, upload)
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

#[cfg(test)]
mod tests {
    use mavlink::dialects::ardupilotmega::MavMessage;

    use super::*;
    use crate::mav::gcs::gcs_header;
    use crate::mav::link::effects::testing::{param_names, sent, table, texts};

    const GCS: LinkKind = LinkKind::Gcs;

    #[test]
    fn a_list_sends_the_hash_first_then_one_value_per_period_and_ends() {
        let params = table();
        let mut p = ParamService::default();
        p.request_list(GCS, 5u16, 1.0);
        assert_eq!(p.next_due_s(), Some(1.0));
        let first = p.stream_lists(1.0, &params);
        assert_eq!(param_names(&first), vec![HASH_CHECK]);
        let more = p.stream_lists(1.0 + 2.5 * PARAM_LIST_PERIOD_S, &params);
        assert_eq!(param_names(&more).len(), 2, "one value per period of wall time");
        let rest = p.stream_lists(1e3, &params);
        assert_eq!(param_names(&rest).len(), params.len() - 2);
        assert_eq!(p.list_count(), 0, "a sent list is done");
        assert_eq!(p.next_due_s(), None);
    }

    #[test]
    fn the_hash_check_stops_a_list_and_forgotten_clients_lose_theirs() {
        let mut p = ParamService::default();
        p.request_list(GCS, 5u16, 0.0);
        p.request_list(GCS, 6u16, 0.0);
        assert!(p.set(GCS, 5, &gcs_header(0), HASH_CHECK.into(), 1.0).is_empty());
        assert_eq!(p.list_count(), 1);
        p.keep_clients(GCS, &[7]);
        assert_eq!(p.list_count(), 0);
    }

    #[test]
    fn a_set_is_asked_echoed_to_the_link_and_announced_to_every_link_later() {
        let mut params = table();
        let mut p = ParamService::default();
        let out = p.set(GCS, 5u16, &gcs_header(0), "MIS_TAKEOFF_ALT".into(), 5.0);
        let [Effect::Ask(Some(Pending::Param(set)), VehicleRequest::SetParam { name, value })] = &out[..] else {
            panic!("{out:?}");
        };
        assert_eq!((name.as_str(), *value), ("MIS_TAKEOFF_ALT", 5.0));
        let result = params.set("MIS_TAKEOFF_ALT", 5.0, 1e-3);
        let echo = p.set_done(1.0, set.clone(), Some(result), &params, vec![1, 2]);
        let to: Vec<u16> = sent(&echo).iter().map(|(_, to, _)| *to).collect();
        assert_eq!(to, vec![1, 2, 5], "the link's targets and the sender");
        assert!(p.announce_changed(1.001, &params).is_empty());
        assert_eq!(p.next_due_s(), Some(1.0 + PARAM_CHANGE_DELAY_S));
        let later = p.announce_changed(1.0 + PARAM_CHANGE_DELAY_S, &params);
        assert!(matches!(&later[..], [Effect::Everyone(MavMessage::PARAM_VALUE(_))]));
    }

    #[test]
    fn a_refused_or_unknown_set_says_why_to_the_sender() {
        let mut params = table();
        let mut p = ParamService::default();
        let set = |name: &str| ParamSet {
            link: GCS,
            to: 5u16,
            header: gcs_header(0),
            name: name.into(),
        };
        let refused = params.set("MIS_TAKEOFF_ALT", -1e9, 1e-3);
        let out = p.set_done(0.0, set("MIS_TAKEOFF_ALT"), Some(refused), &params, vec![1]);
        assert_eq!(param_names(&out), vec!["MIS_TAKEOFF_ALT"], "the unchanged value");
        assert_eq!(texts(&out).len(), 1);
        let out = p.set_done(0.0, set("NOPE"), Some(params.set("NOPE", 1.0, 1e-3)), &params, vec![1]);
        assert!(matches!(sent(&out)[0].2, MavMessage::PARAM_ERROR(_)));
        assert_eq!(texts(&out), vec!["Unknown parameter NOPE"]);
        let out = p.set_done(0.0, set("MIS_TAKEOFF_ALT"), None, &params, vec![1]);
        assert_eq!(texts(&out), vec!["Vehicle busy"]);
        assert_eq!(p.next_due_s(), None, "nothing changed");
    }

    #[test]
    fn a_read_by_name_or_index_and_an_unknown_name() {
        let params = table();
        let p = ParamService::<u16>::default();
        let header = gcs_header(0);
        let by_name = p.read((GCS, 5, &header), "MIS_TAKEOFF_ALT", None, &params);
        assert_eq!(param_names(&by_name), vec!["MIS_TAKEOFF_ALT"]);
        assert_eq!(param_names(&p.read((GCS, 5, &header), "", Some(0), &params)).len(), 1);
        assert_eq!(
            param_names(&p.read((GCS, 5, &header), HASH_CHECK, None, &params)),
            vec![HASH_CHECK]
        );
        let unknown = p.read((GCS, 5, &header), "NOPE", None, &params);
        assert!(matches!(sent(&unknown)[0].2, MavMessage::PARAM_ERROR(_)));
    }
}
