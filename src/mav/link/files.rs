//! MAVLink FTP on every link and the component metadata it serves: one [`FtpServer`] per link
//! (PX4 runs one per MAVLink instance) over the vehicle's one file system, replies to the
//! sender, and burst reads paced at one frame per [`FTP_BURST_PERIOD_S`] of wall time to the
//! client that asked; COMPONENT_METADATA / COMPONENT_INFORMATION carry the general metadata
//! file's CRC.

use std::hash::Hash;

use mavlink::dialects::common::{MavMessage, FILE_TRANSFER_PROTOCOL_DATA};
use mavlink::MavHeader;

use super::{LinkKind, LinkMachine, Now};
use crate::mav::ftp::{FtpServer, Payload, PublishError, Vfs};
use crate::mav::metadata;
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
    fs: Vfs,
    links: Vec<FtpLink<A>>,
    /// CRC-32 of the general metadata file.
    pub general_crc: u32,
}

impl<A> Files<A> {
    /// The file system with the component metadata of `params`, a server per link of `links`.
    pub fn new(params: &ParamTable, links: impl Iterator<Item = LinkKind>) -> Self {
        let mut fs = Vfs::default();
        // The metadata paths are fixed and outside the scratch area: publishing cannot fail.
        let general_crc = metadata::install(&mut fs, params).unwrap_or_default();
        let links = links
            .map(|link| FtpLink {
                link,
                server: FtpServer::default(),
                client: None,
                next_s: 0.0,
            })
            .collect();
        Self { fs, links, general_crc }
    }

    /// Wall time the next burst frame of any link is due [s].
    pub fn next_burst_s(&self) -> Option<f64> {
        self.links
            .iter()
            .filter(|l| l.server.bursting())
            .map(|l| l.next_s)
            .reduce(f64::min)
    }
}

/// FILE_TRANSFER_PROTOCOL with `payload` to the client with MAVLink ids `ids`.
fn ftp_message(ids: (u8, u8), payload: &Payload) -> MavMessage {
    MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
        target_network: 0,
        target_system: ids.0,
        target_component: ids.1,
        payload: payload.encode(),
    })
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// Publishes the flight log `name` (a file name) in the FTP log directory.
    pub fn handle_log_file(&mut self, name: &str, bytes: Vec<u8>) -> Result<(), PublishError> {
        self.files.fs.publish_log(name, bytes)
    }

    /// The files served over MAVLink FTP.
    pub fn files(&self) -> &Vfs {
        &self.files.fs
    }

    /// One FTP request from `from` on `link`: the reply to the sender, or a burst that starts.
    pub(super) fn ftp(&mut self, now: Now, link: LinkKind, from: A, sender: &MavHeader, payload: &[u8; 251]) {
        let ids = (sender.system_id as u8, sender.component_id);
        let Files { fs, links, .. } = &mut self.files;
        let Some(ftp) = links.iter_mut().find(|l| l.link == link) else {
            return;
        };
        match ftp.server.handle(fs, &Payload::decode(payload), now.wall_s) {
            Some(reply) => self.send(now, link, from, &ftp_message(ids, &reply)),
            None => {
                ftp.client = Some((from, ids));
                ftp.next_s = now.wall_s;
            }
        }
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
                    self.send(now, link, to, &ftp_message(ids, frame));
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
