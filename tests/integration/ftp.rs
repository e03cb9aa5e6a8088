//! MAVLink FTP and component metadata against the vehicle's MAVLink endpoint with virtual
//! clocks, as QGroundControl and MAVSDK use them: list, open, read, burst-read, CRC, the
//! scratch area, escapes and sessions; COMPONENT_METADATA pointing at `.xz` files that download
//! and inflate.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::crc32::crc32_part;
use rotorpilot::mav::ftp::{Opcode, Payload};
use rotorpilot::mav::streams::LinkKind;

const ACK: u8 = 128;
const NAK: u8 = 129;

/// Sends `req` from QGC on the GCS link; the FTP replies that came back at once.
fn ftp(b: &mut Bench, req: Payload) -> Vec<Payload> {
    b.send(Gcs, QGC, req.message((1, 1)));
    replies(&b.out())
}

fn replies(out: &[(LinkKind, u16, MavMessage)]) -> Vec<Payload> {
    out.iter()
        .filter_map(|(_, to, m)| match m {
            MavMessage::FILE_TRANSFER_PROTOCOL(f) => {
                assert_eq!((*to, f.target_system, f.target_component), (QGC, 255, 190));
                Some(Payload::decode(&f.payload))
            }
            _ => None,
        })
        .collect()
}

/// The one reply to `req`.
fn one(b: &mut Bench, op: Opcode, seq: u16, session: u8, offset: u32, data: &[u8]) -> Payload {
    let r = ftp(b, Payload::request(op, seq, session, offset, data));
    assert_eq!(r.len(), 1, "{op:?}: {r:?}");
    assert_eq!(r[0].seq, seq.wrapping_add(1));
    assert_eq!(r[0].req_opcode, op as u8);
    r[0].clone()
}

fn nak(p: &Payload) -> Option<u8> {
    (p.opcode == NAK).then(|| p.data[0])
}

/// Lists `dir` from entry 0 on, as QGroundControl does, until EOF.
fn list(b: &mut Bench, seq: &mut u16, dir: &str) -> Vec<String> {
    let mut entries = Vec::new();
    loop {
        let r = one(b, Opcode::ListDirectory, *seq, 0, entries.len() as u32, dir.as_bytes());
        *seq += 2;
        if nak(&r) == Some(6) {
            return entries;
        }
        assert_eq!(r.opcode, ACK, "{r:?}");
        for e in r.data.split(|c| *c == 0).filter(|e| !e.is_empty()) {
            entries.push(String::from_utf8(e.to_vec()).unwrap());
        }
    }
}

/// Downloads `path` as QGroundControl does: OpenFileRO, a burst paced in wall time until the
/// NAK EOF, ResetSessions.
fn download(b: &mut Bench, seq: &mut u16, path: &str) -> Vec<u8> {
    let open = one(b, Opcode::OpenFileRO, *seq, 0, 0, path.as_bytes());
    assert_eq!(open.opcode, ACK, "open {path}: {open:?}");
    let size = open.data_u32().unwrap() as usize;
    assert!(ftp(
        b,
        Payload::request(Opcode::BurstReadFile, *seq + 2, open.session, 0, &[])
    )
    .is_empty());
    let mut bytes = Vec::new();
    let mut expected_seq = *seq + 3;
    let mut wall = b.now.wall_s;
    loop {
        wall += 1e-3;
        b.at(wall, b.now.sim_s);
        for frame in replies(&b.out()) {
            assert_eq!(frame.seq, expected_seq);
            expected_seq += 1;
            if frame.opcode == NAK {
                assert_eq!(frame.data, vec![6], "a burst ends with EOF");
                assert_eq!(bytes.len(), size);
                let reset = one(b, Opcode::ResetSessions, expected_seq, 0, 0, &[]);
                assert_eq!(reset.opcode, ACK);
                *seq = expected_seq + 2;
                return bytes;
            }
            assert_eq!((frame.req_opcode, frame.offset as usize), (15, bytes.len()));
            bytes.extend(frame.data);
        }
        assert!(wall < 10.0, "the burst never ended");
    }
}

/// An `.xz` file inflated.
fn unxz(xz: &[u8]) -> Vec<u8> {
    use std::io::Read;
    let mut out = Vec::new();
    lzma_rust2::XzReader::new(xz, false).read_to_end(&mut out).unwrap();
    out
}

