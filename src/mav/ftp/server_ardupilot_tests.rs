//! The FTP server under ArduPilot's session rule (and PX4's, side by side).

use super::*;
use crate::mav::ftp::Vfs;

const ACK: u8 = 128;
const SESSION: u8 = 153;

fn fs() -> Storage {
    let mut fs = Vfs::new(1000);
    fs.publish("/etc/extras/big.bin", (0..600u32).map(|i| i as u8).collect())
        .unwrap();
    Storage::new(fs, Box::<crate::mav::logs::MemLogStore>::default())
}

fn req(op: Opcode, seq: u16, session: u8, offset: u32, data: &[u8]) -> Payload {
    Payload::request(op, seq, session, offset, data)
}

fn nak_code(p: &Payload) -> Option<u8> {
    (p.opcode == Opcode::Nak as u8).then(|| p.data[0])
}

fn ardupilot() -> FtpServer {
    FtpServer::new(SessionRule::ArduPilot)
}

const BIG: &[u8] = b"/etc/extras/big.bin\0";

#[test]
fn the_clients_session_number_is_the_sessions_number() {
    let (mut fs, mut s) = (fs(), ardupilot());
    assert_eq!(s.rule(), SessionRule::ArduPilot);
    let open = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 0, SESSION, 0, BIG), 0.0)
        .unwrap();
    assert_eq!((open.opcode, open.session, open.data_u32()), (ACK, SESSION, Some(600)));
    let read = s
        .handle(&mut fs, &req(Opcode::ReadFile, 1, SESSION, 590, &[0; 100]), 0.0)
        .unwrap();
    assert_eq!((read.session, read.opcode), (SESSION, ACK));
    assert_eq!(read.data, (590..600u32).map(|i| i as u8).collect::<Vec<_>>());
    let other = s
        .handle(&mut fs, &req(Opcode::ReadFile, 2, 7, 0, &[0; 10]), 0.0)
        .unwrap();
    assert_eq!(
        (nak_code(&other), other.session),
        (Some(4), 7),
        "InvalidSession, under its number"
    );
    let listing = s
        .handle(&mut fs, &req(Opcode::ListDirectory, 3, 0, 0, b"/"), 0.0)
        .unwrap();
    assert_eq!(nak_code(&listing), Some(4), "any request under another number");

    assert!(s
        .handle(&mut fs, &req(Opcode::BurstReadFile, 4, SESSION, 100, &[]), 0.0)
        .is_none());
    let mut got = Vec::new();
    while let Some(frame) = s.burst_frame(&mut fs, 0.0) {
        assert_eq!(frame.session, SESSION, "every burst frame carries the session");
        if frame.opcode == Opcode::Nak as u8 {
            assert_eq!(frame.data, vec![6]);
            break;
        }
        got.extend(frame.data);
    }
    assert_eq!(got, (100..600u32).map(|i| i as u8).collect::<Vec<_>>());

    let end = s
        .handle(&mut fs, &req(Opcode::TerminateSession, 6, SESSION, 0, &[]), 0.0)
        .unwrap();
    assert_eq!((end.opcode, end.session), (ACK, SESSION));
    let closed = s
        .handle(&mut fs, &req(Opcode::ReadFile, 8, SESSION, 0, &[0; 10]), 0.0)
        .unwrap();
    assert_eq!(nak_code(&closed), Some(10), "FileNotFound with nothing open");
    let again = s
        .handle(&mut fs, &req(Opcode::TerminateSession, 10, SESSION, 0, &[]), 0.0)
        .unwrap();
    assert_eq!(again.opcode, ACK, "ArduPilot ACKs a TerminateSession with nothing open");
    let next = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 12, 154, 0, BIG), 0.0)
        .unwrap();
    assert_eq!(
        (next.opcode, next.session),
        (ACK, 154),
        "the next transfer, its own number"
    );
}

