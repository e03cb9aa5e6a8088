//! The MAVLink log protocol and the logs over MAVLink FTP, against the vehicle's MAVLink endpoint
//! with virtual clocks and an in-memory log store, as QGroundControl, MAVSDK and MAVProxy use
//! them: the list (empty, whole, ranged, re-requested), downloads in QGC's and MAVSDK's chunks
//! and MAVProxy's one request with its gap re-requests, a resume from an offset, requests past
//! the end, pacing in wall time, LOG_REQUEST_END, LOG_ERASE (the log being written stays), and
//! the same files listed and burst-read at PX4's FTP path.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use std::collections::BTreeMap;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::crc32::crc32_part;
use rotorpilot::mav::ftp::{Opcode, Payload};
use rotorpilot::mav::link::{LOG_MESSAGES_AT_ONCE, LOG_MESSAGE_PERIOD_S};
use rotorpilot::mav::logs::{MemLogStore, LOG_DATA_LEN};
use rotorpilot::mav::streams::LinkKind;

/// 2026-01-01 10:00:00, 2026-01-02 11:30:00 and 2026-01-02 12:00:00 UTC.
const TIMES: [u32; 3] = [1_767_261_600, 1_767_353_400, 1_767_355_200];
/// Their sizes: not a multiple of 90, a few bytes, a multiple of 90.
const SIZES: [usize; 3] = [20_001, 3, 180];

/// `n` pseudo-random bytes (a 32-bit LCG).
fn noise(n: usize, seed: u32) -> Vec<u8> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as u8
        })
        .collect()
}

fn logs() -> Vec<Vec<u8>> {
    SIZES.iter().enumerate().map(|(k, n)| noise(*n, k as u32 + 1)).collect()
}

/// A vehicle holding [`logs`]; `writing` marks one as being written.
fn bench(writing: Option<u32>) -> Bench {
    let mut store = MemLogStore::default();
    for (utc_s, bytes) in TIMES.iter().zip(logs()) {
        store.insert(*utc_s, bytes);
    }
    store.set_writing(writing);
    Bench::with(|c| c.logs = Box::new(store))
}

fn list_request(start: u16, end: u16) -> MavMessage {
    MavMessage::LOG_REQUEST_LIST(LOG_REQUEST_LIST_DATA {
        start,
        end,
        target_system: 1,
        target_component: 1,
    })
}

fn data_request(id: u16, ofs: u32, count: u32) -> MavMessage {
    MavMessage::LOG_REQUEST_DATA(LOG_REQUEST_DATA_DATA {
        ofs,
        count,
        id,
        target_system: 1,
        target_component: 1,
    })
}

/// The log messages sent to `to` while wall time advances 1 ms at a time, until 20 ms pass
/// without one (LOG_ENTRY and LOG_DATA carry no target: they go to the client that asked).
fn collect(b: &mut Bench, to: u16) -> Vec<MavMessage> {
    let (mut got, mut quiet_ms) = (Vec::new(), 0);
    while quiet_ms < 20 {
        let out = b.out();
        let mine: Vec<_> = out
            .iter()
            .filter(|(_, _, m)| matches!(m, MavMessage::LOG_ENTRY(_) | MavMessage::LOG_DATA(_)))
            .collect();
        assert!(mine.iter().all(|(_, dest, _)| *dest == to), "{mine:?}");
        assert!(mine.len() <= LOG_MESSAGES_AT_ONCE, "{} at once", mine.len());
        quiet_ms = if mine.is_empty() { quiet_ms + 1 } else { 0 };
        got.extend(mine.into_iter().map(|(_, _, m)| m.clone()));
        let (wall, sim) = (b.now.wall_s + 1e-3, b.now.sim_s);
        b.at(wall, sim);
    }
    got
}

fn entries(messages: &[MavMessage]) -> Vec<LOG_ENTRY_DATA> {
    messages
        .iter()
        .filter_map(|m| match m {
            MavMessage::LOG_ENTRY(e) => Some(e.clone()),
            _ => None,
        })
        .collect()
}

fn pieces(messages: &[MavMessage]) -> Vec<LOG_DATA_DATA> {
    messages
        .iter()
        .filter_map(|m| match m {
            MavMessage::LOG_DATA(d) => Some(d.clone()),
            _ => None,
        })
        .collect()
}

