//! MAVLink FTP sessions of an ArduCopter-faced vehicle (docs/ardupilot.md §5.1) through the
//! shipped link machine with virtual clocks: MAVProxy's parameter download, under the random
//! session number it picks, is answered under that number (open, burst frames, EOF, terminate),
//! one file at a time; a PX4-faced vehicle still numbers sessions itself.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use std::hash::{BuildHasher, RandomState};

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::ftp::{decode, Opcode, Payload, MAGIC_WITH_DEFAULTS};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::translate::Identity;

const ACK: u8 = 128;
const NAK: u8 = 129;
const PARAMS: &[u8] = b"@PARAM/param.pck?withdefaults=1";

fn bench(personality: Personality) -> Bench {
    Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(personality))
}

/// A session number as MAVProxy picks one: at random (printed by a failing assertion).
fn random_session() -> u8 {
    RandomState::new().hash_one("mavproxy") as u8
}

/// The FTP replies the vehicle sent since the last call.
fn replies(b: &mut Bench) -> Vec<Payload> {
    b.out()
        .into_iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::FILE_TRANSFER_PROTOCOL(f) => Some(Payload::decode(&f.payload)),
            _ => None,
        })
        .collect()
}

/// Sends `op` under `session` with sequence number `seq` from the GCS link's ground station.
fn send(b: &mut Bench, op: Opcode, seq: u16, session: u8, data: &[u8]) -> Vec<Payload> {
    let mut req = Payload::request(op, seq, session, 0, data);
    if op == Opcode::BurstReadFile {
        req.size = 239; // MAVProxy's burst size
    }
    b.send(Gcs, QGC, req.message((1, 1)));
    replies(b)
}

/// MAVProxy's download of the parameters under `session` from sequence number `seq`: open,
/// burst to EOF, terminate; every reply checked to carry `session`. The file's bytes.
fn download(b: &mut Bench, session: u8, seq: u16) -> Vec<u8> {
    let open = send(b, Opcode::OpenFileRO, seq, session, PARAMS);
    assert_eq!(open.len(), 1, "{open:?}");
    assert_eq!(
        (open[0].opcode, open[0].session),
        (ACK, session),
        "the open, session {session}"
    );
    let size = open[0].data_u32().unwrap() as usize;
    assert!(send(b, Opcode::BurstReadFile, seq + 1, session, &[]).is_empty());
    let (mut bytes, mut wall) = (Vec::new(), b.now.wall_s);
    'burst: while wall < b.now.wall_s + 5.0 {
        wall += 1e-3;
        b.at(wall, wall);
        for frame in replies(b) {
            assert_eq!(frame.session, session, "a burst frame under session {session}");
            if frame.opcode == NAK {
                assert_eq!(frame.data, vec![6], "EOF");
                break 'burst;
            }
            assert_eq!(frame.offset as usize, bytes.len());
            bytes.extend(frame.data);
        }
    }
    assert_eq!(bytes.len(), size);
    let end = send(b, Opcode::TerminateSession, seq + 2, session, &[]);
    assert_eq!((end[0].opcode, end[0].session), (ACK, session));
    bytes
}

#[test]
fn mavproxys_parameter_download_is_answered_under_its_random_session() {
    let mut b = bench(Personality::ArduPilot);
    let session = random_session();
    let file = decode(&download(&mut b, session, 0)).unwrap();
    assert_eq!(file.magic, MAGIC_WITH_DEFAULTS);
    // The table, then what the link holds: SYSID_THISMAV and SR0_*, SR1_* of the two links.
    let count = table().len() + 1 + 2 * 10;
    assert_eq!((file.entries.len(), usize::from(file.total)), (count, count));
    assert!(file.entries.iter().any(|e| e.name == "SR1_ADSB"));
    // MAVProxy's next transfer takes the next number; 0 and 255 are numbers like any other.
    for (k, next) in [session.wrapping_add(1), 0, 255].into_iter().enumerate() {
        let again = download(&mut b, next, 10 + 10 * k as u16);
        assert_eq!(decode(&again).unwrap().entries.len(), count, "session {next}");
    }
}

#[test]
fn a_second_session_waits_for_the_open_one() {
    let mut b = bench(Personality::ArduPilot);
    let session = random_session();
    let other = session.wrapping_add(128);
    let open = send(&mut b, Opcode::OpenFileRO, 0, session, PARAMS);
    assert_eq!(open[0].session, session);
    let refused = send(&mut b, Opcode::OpenFileRO, 0, other, PARAMS);
    assert_eq!(
        (refused[0].opcode, refused[0].data[0], refused[0].session),
        (NAK, 4, other)
    );
    let read = send(&mut b, Opcode::ReadFile, 2, session, &[0; 239]);
    assert_eq!(
        (read[0].opcode, read[0].session),
        (ACK, session),
        "the open one reads on"
    );
    assert_eq!(send(&mut b, Opcode::TerminateSession, 4, session, &[])[0].opcode, ACK);
    let opened = send(&mut b, Opcode::OpenFileRO, 2, other, PARAMS);
    assert_eq!((opened[0].opcode, opened[0].session), (ACK, other), "once it ended");
}

#[test]
fn a_px4_vehicle_still_names_the_session_itself() {
    let mut b = bench(Personality::Px4);
    let session = random_session() | 1;
    let open = send(&mut b, Opcode::OpenFileRO, 0, session, PARAMS);
    assert_eq!((open[0].opcode, open[0].session), (ACK, 0), "PX4's slot, not {session}");
    let read = send(&mut b, Opcode::ReadFile, 2, session, &[0; 239]);
    assert_eq!(
        (read[0].opcode, read[0].data[0]),
        (NAK, 4),
        "InvalidSession under {session}"
    );
}
