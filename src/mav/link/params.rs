//! The parameter protocol of the link: PARAM_REQUEST_LIST streamed at one PARAM_VALUE per
//! millisecond of wall time at most, PX4's `_HASH_CHECK` first (a PARAM_SET of `_HASH_CHECK`
//! stops the list: the ground station loaded its cached copy), PARAM_REQUEST_READ by index or
//! name (`_HASH_CHECK` included), and PARAM_SET: the
//! vehicle applies it at its next tick, then every peer of the link gets the resulting
//! PARAM_VALUE (the unchanged value when refused, with a STATUSTEXT saying why) and an
//! unknown name gets PARAM_ERROR. As PX4 does, a changed parameter is sent again 5 ms later to
//! every peer of every link, so that every ground station and every client plugin that did not
//! ask (MAVSDK's Failure plugin follows `SYS_FAILURE_EN` that way) learns the new value.

use std::hash::Hash;

use mavlink::MavHeader;

use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleReply, VehicleRequest, WARNING};
use crate::mav::params::{hash_check, param_error_unknown, param_value, HASH_CHECK};
use crate::mav::telemetry::status_text;
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
    /// Parameter `index` changed at `now_s` [s].
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

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// The table as the vehicle answered it: the link's copy, which `@PARAM/param.pck` packs.
    pub(super) fn take_table(&mut self, table: ParamTable) {
        self.params = table;
        self.files.params_stale = true;
    }

    /// The changed parameters' PARAM_VALUEs to every peer of every link, once due.
    pub(super) fn announce_changed_params(&mut self, now: Now) {
        for index in self.changed_params.take_due(now.wall_s) {
            if let Some(msg) = param_value(&self.params, index) {
                self.broadcast(now, &msg);
            }
        }
    }

    /// The PARAM_VALUEs of every list that are due by `now`.
    pub(super) fn stream_param_lists(&mut self, now: Now) {
        let mut lists = std::mem::take(&mut self.param_lists);
        for list in &mut lists {
            while list.next_s <= now.wall_s {
                let msg = if std::mem::take(&mut list.hash_pending) {
                    hash_check(&self.params)
                } else {
                    let Some(msg) = param_value(&self.params, list.next) else {
                        break;
                    };
                    list.next += 1;
                    msg
                };
                self.send(now, list.link, list.to, &msg);
                list.next_s += PARAM_LIST_PERIOD_S;
            }
        }
        lists.retain(|l| l.hash_pending || l.next < self.params.len());
        self.param_lists = lists;
    }

    /// PARAM_REQUEST_READ: by `index`, or by `name` without one.
    pub(super) fn param_read(
        &mut self,
        now: Now,
        link: LinkKind,
        to: A,
        header: &MavHeader,
        name: &str,
        index: Option<usize>,
    ) {
        let found = match index {
            None if name == HASH_CHECK => Some(hash_check(&self.params)),
            _ => index
                .or_else(|| self.params.index_of(name))
                .and_then(|i| param_value(&self.params, i)),
        };
        match found {
            Some(msg) => self.send(now, link, to, &msg),
            None => self.send(now, link, to, &param_error_unknown(header, name)),
        }
    }

    /// PARAM_SET: asks the vehicle, which answers at its next tick; `_HASH_CHECK`, whatever its
    /// value, stops the lists streaming to the sender and is not answered (as PX4 does).
    pub(super) fn param_set(&mut self, link: LinkKind, to: A, header: &MavHeader, name: String, value: f64) {
        if name == HASH_CHECK {
            self.param_lists.retain(|l| !(l.link == link && l.to == to));
            return;
        }
        let token = self.expect(Pending::Param(ParamSet {
            link,
            to,
            header: *header,
            name: name.clone(),
        }));
        self.to_vehicle.push_back(ToVehicle {
            token: Some(token),
            request: VehicleRequest::SetParam { name, value },
        });
    }

    /// The vehicle's answer to `set`.
    pub(super) fn param_set_done(&mut self, now: Now, set: ParamSet<A>, reply: VehicleReply) {
        let ParamSet { link, to, header, name } = set;
        let result = match reply {
            VehicleReply::Param { result, table } => {
                self.take_table(*table);
                Some(result)
            }
            _ => None,
        };
        match result {
            Some(Ok(index)) => {
                self.changed_params.changed(index, now.wall_s);
                if let Some(msg) = param_value(&self.params, index) {
                    let mut targets = self.port(link).map(|p| p.targets()).unwrap_or_default();
                    if !targets.contains(&to) {
                        targets.push(to);
                    }
                    for target in targets {
                        self.send(now, link, target, &msg);
                    }
                }
            }
            Some(Err(ParamError::Unknown(..))) => {
                self.send(now, link, to, &param_error_unknown(&header, &name));
                let text = format!("Unknown parameter {name}");
                self.send(now, link, to, &status_text(WARNING, &text));
            }
            refused => {
                if let Some(msg) = self.params.index_of(&name).and_then(|i| param_value(&self.params, i)) {
                    self.send(now, link, to, &msg);
                }
                let why = match refused {
                    Some(Err(e)) => e.to_string(),
                    _ => "Vehicle busy".to_string(),
                };
                self.send(now, link, to, &status_text(WARNING, &why));
            }
        }
    }
}