/// `request` from QGC on the GCS link; the log messages it brings.
fn ask(b: &mut Bench, request: MavMessage) -> Vec<MavMessage> {
    b.send(Gcs, QGC, request);
    collect(b, QGC)
}

#[test]
fn the_list_numbers_the_logs_oldest_first_with_their_names_time() {
    let mut b = bench(None);
    let listed = entries(&ask(&mut b, list_request(0, 0xFFFF)));
    let got: Vec<_> = listed
        .iter()
        .map(|e| (e.id, e.num_logs, e.last_log_num, e.size, e.time_utc))
        .collect();
    assert_eq!(
        got,
        vec![
            (0, 3, 2, 20_001, TIMES[0]),
            (1, 3, 2, 3, TIMES[1]),
            (2, 3, 2, 180, TIMES[2])
        ]
    );
    // QGC re-requests the entries it missed: the range, answered from the same snapshot.
    let again = entries(&ask(&mut b, list_request(1, 1)));
    assert_eq!(
        again.iter().map(|e| (e.id, e.last_log_num)).collect::<Vec<_>>(),
        vec![(1, 1)]
    );
    let past = entries(&ask(&mut b, list_request(9, 0xFFFF)));
    assert_eq!(
        past.iter().map(|e| e.id).collect::<Vec<_>>(),
        vec![2],
        "clamped to the last"
    );
    // Another system's request is not ours.
    let mut other = list_request(0, 0xFFFF);
    if let MavMessage::LOG_REQUEST_LIST(r) = &mut other {
        r.target_system = 7;
    }
    assert!(ask(&mut b, other).is_empty());
}

#[test]
fn without_logs_the_list_is_one_entry_saying_none() {
    let mut b = Bench::new();
    b.send(Api, SDK, list_request(0, 0xFFFF));
    let listed = entries(&collect(&mut b, SDK));
    assert_eq!(listed.len(), 1);
    let e = &listed[0];
    assert_eq!((e.num_logs, e.last_log_num, e.id, e.size, e.time_utc), (0, 0, 0, 0, 0));
    b.send(Api, SDK, data_request(0, 0, 90));
    assert!(collect(&mut b, SDK).is_empty(), "no log 0");
}

/// Downloads log `id` of `size` bytes in requests of `chunk` bytes (QGC: 512 bins of 90 bytes,
/// the last one rounded up to whole bins; MAVSDK: 46 080 bytes, the last one exact).
fn chunked(b: &mut Bench, id: u16, size: usize, chunk: usize, round_up: bool) -> Vec<u8> {
    let mut file = vec![0u8; size];
    let mut ofs = 0;
    while ofs < size {
        let rest = (size - ofs).min(chunk);
        let count = if round_up {
            rest.div_ceil(LOG_DATA_LEN) * LOG_DATA_LEN
        } else {
            rest
        };
        let got = pieces(&ask(b, data_request(id, ofs as u32, count as u32)));
        let want = rest.div_ceil(LOG_DATA_LEN);
        assert_eq!(got.len(), want, "one LOG_DATA per 90 bytes");
        for (k, d) in got.iter().enumerate() {
            assert_eq!((d.id, d.ofs as usize), (id, ofs + k * LOG_DATA_LEN), "aligned offsets");
            let n = usize::from(d.count);
            assert_eq!(n, (size - d.ofs as usize).min(LOG_DATA_LEN));
            file[d.ofs as usize..d.ofs as usize + n].copy_from_slice(&d.data[..n]);
        }
        ofs += rest;
    }
    file
}

#[test]
fn qgc_and_mavsdk_download_every_log_in_their_chunks() {
    let mut b = bench(None);
    ask(&mut b, list_request(0, 0xFFFF));
    for (id, bytes) in logs().iter().enumerate() {
        assert_eq!(
            &chunked(&mut b, id as u16, bytes.len(), 512 * 90, true),
            bytes,
            "QGC, log {id}"
        );
        assert_eq!(
            &chunked(&mut b, id as u16, bytes.len(), 512 * 90, false),
            bytes,
            "MAVSDK, log {id}"
        );
    }
}