fn request(id: f32) -> MavMessage {
    let params = [id, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    MavMessage::COMMAND_LONG(rotorpilot::mav::gcs::command_long(
        (1, 1),
        MavCmd::MAV_CMD_REQUEST_MESSAGE,
        params,
    ))
}

#[test]
fn qgc_finds_the_component_metadata_and_downloads_it_by_ftp() {
    let mut b = Bench::new();
    b.send(Gcs, QGC, request(148.0));
    let out = b.out();
    let version = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::AUTOPILOT_VERSION(v) => Some(v.capabilities),
        _ => None,
    });
    assert!(version
        .unwrap()
        .contains(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_FTP));

    b.send(Gcs, QGC, request(397.0));
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
    let [(_, _, MavMessage::COMPONENT_METADATA(meta))] = &named(&out, "COMPONENT_METADATA")[..] else {
        panic!("{out:?}")
    };
    let uri = meta.uri.to_str().unwrap().to_string();
    assert_eq!(uri, "mftp://etc/extras/component_general.json.xz");
    b.send(Gcs, QGC, request(395.0));
    let out = b.out();
    let [(_, _, MavMessage::COMPONENT_INFORMATION(info))] = &named(&out, "COMPONENT_INFORMATION")[..] else {
        panic!("{out:?}")
    };
    assert_eq!(info.general_metadata_file_crc, meta.file_crc);

    // QGC keeps the slash after the scheme: it asks for "/etc/...".
    let mut seq = 0;
    let general_xz = download(&mut b, &mut seq, &uri["mftp:/".len()..]);
    let general = unxz(&general_xz);
    assert_eq!(
        crc32_part(&general, 0),
        meta.file_crc,
        "file_crc is PX4's CRC-32 of the uncompressed file"
    );
    let doc: serde_json::Value = serde_json::from_slice(&general).unwrap();
    let types = &doc["metadataTypes"][0];
    assert_eq!(types["type"], 1);
    let param_uri = types["uri"].as_str().unwrap();
    let params_xz = download(&mut b, &mut seq, &param_uri["mftp:/".len()..]);
    assert!(params_xz.len() > 2000, "more than one burst frame: {}", params_xz.len());
    assert_eq!(
        types["fileCrc"].as_u64(),
        Some(u64::from(crc32_part(&params_xz, 0))),
        "fileCrc is the CRC of the served .xz file"
    );
    let crc = one(
        &mut b,
        Opcode::CalcFileCRC32,
        seq,
        0,
        0,
        b"/etc/extras/parameters.json.xz\0",
    );
    assert_eq!(crc.data_u32(), Some(crc32_part(&params_xz, 0)));
    let doc: serde_json::Value = serde_json::from_slice(&unxz(&params_xz)).unwrap();
    let names: Vec<&str> = doc["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names.len(), table().len());
    assert!(names.contains(&"RP_PAS_KA_Y"));

    seq += 2;
    assert_eq!(list(&mut b, &mut seq, "/"), vec!["Detc", "Dfs"]);
    let extras = list(&mut b, &mut seq, "/etc/extras");
    assert_eq!(
        extras,
        vec![
            format!("Fcomponent_general.json.xz\t{}", general_xz.len()),
            format!("Fparameters.json.xz\t{}", params_xz.len())
        ]
    );
    assert_eq!(
        list(&mut b, &mut seq, "/fs/microsd/log"),
        Vec::<String>::new(),
        "no logs yet: EOF at once"
    );
}