#[test]
fn one_file_at_a_time_until_it_is_idle_for_three_seconds() {
    let (mut fs, mut s) = (fs(), ardupilot());
    s.handle(&mut fs, &req(Opcode::OpenFileRO, 0, SESSION, 0, BIG), 0.0);
    let same = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 2, SESSION, 0, BIG), 1.0)
        .unwrap();
    assert_eq!(nak_code(&same), Some(1), "Fail: a file is open");
    let other = s.handle(&mut fs, &req(Opcode::OpenFileRO, 4, 9, 0, BIG), 2.0).unwrap();
    assert_eq!(
        nak_code(&other),
        Some(4),
        "InvalidSession: another session's file is open"
    );
    for (seq, op) in [(6, Opcode::TerminateSession), (8, Opcode::ResetSessions)] {
        let ended = s.handle(&mut fs, &req(op, seq, 9, 0, &[]), 2.5).unwrap();
        assert_eq!((ended.opcode, ended.session), (ACK, 9), "{op:?} of another session");
    }
    let still = s
        .handle(&mut fs, &req(Opcode::ReadFile, 10, SESSION, 0, &[0; 4]), 3.0)
        .unwrap();
    assert_eq!(still.data, vec![0, 1, 2, 3], "and closes nothing");
    s.expire(100.0);
    // Idle for 3 s: another session takes the file's place.
    let taken = s.handle(&mut fs, &req(Opcode::OpenFileRO, 12, 9, 0, BIG), 6.0).unwrap();
    assert_eq!(
        (taken.opcode, taken.session),
        (ACK, 9),
        "kept past PX4's idle expiry, then taken"
    );
    let old = s
        .handle(&mut fs, &req(Opcode::ReadFile, 14, SESSION, 0, &[0; 4]), 6.5)
        .unwrap();
    assert_eq!(nak_code(&old), Some(4));
    // Idle for more than 3 s: an OpenFileRO under the same number opens afresh.
    let reopened = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 16, 9, 0, BIG), 10.0)
        .unwrap();
    assert_eq!(reopened.opcode, ACK);
    let create = s
        .handle(&mut fs, &req(Opcode::CreateFile, 18, 9, 0, b"/fs/microsd/a"), 20.0)
        .unwrap();
    assert_eq!(nak_code(&create), Some(1), "a write open never replaces an open file");
}

#[test]
fn a_repeated_request_gets_its_reply_only_under_its_session() {
    let (mut fs, mut s) = (fs(), ardupilot());
    let open = req(Opcode::OpenFileRO, 20, SESSION, 0, BIG);
    let first = s.handle(&mut fs, &open, 0.0).unwrap();
    assert_eq!(s.handle(&mut fs, &open, 0.1), Some(first), "the lost ACK again");
    let intruder = s.handle(&mut fs, &req(Opcode::OpenFileRO, 20, 8, 0, BIG), 0.2).unwrap();
    assert_eq!((nak_code(&intruder), intruder.session), (Some(4), 8));
}

#[test]
fn a_parameter_upload_under_the_clients_number() {
    let (mut fs, mut s) = (fs(), ardupilot());
    let create = s
        .handle(&mut fs, &req(Opcode::CreateFile, 0, 42, 0, b"@PARAM/param.pck"), 0.0)
        .unwrap();
    assert_eq!((create.opcode, create.session), (ACK, 42));
    let mut file = vec![0x1B, 0x67, 1, 0, 0, 0, 4, 7 << 4];
    file.extend(b"PARAM_01");
    file.extend(2.5f32.to_le_bytes());
    file[4] = file.len() as u8;
    let w = s
        .handle(&mut fs, &req(Opcode::WriteFile, 2, 42, 0, &file), 0.0)
        .unwrap();
    assert_eq!((w.opcode, w.session), (ACK, 42));
    let end = req(Opcode::TerminateSession, 4, 42, 0, &[]);
    assert_eq!(s.handle(&mut fs, &end, 0.0), None);
    let upload = s.take_upload().unwrap();
    assert_eq!(upload.parsed.map(|p| p.len()), Ok(1));
    let answer = s.answer_upload(&end, Ok(()));
    assert_eq!((answer.opcode, answer.session), (ACK, 42));
}

#[test]
fn px4s_rule_still_numbers_sessions_itself() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    assert_eq!(s.rule(), SessionRule::Px4);
    let open = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 0, SESSION, 0, BIG), 0.0)
        .unwrap();
    assert_eq!(
        (open.opcode, open.session),
        (ACK, 0),
        "the slot, not the client's number"
    );
    let read = s
        .handle(&mut fs, &req(Opcode::ReadFile, 2, SESSION, 0, &[0; 4]), 0.0)
        .unwrap();
    assert_eq!((nak_code(&read), read.session), (Some(4), SESSION));
    let slot = s
        .handle(&mut fs, &req(Opcode::ReadFile, 4, 0, 0, &[0; 4]), 0.0)
        .unwrap();
    assert_eq!(slot.data, vec![0, 1, 2, 3]);
    let end = s
        .handle(&mut fs, &req(Opcode::TerminateSession, 6, SESSION, 0, &[]), 0.0)
        .unwrap();
    assert_eq!(
        nak_code(&end),
        Some(4),
        "PX4 NAKs the end of a session it does not have"
    );
    assert_eq!(
        s,
        {
            let mut same = FtpServer::new(SessionRule::Px4);
            same.handle(&mut fs, &req(Opcode::OpenFileRO, 0, SESSION, 0, BIG), 0.0);
            same.handle(&mut fs, &req(Opcode::ReadFile, 2, SESSION, 0, &[0; 4]), 0.0);
            same.handle(&mut fs, &req(Opcode::ReadFile, 4, 0, 0, &[0; 4]), 0.0);
            same.handle(&mut fs, &req(Opcode::TerminateSession, 6, SESSION, 0, &[]), 0.0);
            same
        },
        "new(Px4) is the default server"
    );
}