#[test]
fn mavproxy_downloads_with_one_request_and_fills_gaps() {
    let mut b = bench(None);
    ask(&mut b, list_request(0, 0xFFFF));
    let bytes = &logs()[0];
    let all = pieces(&ask(&mut b, data_request(0, 0, u32::MAX)));
    assert_eq!(all.len(), 223);
    // The last piece is short: MAVProxy's end of the download.
    assert_eq!((all[222].ofs, all[222].count), (19_980, 21));
    // Pieces lost on the way (every 7th): re-requested as MAVProxy does, in 90-byte bins.
    let mut file: BTreeMap<u32, Vec<u8>> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| k % 7 != 3)
        .map(|(_, d)| (d.ofs, d.data[..usize::from(d.count)].to_vec()))
        .collect();
    let missing: Vec<u32> = (0..223u32).map(|k| k * 90).filter(|o| !file.contains_key(o)).collect();
    for ofs in missing {
        let got = pieces(&ask(&mut b, data_request(0, ofs, 90)));
        assert_eq!((got.len(), got[0].ofs), (1, ofs));
        file.insert(ofs, got[0].data[..usize::from(got[0].count)].to_vec());
    }
    assert_eq!(&file.into_values().flatten().collect::<Vec<_>>(), bytes);
    // A size that is a multiple of 90 ends on a full piece; MAVProxy then asks from the end and
    // gets MAVLink's empty LOG_DATA.
    let third = pieces(&ask(&mut b, data_request(2, 0, u32::MAX)));
    assert_eq!(third.iter().map(|d| d.count).collect::<Vec<_>>(), vec![90, 90]);
    let end = pieces(&ask(&mut b, data_request(2, 180, u32::MAX)));
    assert_eq!(end.iter().map(|d| (d.ofs, d.count)).collect::<Vec<_>>(), vec![(180, 0)]);
    let past = pieces(&ask(&mut b, data_request(0, 1_000_000, 90)));
    assert_eq!(
        past.iter().map(|d| (d.ofs, d.count)).collect::<Vec<_>>(),
        vec![(1_000_000, 0)]
    );
    assert!(ask(&mut b, data_request(3, 0, 90)).is_empty(), "no log 3: nothing");
}

#[test]
fn a_download_resumes_from_an_offset_and_is_paced_in_wall_time() {
    let mut b = bench(None);
    ask(&mut b, list_request(0, 0xFFFF));
    let bytes = &logs()[0];
    b.send(Gcs, QGC, data_request(0, 0, u32::MAX));
    let start = b.now.wall_s;
    let mut got = Vec::new();
    while got.len() < 60 {
        let (wall, sim) = (b.now.wall_s + 1e-3, b.now.sim_s);
        b.at(wall, sim);
        got.extend(pieces(&b.out().into_iter().map(|(_, _, m)| m).collect::<Vec<_>>()));
    }
    // One LOG_DATA per period of wall time, the first at once.
    let paced = (b.now.wall_s - start) / LOG_MESSAGE_PERIOD_S;
    assert!(
        (paced - 1.0..=paced + 2.0).contains(&(got.len() as f64)),
        "{} by {paced} periods",
        got.len()
    );
    // The client stops (QGC's cancel), then resumes where its file ends.
    b.send(
        Gcs,
        QGC,
        MavMessage::LOG_REQUEST_END(LOG_REQUEST_END_DATA {
            target_system: 1,
            target_component: 1,
        }),
    );
    assert!(collect(&mut b, QGC).is_empty(), "END stops the transfer");
    let have = got.len() * 90;
    let mut file = got
        .iter()
        .flat_map(|d| d.data[..usize::from(d.count)].to_vec())
        .collect::<Vec<_>>();
    let rest = pieces(&ask(&mut b, data_request(0, have as u32, u32::MAX)));
    assert_eq!(rest[0].ofs as usize, have);
    file.extend(rest.iter().flat_map(|d| d.data[..usize::from(d.count)].to_vec()));
    assert_eq!(&file, bytes);
    // After a stall (the link task woke 1 s late) a bounded batch, then the normal pace again.
    b.send(Gcs, QGC, data_request(0, 0, u32::MAX));
    b.out();
    let count = |b: &mut Bench, dt: f64| {
        let (wall, sim) = (b.now.wall_s + dt, b.now.sim_s);
        b.at(wall, sim);
        pieces(&b.out().into_iter().map(|(_, _, m)| m).collect::<Vec<_>>()).len()
    };
    assert_eq!(count(&mut b, 1.0), LOG_MESSAGES_AT_ONCE);
    let per_ms = (1e-3 / LOG_MESSAGE_PERIOD_S).round() as usize;
    assert!((per_ms - 1..=per_ms + 1).contains(&count(&mut b, 1e-3)), "no backlog");
}