#[test]
fn the_scratch_area_takes_files_and_nothing_escapes() {
    let mut b = Bench::new();
    let d = one(&mut b, Opcode::CreateDirectory, 0, 0, 0, b"/fs/microsd/mission");
    assert_eq!(d.opcode, ACK);
    let create = one(&mut b, Opcode::CreateFile, 2, 0, 0, b"/fs/microsd/mission/plan.txt\0");
    assert_eq!(create.opcode, ACK);
    // A second open while the first session is held: PX4 has one session per link.
    let busy = one(&mut b, Opcode::OpenFileRO, 4, 0, 0, b"/etc/extras/parameters.json.xz");
    assert_eq!(nak(&busy), Some(5));
    let text = b"waypoint 1\nwaypoint 2\n";
    let w = one(&mut b, Opcode::WriteFile, 6, create.session, 0, text);
    assert_eq!(w.data_u32(), Some(text.len() as u32));
    // The ACK was lost: the same request gets the same reply, nothing written twice.
    assert_eq!(
        ftp(&mut b, Payload::request(Opcode::WriteFile, 6, create.session, 0, text)),
        vec![w]
    );
    assert_eq!(
        one(&mut b, Opcode::TerminateSession, 8, create.session, 0, &[]).opcode,
        ACK
    );
    let open = one(&mut b, Opcode::OpenFileRO, 10, 0, 0, b"/fs/microsd/mission/plan.txt");
    assert_eq!(open.data_u32(), Some(text.len() as u32));
    let read = one(&mut b, Opcode::ReadFile, 12, open.session, 0, &[0; 239]);
    assert_eq!(read.data, text);
    assert_eq!(
        one(&mut b, Opcode::TerminateSession, 14, open.session, 0, &[]).opcode,
        ACK
    );
    let crc = one(&mut b, Opcode::CalcFileCRC32, 16, 0, 0, b"/fs/microsd/mission/plan.txt");
    assert_eq!(crc.data_u32(), Some(crc32_part(text, 0)));
    let mv = one(
        &mut b,
        Opcode::Rename,
        18,
        0,
        0,
        b"/fs/microsd/mission/plan.txt\0/fs/microsd/plan.txt\0",
    );
    assert_eq!(mv.opcode, ACK);
    assert_eq!(
        one(&mut b, Opcode::RemoveDirectory, 20, 0, 0, b"/fs/microsd/mission").opcode,
        ACK
    );
    assert_eq!(
        one(&mut b, Opcode::TruncateFile, 22, 0, 4, b"/fs/microsd/plan.txt").opcode,
        ACK
    );
    assert_eq!(b.m.files().read("/fs/microsd/plan.txt").unwrap(), b"wayp");
    assert_eq!(
        one(&mut b, Opcode::RemoveFile, 24, 0, 0, b"/fs/microsd/plan.txt").opcode,
        ACK
    );
    assert_eq!(
        nak(&one(&mut b, Opcode::RemoveFile, 26, 0, 0, b"/fs/microsd/plan.txt")),
        Some(10)
    );

    // Escapes and writes outside the scratch area.
    for (k, path) in [
        &b"/fs/microsd/../../etc/extras/parameters.json.xz"[..],
        b"../etc/extras/parameters.json.xz",
        b"/fs/microsd/log/../x",
    ]
    .into_iter()
    .enumerate()
    {
        let r = one(&mut b, Opcode::OpenFileRO, 30 + 2 * k as u16, 0, 0, path);
        assert_eq!(nak(&r), Some(9), "{}", String::from_utf8_lossy(path));
    }
    assert_eq!(
        nak(&one(
            &mut b,
            Opcode::CreateFile,
            40,
            0,
            0,
            b"/etc/extras/parameters.json.xz"
        )),
        Some(9)
    );
    assert_eq!(
        nak(&one(
            &mut b,
            Opcode::RemoveFile,
            42,
            0,
            0,
            b"/etc/extras/parameters.json.xz"
        )),
        Some(9)
    );
    assert_eq!(nak(&one(&mut b, Opcode::CreateDirectory, 44, 0, 0, b"/tmp")), Some(9));
    assert_eq!(
        nak(&one(&mut b, Opcode::OpenFileRO, 46, 0, 0, b"/etc/passwd")),
        Some(10)
    );
    assert_eq!(nak(&one(&mut b, Opcode::OpenFileRO, 48, 0, 0, &[0xff, 0x00])), Some(1));
    let mut unknown = Payload::request(Opcode::None, 50, 0, 0, &[]);
    unknown.opcode = 99;
    assert_eq!(nak(&ftp(&mut b, unknown)[0]), Some(7));
    // The flight logs' directory is the log store's (tests/integration/log_download.rs): read-only.
    for (k, path) in [&b"/fs/microsd/log/x.ulg"[..], b"/fs/microsd/log/2026-01-01"]
        .into_iter()
        .enumerate()
    {
        let create = if k == 0 {
            Opcode::CreateFile
        } else {
            Opcode::CreateDirectory
        };
        assert_eq!(nak(&one(&mut b, create, 60 + 2 * k as u16, 0, 0, path)), Some(9));
    }
}
