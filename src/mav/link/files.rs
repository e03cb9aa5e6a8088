//! MAVLink FTP on every link and the component metadata it serves: one [`FtpServer`] per link
//! (PX4 runs one per MAVLink instance) over the vehicle's one file system (the metadata and
//! scratch files in memory, the flight logs from the log store), replies to the sender, and
//! burst reads paced at one frame per [`FTP_BURST_PERIOD_S`] of wall time to the client that
//! asked; COMPONENT_METADATA / COMPONENT_INFORMATION carry the general metadata file's CRC.
//! `@PARAM/param.pck` packs the parameter table the link holds (the vehicle's, shared; packed
//! again at the first FTP request after it changed) under the personality's names (PX4's, or
//! ArduCopter's names, units and storage types); an uploaded one goes to `param_upload.rs`. The
//! servers number sessions as the personality's autopilot does ([`SessionRule`]).
//!
//! [`Files`] owns the file system and the FTP servers; the log protocol reads the flight logs
//! through it ([`Files::log_store`]).

use mavlink::dialects::ardupilotmega::MavMessage;

use super::effects::{Client, Effect};
use super::LinkKind;
use crate::mav::ftp::{ErrorCode, FtpServer, Payload, SessionRule, Storage, Vfs};
use crate::mav::identity::Personality;
use crate::mav::logs::LogStore;
use crate::mav::metadata::{self, MetadataFiles};
use crate::mav::param_encoding::Shown;
use crate::params::ParamTable;

/// Wall time between two frames of a burst read [s].
pub const FTP_BURST_PERIOD_S: f64 = 1e-3;

/// The FTP server of one link and where its burst goes.
#[derive(Debug)]
struct FtpLink<A> {
    link: LinkKind,
    server: FtpServer,
    /// The client of the burst in progress: address and MAVLink ids.
    client: Option<(A, (u8, u8))>,
    /// Wall time the next burst frame is due [s].
    next_s: f64,
}

/// The vehicle's files and the FTP servers of its links.
#[derive(Debug)]
pub(super) struct Files<A> {
    fs: Storage,
    links: Vec<FtpLink<A>>,
    /// CRC-32 of the general metadata file.
    general_crc: u32,
    /// The parameters changed since [`Storage::params`] was packed from them (or were never
    /// packed).
    params_stale: bool,
}

impl<A: Copy> Files<A> {
    /// The file system with the component metadata of `params` (`built` when the caller made
    /// them already) and the flight logs of `logs`, an FTP server per link of `links` numbering
    /// sessions as `personality`'s autopilot does.
    pub fn new(
        params: &ParamTable,
        built: Option<MetadataFiles>,
        links: &[LinkKind],
        logs: Box<dyn LogStore>,
        personality: Personality,
    ) -> Self {
        let mut vfs = Vfs::default();
        // The metadata paths are fixed and outside the scratch area, and the files are compressed
        // in memory: installing them cannot fail.
        let general_crc = match built {
            Some(files) => files.publish(&mut vfs),
            None => metadata::install(&mut vfs, params),
        }
        .unwrap_or_default();
        let ftp = links
            .iter()
            .map(|link| FtpLink {
                link: *link,
                server: FtpServer::new(session_rule(personality)),
                client: None,
                next_s: 0.0,
            })
            .collect();
        Self {
            // `@PARAM/param.pck` is packed at the first request, with what the link holds then.
            fs: Storage::new(vfs, logs),
            links: ftp,
            general_crc,
            params_stale: true,
        }
    }

    /// The files served from memory (metadata, scratch area).
    pub fn vfs(&self) -> &Vfs {
        &self.fs.vfs
    }

    /// The flight logs served.
    pub fn log_store(&mut self) -> &mut dyn LogStore {
        self.fs.logs.as_mut()
    }

    /// The parameter table changed: `@PARAM/param.pck` is packed again at the next request.
    pub fn params_changed(&mut self) {
        self.params_stale = true;
    }

    /// Wall time the next burst frame of any link is due [s].
    pub fn next_due_s(&self) -> Option<f64> {
        self.links
            .iter()
            .filter(|l| l.server.bursting())
            .map(|l| l.next_s)
            .reduce(f64::min)
    }

    /// One FTP request from `from` (MAVLink ids `ids`) on `link` at wall time `wall_s` [s],
    /// `params` the table as it is: the reply to the sender, a burst that starts, or an uploaded
    /// parameter file for the vehicle.
    pub fn ftp(
        &mut self,
        wall_s: f64,
        (link, from, ids): Client<A>,
        payload: &[u8; 251],
        shown: Shown<'_>,
    ) -> Vec<Effect<A>> {
        let Self {
            fs,
            links,
            params_stale,
            ..
        } = self;
        let Some(ftp) = links.iter_mut().find(|l| l.link == link) else {
            return Vec::new();
        };
        if std::mem::take(params_stale) {
            fs.params = shown.packed();
        }
        match ftp.server.handle(fs, &Payload::decode(payload), wall_s) {
            Some(reply) => vec![Effect::send(link, from, reply.message(ids))],
            None => match ftp.server.take_upload() {
                Some(upload) => vec![Effect::Upload((link, from, ids), upload)],
                None => {
                    ftp.client = Some((from, ids));
                    ftp.next_s = wall_s;
                    Vec::new()
                }
            },
        }
    }

