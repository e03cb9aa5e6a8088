//! A parameter file uploaded over MAVLink FTP (`@PARAM/param.pck`, CreateFile, WriteFile…,
//! TerminateSession), applied as PARAM_SETs are: once its TerminateSession came, each parameter
//! in file order goes to the vehicle as a PARAM_SET does (the same request, the same checks,
//! [`UPLOAD_WINDOW`] waiting at once so the vehicle's inbox never overflows), and each one set is
//! announced to every link 5 ms later as a PARAM_SET's is. The TerminateSession is answered
//! once the vehicle answered them all, as PX4 answers it once the file is applied:
//! - a malformed file (PX4's rules, [`parse_upload`](crate::mav::ftp::parse_upload)) sets
//!   nothing: NAK FailErrno EINVAL and a STATUSTEXT naming the fault;
//! - a name the vehicle does not have is skipped, as PX4 and ArduPilot skip it (a file saved by
//!   another firmware loads), with one STATUSTEXT counting them;
//! - a value the vehicle refuses (out of range, not an integer for an INT32, settings that do
//!   not validate) leaves that parameter as it was, with PARAM_SET's STATUSTEXT saying why, and
//!   the others are applied; the TerminateSession is then NAKed (FailErrno EINVAL), as PX4 NAKs
//!   an upload a parameter of which it could not set.

use std::collections::VecDeque;
use std::hash::Hash;

use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleReply, VehicleRequest, WARNING};
use crate::mav::ftp::{ErrorCode, ParamUpload, Payload, EINVAL};
use crate::mav::telemetry::status_text;
use crate::params::ParamError;

/// PARAM_SETs of one upload waiting for the vehicle at once.
pub const UPLOAD_WINDOW: usize = 32;
/// Refusals of one upload told one by one; more are counted in one STATUSTEXT.
const REFUSALS_TOLD: usize = 5;

/// Where an upload's answers go: link, client address, client's MAVLink ids.
type Client<A> = (LinkKind, A, (u8, u8));

/// One upload being applied.
#[derive(Debug)]
struct Upload<A> {
    id: u64,
    client: Client<A>,
    /// The TerminateSession to answer.
    request: Payload,
    /// Names and values not yet asked of the vehicle, in file order.
    queue: VecDeque<(String, f64)>,
    /// PARAM_SETs asked and not yet answered.
    in_flight: usize,
    /// Names the vehicle does not have.
    unknown: Vec<String>,
    /// Why the refused values were refused.
    refused: Vec<String>,
}

/// The uploads being applied.
#[derive(Debug)]
pub(super) struct Uploads<A> {
    list: Vec<Upload<A>>,
    next_id: u64,
}

impl<A> Default for Uploads<A> {
    fn default() -> Self {
        Self {
            list: Vec::new(),
            next_id: 0,
        }
    }
}

impl<A> Uploads<A> {
    fn position(&self, id: u64) -> Option<usize> {
        self.list.iter().position(|u| u.id == id)
    }
}

/// One PARAM_SET of an upload, waiting for the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct UploadSet {
    id: u64,
    name: String,
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// The upload of `client` whose TerminateSession came: refused when malformed, else its
    /// parameters asked of the vehicle.
    pub(super) fn start_param_upload(&mut self, now: Now, client: Client<A>, upload: ParamUpload) {
        let ParamUpload { request, parsed } = upload;
        let entries = match parsed {
            Ok(entries) => entries,
            Err(e) => {
                let (link, to, _) = client;
                self.send(now, link, to, &status_text(WARNING, &format!("param.pck: {e}")));
                self.answer_param_upload(now, client, &request, Err(ErrorCode::FailErrno(EINVAL)));
                return;
            }
        };
        let uploads = &mut self.files.uploads;
        let id = uploads.next_id;
        uploads.next_id += 1;
        uploads.list.push(Upload {
            id,
            client,
            request,
            queue: entries.into_iter().map(|(name, v)| (name, v.as_f64())).collect(),
            in_flight: 0,
            unknown: Vec::new(),
            refused: Vec::new(),
        });
        self.pump_param_upload(now, id);
    }

    /// Asks the vehicle for the next parameters of upload `id` while the window has room; answers
    /// the upload once every one is answered.
    fn pump_param_upload(&mut self, now: Now, id: u64) {
        let Some(k) = self.files.uploads.position(id) else {
            return;
        };
        let upload = &mut self.files.uploads.list[k];
        let room = UPLOAD_WINDOW.saturating_sub(upload.in_flight);
        let asks: Vec<(String, f64)> = (0..room).map_while(|_| upload.queue.pop_front()).collect();
        upload.in_flight += asks.len();
        if upload.in_flight == 0 {
            let done = self.files.uploads.list.remove(k);
            self.finish_param_upload(now, done);
            return;
        }
        for (name, value) in asks {
            let token = self.expect(Pending::Upload(UploadSet { id, name: name.clone() }));
            self.to_vehicle.push_back(ToVehicle {
                token: Some(token),
                request: VehicleRequest::SetParam { name, value },
            });
        }
    }

    /// The vehicle's answer to one PARAM_SET of an upload.
    pub(super) fn upload_set_done(&mut self, now: Now, set: UploadSet, reply: VehicleReply) {
        let result = match reply {
            VehicleReply::Param { result, table } => {
                self.take_table(*table);
                result
            }
            _ => Err(ParamError::Invalid {
                name: set.name,
                reason: "vehicle busy".into(),
            }),
        };
        if let Ok(index) = result {
            self.changed_params.changed(index, now.wall_s);
        }
        let Some(k) = self.files.uploads.position(set.id) else {
            return;
        };
        let upload = &mut self.files.uploads.list[k];
        upload.in_flight = upload.in_flight.saturating_sub(1);
        match result {
            Ok(_) => {}
            Err(ParamError::Unknown(name, _)) => upload.unknown.push(name),
            Err(refused) => upload.refused.push(refused.to_string()),
        }
        self.pump_param_upload(now, set.id);
    }

    /// What an applied upload's client hears: the refusals, the names skipped, the answer.
    fn finish_param_upload(&mut self, now: Now, upload: Upload<A>) {
        let (link, to, _) = upload.client;
        let mut texts: Vec<String> = upload.refused.iter().take(REFUSALS_TOLD).cloned().collect();
        if upload.refused.len() > REFUSALS_TOLD {
            texts.push(format!(
                "param.pck: {} more refused",
                upload.refused.len() - REFUSALS_TOLD
            ));
        }
        if let Some(first) = upload.unknown.first() {
            texts.push(format!("param.pck: {} unknown skipped: {first}", upload.unknown.len()));
        }
        for text in texts {
            self.send(now, link, to, &status_text(WARNING, &text));
        }
        let result = match upload.refused.is_empty() {
            true => Ok(()),
            false => Err(ErrorCode::FailErrno(EINVAL)),
        };
        self.answer_param_upload(now, upload.client, &upload.request, result);
    }
}
