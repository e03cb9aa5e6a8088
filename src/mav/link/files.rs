//! MAVLink FTP on every link and the component metadata it serves: one [`FtpServer`] per link
//! (PX4 runs one per MAVLink instance) over the vehicle's one file system (the metadata and
//! scratch files in memory, the flight logs from the log store), replies to the sender, and
//! burst reads paced at one frame per [`FTP_BURST_PERIOD_S`] of wall time to the client that
//! asked; COMPONENT_METADATA / COMPONENT_INFORMATION carry the general metadata file's CRC.
//! `@PARAM/param.pck` packs the link's copy of the parameter table (refreshed at the first FTP
//! request after it changed); an uploaded one goes to `param_upload.rs`.

use std::hash::Hash;

use mavlink::dialects::common::MavMessage;
use mavlink::MavHeader;

use super::logs::LogLink;
use super::param_upload::Uploads;
use super::{LinkKind, LinkMachine, Now};
use crate::mav::ftp::{ErrorCode, FtpServer, Payload, Storage, Vfs};
use crate::mav::logs::LogStore;
use crate::mav::metadata::{self, MetadataFiles};
use crate::mav::params::packed_params;
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

/// The vehicle's files, the FTP servers and the log protocol of its links.
#[derive(Debug)]
pub(super) struct Files<A> {
    pub(super) fs: Storage,
    links: Vec<FtpLink<A>>,
    /// The log protocol of each link.
    pub(super) logs: Vec<LogLink<A>>,
    /// CRC-32 of the general metadata file.
    pub general_crc: u32,
    /// The parameter table changed since [`Storage::params`] was packed from it.
    pub(super) params_stale: bool,
    /// The parameter files uploaded and being applied.
    pub(super) uploads: Uploads<A>,
}

impl<A> Files<A> {
    /// The file system with the component metadata of `params` (`built` when the caller made
    /// them already) and the flight logs of `logs`, an FTP server and a log server per link of
    /// `links`.
    pub fn new(params: &ParamTable, built: Option<MetadataFiles>, links: &[LinkKind], logs: Box<dyn LogStore>) -> Self {
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
                server: FtpServer::default(),
                client: None,
                next_s: 0.0,
            })
            .collect();
        let mut fs = Storage::new(vfs, logs);
        fs.params = packed_params(params);
        Self {
            fs,
            links: ftp,
            logs: links.iter().map(|link| LogLink::new(*link)).collect(),
            general_crc,
            params_stale: false,
            uploads: Uploads::default(),
        }
    }

    /// Wall time the next burst frame or log message of any link is due [s].
    pub fn next_due_s(&self) -> Option<f64> {
        let bursts = self.links.iter().filter(|l| l.server.bursting()).map(|l| l.next_s);
        bursts
            .chain(self.logs.iter().filter_map(LogLink::due_s))
            .reduce(f64::min)
    }
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// The files served over MAVLink FTP from memory (metadata, scratch area).
    pub fn files(&self) -> &Vfs {
        &self.files.fs.vfs
    }

    /// One FTP request from `from` on `link`: the reply to the sender, a burst that starts, or
    /// an uploaded parameter file for the vehicle.
    pub(super) fn ftp(&mut self, now: Now, link: LinkKind, from: A, sender: &MavHeader, payload: &[u8; 251]) {
        let ids = (sender.system_id as u8, sender.component_id);
        let Files {
            fs,
            links,
            params_stale,
            ..
        } = &mut self.files;
        let Some(ftp) = links.iter_mut().find(|l| l.link == link) else {
            return;
        };
        if std::mem::take(params_stale) {
            fs.params = packed_params(&self.params);
        }
        match ftp.server.handle(fs, &Payload::decode(payload), now.wall_s) {
            Some(reply) => self.send(now, link, from, &reply.message(ids)),
            None => match ftp.server.take_upload() {
                Some(upload) => self.start_param_upload(now, (link, from, ids), upload),
                None => {
                    ftp.client = Some((from, ids));
                    ftp.next_s = now.wall_s;
                }
            },
        }
    }

    /// The answer to the upload's TerminateSession `request` from `to` (address, MAVLink ids) on
    /// `link`: an ACK, or a NAK with the error.
    pub(super) fn answer_param_upload(
        &mut self,
        now: Now,
        (link, to, ids): (LinkKind, A, (u8, u8)),
        request: &Payload,
        result: Result<(), ErrorCode>,
    ) {
        let Some(ftp) = self.files.links.iter_mut().find(|l| l.link == link) else {
            return;
        };
        let reply = ftp.server.answer_upload(request, result);
        self.send(now, link, to, &reply.message(ids));
    }

    /// The burst frames due by `now`, and idle sessions closed.
    pub(super) fn stream_ftp_bursts(&mut self, now: Now) {
        for k in 0..self.files.links.len() {
            let mut frames = Vec::new();
            let Files { fs, links, .. } = &mut self.files;
            let ftp = &mut links[k];
            ftp.server.expire(now.wall_s);
            while ftp.server.bursting() && ftp.next_s <= now.wall_s {
                match ftp.server.burst_frame(fs, now.wall_s) {
                    Some(frame) => frames.push(frame),
                    None => break,
                }
                ftp.next_s += FTP_BURST_PERIOD_S;
            }
            let (link, client) = (ftp.link, ftp.client);
            if let Some((to, ids)) = client {
                for frame in &frames {
                    self.send(now, link, to, &frame.message(ids));
                }
            }
        }
    }

    /// COMPONENT_METADATA at `now`.
    pub(super) fn component_metadata(&self, now: Now) -> MavMessage {
        metadata::component_metadata(self.files.general_crc, (now.wall_s * 1e3) as u32)
    }

    /// COMPONENT_INFORMATION at `now`.
    pub(super) fn component_information(&self, now: Now) -> MavMessage {
        metadata::component_information(self.files.general_crc, (now.wall_s * 1e3) as u32)
    }
}