    /// The answer to the upload's TerminateSession `request` from `client`: an ACK, or a NAK
    /// with the error.
    pub fn answer_upload(
        &mut self,
        (link, to, ids): Client<A>,
        request: &Payload,
        result: Result<(), ErrorCode>,
    ) -> Vec<Effect<A>> {
        let Some(ftp) = self.links.iter_mut().find(|l| l.link == link) else {
            return Vec::new();
        };
        let reply = ftp.server.answer_upload(request, result);
        vec![Effect::send(link, to, reply.message(ids))]
    }

    /// The burst frames due by wall time `wall_s` [s], and idle sessions closed.
    pub fn stream_bursts(&mut self, wall_s: f64) -> Vec<Effect<A>> {
        let mut out = Vec::new();
        for ftp in &mut self.links {
            let mut frames = Vec::new();
            ftp.server.expire(wall_s);
            while ftp.server.bursting() && ftp.next_s <= wall_s {
                match ftp.server.burst_frame(&mut self.fs, wall_s) {
                    Some(frame) => frames.push(frame),
                    None => break,
                }
                ftp.next_s += FTP_BURST_PERIOD_S;
            }
            if let Some((to, ids)) = ftp.client {
                out.extend(frames.iter().map(|f| Effect::send(ftp.link, to, f.message(ids))));
            }
        }
        out
    }

    /// COMPONENT_METADATA at wall time `wall_s` [s].
    pub fn component_metadata(&self, wall_s: f64) -> MavMessage {
        metadata::component_metadata(self.general_crc, (wall_s * 1e3) as u32)
    }

    /// COMPONENT_INFORMATION at wall time `wall_s` [s].
    pub fn component_information(&self, wall_s: f64) -> MavMessage {
        metadata::component_information(self.general_crc, (wall_s * 1e3) as u32)
    }
}

/// How the FTP servers of a vehicle presented as `personality` number their sessions: PX4's
/// slots, or ArduPilot's (the client's number, one file at a time), so that MAVProxy's transfers,
/// which match replies by the random session number they sent, work against ArduCopter.
fn session_rule(personality: Personality) -> SessionRule {
    match personality {
        Personality::Px4 => SessionRule::Px4,
        Personality::ArduPilot => SessionRule::ArduPilot,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::ardupilot::copter_link_params::LinkParams;
    use crate::mav::ftp::Opcode;
    use crate::mav::link::effects::testing::{sent, table};
    use crate::mav::logs::MemLogStore;

    const ACK: u8 = 128;
    const CLIENT: Client<u16> = (LinkKind::Api, 9, (1, 1));

    fn replies(out: &[Effect<u16>]) -> Vec<Payload> {
        sent(out)
            .into_iter()
            .filter_map(|(_, to, m)| match m {
                MavMessage::FILE_TRANSFER_PROTOCOL(f) if to == 9 => Some(Payload::decode(&f.payload)),
                _ => None,
            })
            .collect()
    }

    /// `params` as PX4 shows them.
    fn shown(params: &ParamTable) -> Shown<'_> {
        static HELD: LinkParams = LinkParams {
            system_id: 1,
            stream_rates: Vec::new(),
        };
        Shown {
            personality: Personality::Px4,
            table: params,
            link: &HELD,
        }
    }

    fn request(op: Opcode, seq: u16, session: u8, data: &[u8]) -> [u8; 251] {
        Payload::request(op, seq, session, 0, data).encode()
    }

    #[test]
    fn a_burst_goes_to_its_client_one_frame_per_period() {
        let params = table();
        let mut f = Files::new(
            &params,
            None,
            &[LinkKind::Api],
            Box::new(MemLogStore::default()),
            Personality::Px4,
        );
        assert_ne!(f.component_metadata(0.0), f.component_information(0.0));
        let open = f.ftp(
            0.0,
            CLIENT,
            &request(Opcode::OpenFileRO, 0, 0, b"@PARAM/param.pck"),
            shown(&params),
        );
        assert_eq!(replies(&open)[0].opcode, ACK);
        let burst = f.ftp(0.0, CLIENT, &request(Opcode::BurstReadFile, 2, 0, &[]), shown(&params));
        assert!(burst.is_empty(), "a burst answers from the timer");
        assert_eq!(f.next_due_s(), Some(0.0));
        let frames = f.stream_bursts(2.5 * FTP_BURST_PERIOD_S);
        assert_eq!(replies(&frames).len(), 3, "one frame per period, to the client");
        let other = (LinkKind::Gcs, 9, (1, 1));
        assert!(f
            .ftp(0.0, other, &request(Opcode::ListDirectory, 0, 0, b"/"), shown(&params))
            .is_empty());
    }

    #[test]
    fn an_uploaded_parameter_file_goes_to_the_parameters_and_its_answer_back() {
        let params = table();
        let mut f = Files::new(
            &params,
            None,
            &[LinkKind::Api],
            Box::new(MemLogStore::default()),
            Personality::Px4,
        );
        let create = f.ftp(
            0.0,
            CLIENT,
            &request(Opcode::CreateFile, 0, 0, b"@PARAM/param.pck\0"),
            shown(&params),
        );
        let session = replies(&create)[0].session;
        let out = f.ftp(
            0.0,
            CLIENT,
            &request(Opcode::TerminateSession, 2, session, &[]),
            shown(&params),
        );
        let [Effect::Upload(client, upload)] = &out[..] else {
            panic!("{out:?}");
        };
        assert_eq!(*client, CLIENT);
        let answer = f.answer_upload(CLIENT, &upload.request, Ok(()));
        assert_eq!(replies(&answer)[0].opcode, ACK);
    }
}
