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
//!
//! [`Uploads`] owns the files being applied; the link carries out what it returns.

use std::collections::VecDeque;

use super::boundary::VehicleRequest;
use super::commands::Pending;
use super::effects::{Client, Effect};
use super::WARNING;
use crate::mav::ftp::{ErrorCode, ParamUpload, Payload, EINVAL};
use crate::mav::stream_messages::status_text;
use crate::params::ParamError;

/// PARAM_SETs of one upload waiting for the vehicle at once.
pub const UPLOAD_WINDOW: usize = 32;
/// Refusals of one upload told one by one; more are counted in one STATUSTEXT.
const REFUSALS_TOLD: usize = 5;

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

/// One PARAM_SET of an upload, waiting for the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct UploadSet {
    id: u64,
    /// The parameter's name.
    pub name: String,
}

impl<A: Copy> Uploads<A> {
    fn position(&self, id: u64) -> Option<usize> {
        self.list.iter().position(|u| u.id == id)
    }

    /// The upload of `client` whose TerminateSession came: refused when malformed, else its
    /// parameters asked of the vehicle as `setting` names them (the setting and its value for a
    /// file's name and value; unknown or refused, counted as the vehicle's answers are).
    pub fn start(
        &mut self,
        client: Client<A>,
        upload: ParamUpload,
        setting: impl Fn(&str, f64) -> Result<(String, f64), ParamError>,
    ) -> Vec<Effect<A>> {
        let ParamUpload { request, parsed } = upload;
        let entries = match parsed {
            Ok(entries) => entries,
            Err(e) => {
                let (link, to, _) = client;
                return vec![
                    Effect::send(link, to, status_text(WARNING, &format!("param.pck: {e}"))),
                    Effect::UploadAnswer(client, request, Err(ErrorCode::FailErrno(EINVAL))),
                ];
            }
        };
        let id = self.next_id;
        self.next_id += 1;
        let (mut queue, mut unknown, mut refused) = (VecDeque::new(), Vec::new(), Vec::new());
        for (name, v) in entries {
            match setting(&name, v.as_f64()) {
                Ok(set) => queue.push_back(set),
                Err(ParamError::Unknown(name, _)) => unknown.push(name),
                Err(e) => refused.push(e.to_string()),
            }
        }
        self.list.push(Upload {
            id,
            client,
            request,
            queue,
            in_flight: 0,
            unknown,
            refused,
        });
        self.pump(id)
    }

    /// Asks the vehicle for the next parameters of upload `id` while the window has room; answers
    /// the upload once every one is answered.
    fn pump(&mut self, id: u64) -> Vec<Effect<A>> {
        let Some(k) = self.position(id) else {
            return Vec::new();
        };
        let upload = &mut self.list[k];
        let room = UPLOAD_WINDOW.saturating_sub(upload.in_flight);
        let asks: Vec<(String, f64)> = (0..room).map_while(|_| upload.queue.pop_front()).collect();
        upload.in_flight += asks.len();
        if upload.in_flight == 0 {
            let done = self.list.remove(k);
            return finish(done);
        }
        asks.into_iter()
            .map(|(name, value)| {
                let set = UploadSet { id, name: name.clone() };
                Effect::Ask(Some(Pending::Upload(set)), VehicleRequest::SetParam { name, value })
            })
            .collect()
    }

    /// The vehicle's answer to one PARAM_SET of an upload.
    pub fn set_done(&mut self, set: UploadSet, result: Result<usize, ParamError>) -> Vec<Effect<A>> {
        let Some(k) = self.position(set.id) else {
            return Vec::new();
        };
        let upload = &mut self.list[k];
        upload.in_flight = upload.in_flight.saturating_sub(1);
        match result {
            Ok(_) => {}
            Err(ParamError::Unknown(name, _)) => upload.unknown.push(name),
            Err(refused) => upload.refused.push(refused.to_string()),
        }
        self.pump(set.id)
    }
}

/// What an applied upload's client hears: the refusals, the names skipped, the answer.
fn finish<A: Copy>(upload: Upload<A>) -> Vec<Effect<A>> {
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
    let mut out: Vec<Effect<A>> = texts
        .into_iter()
        .map(|text| Effect::send(link, to, status_text(WARNING, &text)))
        .collect();
    let result = match upload.refused.is_empty() {
        true => Ok(()),
        false => Err(ErrorCode::FailErrno(EINVAL)),
    };
    out.push(Effect::UploadAnswer(upload.client, upload.request, result));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::ftp::{Opcode, PackedValue, PckError};
    use crate::mav::link::effects::testing::texts;
    use crate::mav::streams::LinkKind;

    const CLIENT: Client<u16> = (LinkKind::Api, 3, (1, 1));

    fn as_named(name: &str, value: f64) -> Result<(String, f64), ParamError> {
        Ok((name.to_string(), value))
    }

    fn upload(parsed: Result<Vec<(String, PackedValue)>, PckError>) -> ParamUpload {
        ParamUpload {
            request: Payload::request(Opcode::TerminateSession, 9, 0, 0, &[]),
            parsed,
        }
    }

    fn asks(out: &[Effect<u16>]) -> Vec<UploadSet> {
        out.iter()
            .filter_map(|e| match e {
                Effect::Ask(Some(Pending::Upload(set)), _) => Some(set.clone()),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn at_most_a_window_waits_and_the_answer_follows_the_last_reply() {
        let mut u = Uploads::default();
        let entries = (0..UPLOAD_WINDOW + 3)
            .map(|k| (format!("P{k}"), PackedValue::Float(k as f32)))
            .collect();
        let mut waiting = asks(&u.start(CLIENT, upload(Ok(entries)), as_named));
        assert_eq!(waiting.len(), UPLOAD_WINDOW);
        let mut last = Vec::new();
        let mut asked = waiting.len();
        while let Some(set) = waiting.pop() {
            let result = match set.name.as_str() {
                "P1" => Err(ParamError::Invalid {
                    name: "P1".into(),
                    reason: "out of range".into(),
                }),
                "P2" => Err(ParamError::Unknown("P2".into(), String::new())),
                _ => Ok(0),
            };
            last = u.set_done(set, result);
            let more = asks(&last);
            asked += more.len();
            waiting.extend(more);
        }
        assert_eq!(asked, UPLOAD_WINDOW + 3, "each parameter asked once");
        assert_eq!(
            texts(&last),
            vec!["P1: out of range", "param.pck: 1 unknown skipped: P2"]
        );
        assert!(matches!(last.last(), Some(Effect::UploadAnswer(CLIENT, _, Err(_)))));
    }

    #[test]
    fn a_malformed_file_sets_nothing_and_is_refused() {
        let mut u = Uploads::default();
        let out = u.start(CLIENT, upload(Err(PckError::Query("x".into()))), as_named);
        assert!(asks(&out).is_empty());
        assert_eq!(texts(&out), vec!["param.pck: bad query: x"]);
        assert!(matches!(
            out.last(),
            Some(Effect::UploadAnswer(CLIENT, _, Err(ErrorCode::FailErrno(EINVAL))))
        ));
        let out = u.start(CLIENT, upload(Ok(Vec::new())), as_named);
        assert!(
            matches!(&out[..], [Effect::UploadAnswer(CLIENT, _, Ok(()))]),
            "an empty file"
        );
    }
}