#[test]
fn erase_deletes_every_log_but_the_one_being_written() {
    let mut b = bench(Some(TIMES[2]));
    ask(&mut b, list_request(0, 0xFFFF));
    b.send(
        Api,
        SDK,
        MavMessage::LOG_ERASE(LOG_ERASE_DATA {
            target_system: 1,
            target_component: 1,
        }),
    );
    assert!(collect(&mut b, SDK).is_empty(), "LOG_ERASE is not answered");
    assert!(
        ask(&mut b, data_request(0, 0, 90)).is_empty(),
        "the old ids are gone: list again"
    );
    let listed = entries(&ask(&mut b, list_request(0, 0xFFFF)));
    assert_eq!(
        listed
            .iter()
            .map(|e| (e.id, e.num_logs, e.size, e.time_utc))
            .collect::<Vec<_>>(),
        vec![(0, 1, 180, TIMES[2])]
    );
    let mut b = bench(None);
    b.send(
        Gcs,
        QGC,
        MavMessage::LOG_ERASE(LOG_ERASE_DATA {
            target_system: 1,
            target_component: 1,
        }),
    );
    let listed = entries(&ask(&mut b, list_request(0, 0xFFFF)));
    assert_eq!(
        listed.iter().map(|e| e.num_logs).collect::<Vec<_>>(),
        vec![0],
        "an empty list"
    );
}

/// One FTP request from QGC; the replies (with the burst frames due over the next 2 s).
fn ftp(b: &mut Bench, req: Payload) -> Vec<Payload> {
    b.send(Gcs, QGC, req.message((1, 1)));
    let mut out: Vec<(LinkKind, u16, MavMessage)> = b.out();
    for _ in 0..2000 {
        let (wall, sim) = (b.now.wall_s + 1e-3, b.now.sim_s);
        b.at(wall, sim);
        out.extend(b.out());
    }
    out.iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::FILE_TRANSFER_PROTOCOL(f) => Some(Payload::decode(&f.payload)),
            _ => None,
        })
        .collect()
}

#[test]
fn the_logs_are_files_at_px4s_ftp_path() {
    let mut b = bench(None);
    let listing = |b: &mut Bench, seq: u16, dir: &[u8]| -> Vec<String> {
        let r = ftp(b, Payload::request(Opcode::ListDirectory, seq, 0, 0, dir));
        assert_eq!(r[0].opcode, 128, "{r:?}");
        r[0].data
            .split(|c| *c == 0)
            .filter(|e| !e.is_empty())
            .map(|e| String::from_utf8(e.to_vec()).unwrap())
            .collect()
    };
    assert_eq!(
        listing(&mut b, 0, b"/fs/microsd/log"),
        vec!["D2026-01-01", "D2026-01-02"]
    );
    assert_eq!(
        listing(&mut b, 2, b"/fs/microsd/log/2026-01-02"),
        vec!["F11_30_00.ulg\t3", "F12_00_00.ulg\t180"]
    );
    let path = b"/fs/microsd/log/2026-01-01/10_00_00.ulg";
    let open = ftp(&mut b, Payload::request(Opcode::OpenFileRO, 4, 0, 0, path));
    assert_eq!((open[0].opcode, open[0].data_u32()), (128, Some(20_001)));
    let burst = ftp(
        &mut b,
        Payload::request(Opcode::BurstReadFile, 6, open[0].session, 0, &[]),
    );
    let (eof, frames) = burst.split_last().unwrap();
    assert_eq!(
        (eof.opcode, eof.data.clone()),
        (129, vec![6]),
        "the burst ends with EOF"
    );
    let file: Vec<u8> = frames.iter().flat_map(|f| f.data.clone()).collect();
    assert_eq!(file, logs()[0]);
    // A gap read back with ReadFile, as QGC's FTP manager does.
    let read = ftp(
        &mut b,
        Payload::request(Opcode::ReadFile, 8, open[0].session, 19_900, &[0; 239]),
    );
    assert_eq!(read[0].data, logs()[0][19_900..]);
    let crc = ftp(&mut b, Payload::request(Opcode::CalcFileCRC32, 10, 0, 0, path));
    assert_eq!(crc[0].data_u32(), Some(crc32_part(&logs()[0], 0)));
    // Read-only for clients.
    let remove = ftp(&mut b, Payload::request(Opcode::RemoveFile, 12, 0, 0, path));
    assert_eq!((remove[0].opcode, remove[0].data[0]), (129, 9));
}
