use super::*;
use crate::mav::crc32::crc32_part;
use crate::mav::ftp::payload::{EINVAL, ENOSPC};
use crate::mav::ftp::Vfs;

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

#[test]
fn open_read_and_terminate_a_file() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    let open = s
        .handle(
            &mut fs,
            &req(Opcode::OpenFileRO, 10, 0, 0, b"/etc/extras/big.bin\0"),
            0.0,
        )
        .unwrap();
    assert_eq!(
        (open.seq, open.opcode, open.req_opcode, open.data_u32()),
        (11, 128, 4, Some(600))
    );
    let read = s
        .handle(&mut fs, &req(Opcode::ReadFile, 12, open.session, 590, &[0; 100]), 0.0)
        .unwrap();
    assert_eq!(read.data, (590..600u32).map(|i| i as u8).collect::<Vec<_>>());
    let eof = s
        .handle(&mut fs, &req(Opcode::ReadFile, 14, 0, 600, &[0; 10]), 0.0)
        .unwrap();
    assert_eq!(nak_code(&eof), Some(6));
    let second = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 16, 0, 0, b"/etc/extras/big.bin"), 0.0)
        .unwrap();
    assert_eq!(nak_code(&second), Some(5), "one session per link, as PX4");
    let bad = s
        .handle(&mut fs, &req(Opcode::ReadFile, 18, 3, 0, &[0; 10]), 0.0)
        .unwrap();
    assert_eq!(nak_code(&bad), Some(4));
    let term = s
        .handle(&mut fs, &req(Opcode::TerminateSession, 20, 0, 0, &[]), 0.0)
        .unwrap();
    assert_eq!(term.opcode, 128);
    let again = s
        .handle(&mut fs, &req(Opcode::TerminateSession, 22, 0, 0, &[]), 0.0)
        .unwrap();
    assert_eq!(nak_code(&again), Some(4));
    let missing = s
        .handle(&mut fs, &req(Opcode::OpenFileRO, 24, 0, 0, b"/etc/nothing"), 0.0)
        .unwrap();
    assert_eq!((nak_code(&missing), missing.size), (Some(10), 1));
    let escape = s
        .handle(
            &mut fs,
            &req(Opcode::OpenFileRO, 26, 0, 0, b"/fs/../etc/extras/big.bin"),
            0.0,
        )
        .unwrap();
    assert_eq!(nak_code(&escape), Some(9));
}

#[test]
fn a_burst_streams_the_file_then_naks_eof() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    s.handle(&mut fs, &req(Opcode::OpenFileRO, 0, 0, 0, b"etc/extras/big.bin"), 0.0)
        .unwrap();
    assert!(s
        .handle(&mut fs, &req(Opcode::BurstReadFile, 2, 0, 100, &[]), 0.0)
        .is_none());
    let mut got = Vec::new();
    let mut seqs = Vec::new();
    while let Some(frame) = s.burst_frame(&mut fs, 0.0) {
        seqs.push(frame.seq);
        if frame.opcode == Opcode::Nak as u8 {
            assert_eq!(frame.data, vec![6]);
            break;
        }
        assert_eq!((frame.req_opcode, frame.offset as usize), (15, 100 + got.len()));
        got.extend(frame.data);
    }
    assert_eq!(got, (100..600u32).map(|i| i as u8).collect::<Vec<_>>());
    assert_eq!(seqs, vec![3, 4, 5, 6]);
    assert!(!s.bursting() && s.burst_frame(&mut fs, 0.0).is_none());
}

#[test]
fn a_repeated_request_gets_the_same_reply_without_running_again() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    let create = req(Opcode::CreateFile, 40, 0, 0, b"/fs/microsd/a.txt");
    let first = s.handle(&mut fs, &create, 0.0).unwrap();
    assert_eq!(first.opcode, 128);
    // Run again it would need a second session; the lost ACK is sent again instead.
    assert_eq!(s.handle(&mut fs, &create, 0.1), Some(first));
    let write = req(Opcode::WriteFile, 42, 0, 3, b"xyz");
    let w = s.handle(&mut fs, &write, 0.0).unwrap();
    assert_eq!(w.data_u32(), Some(3));
    assert_eq!(s.handle(&mut fs, &write, 0.0), Some(w));
    let crc = s
        .handle(
            &mut fs,
            &req(Opcode::CalcFileCRC32, 44, 0, 0, b"/fs/microsd/a.txt"),
            0.0,
        )
        .unwrap();
    assert_eq!(crc.data_u32(), Some(crc32_part(b"\0\0\0xyz", 0)));
    let big = s
        .handle(&mut fs, &req(Opcode::WriteFile, 46, 0, 0, &[1; 239]), 0.0)
        .unwrap();
    assert_eq!(big.data_u32(), Some(239));
    for (k, seq) in (48..60).step_by(2).enumerate() {
        let r = s.handle(
            &mut fs,
            &req(Opcode::WriteFile, seq, 0, 239 * (k as u32 + 1), &[1; 239]),
            0.0,
        );
        if let Some(code) = r.as_ref().and_then(nak_code) {
            assert_eq!(r.unwrap().data, vec![2, ENOSPC]);
            assert_eq!(code, 2);
            return;
        }
    }
    panic!("the scratch limit never refused a write");
}

#[test]
fn writes_need_a_write_session_and_paths_a_writable_place() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    s.handle(&mut fs, &req(Opcode::OpenFileRO, 0, 0, 0, b"/etc/extras/big.bin"), 0.0)
        .unwrap();
    let w = s.handle(&mut fs, &req(Opcode::WriteFile, 2, 0, 0, b"x"), 0.0).unwrap();
    assert_eq!(nak_code(&w), Some(9));
    s.handle(&mut fs, &req(Opcode::ResetSessions, 4, 0, 0, &[]), 0.0)
        .unwrap();
    let c = s
        .handle(&mut fs, &req(Opcode::CreateFile, 6, 0, 0, b"/etc/x"), 0.0)
        .unwrap();
    assert_eq!(nak_code(&c), Some(9));
    let d = s
        .handle(&mut fs, &req(Opcode::CreateDirectory, 8, 0, 0, b"/fs/microsd/d"), 0.0)
        .unwrap();
    assert_eq!(d.opcode, 128);
    let d = s
        .handle(&mut fs, &req(Opcode::CreateDirectory, 10, 0, 0, b"/fs/microsd/d"), 0.0)
        .unwrap();
    assert_eq!(nak_code(&d), Some(8));
    let r = s
        .handle(&mut fs, &req(Opcode::Rename, 12, 0, 0, b"/fs/microsd/d"), 0.0)
        .unwrap();
    assert_eq!(r.data, vec![2, 22]);
    let r = s
        .handle(
            &mut fs,
            &req(Opcode::Rename, 14, 0, 0, b"/fs/microsd/d\0/fs/microsd/e"),
            0.0,
        )
        .unwrap();
    assert_eq!(r.opcode, 128);
    let l = s
        .handle(&mut fs, &req(Opcode::ListDirectory, 16, 0, 0, b"/fs/microsd"), 0.0)
        .unwrap();
    assert_eq!(l.data, b"De\0Dlog\0");
    let l = s
        .handle(&mut fs, &req(Opcode::ListDirectory, 18, 0, 2, b"/fs/microsd"), 0.0)
        .unwrap();
    assert_eq!(nak_code(&l), Some(6));
    let l = s
        .handle(&mut fs, &req(Opcode::ListDirectory, 20, 0, 0, b"/etc/extras"), 0.0)
        .unwrap();
    assert_eq!(l.data, b"Fbig.bin\t600\0");
    let rm = s
        .handle(&mut fs, &req(Opcode::RemoveDirectory, 22, 0, 0, b"/fs/microsd/e"), 0.0)
        .unwrap();
    assert_eq!(rm.opcode, 128);
    let u = s.handle(&mut fs, &req(Opcode::ReadFile, 24, 0, 0, &[]), 0.0).unwrap();
    assert_eq!(nak_code(&u), Some(4));
    let mut unknown = req(Opcode::None, 26, 0, 0, &[]);
    unknown.opcode = 77;
    assert_eq!(nak_code(&s.handle(&mut fs, &unknown, 0.0).unwrap()), Some(7));
    let mut oversize = req(Opcode::ReadFile, 28, 0, 0, &[]);
    oversize.size = 240;
    assert_eq!(nak_code(&s.handle(&mut fs, &oversize, 0.0).unwrap()), Some(3));
}

#[test]
fn idle_sessions_close_after_ten_seconds() {
    let (mut fs, mut s) = (fs(), FtpServer::default());
    s.handle(&mut fs, &req(Opcode::OpenFileRO, 0, 0, 0, b"/etc/extras/big.bin"), 1.0)
        .unwrap();
    s.expire(11.0);
    assert!(s.session(0).is_ok());
    s.expire(11.5);
    assert_eq!(s.session(0), Err(ErrorCode::InvalidSession));
}

fn with_params() -> Storage {
    use crate::mav::ftp::{PackedParam, PackedValue};
    let mut fs = fs();
    fs.params = (0..40)
        .map(|k| PackedParam {
            name: format!("PARAM_{k:02}"),
            value: PackedValue::Float(k as f32),
            default: PackedValue::Float(0.0),
        })
        .collect();
    fs
}

#[test]
fn the_packed_parameters_download_as_they_were_at_the_open() {
    use crate::mav::ftp::{decode, encode, PackedValue, Query, MAGIC_WITH_DEFAULTS};
    let (mut fs, mut s) = (with_params(), FtpServer::default());
    let path = b"@PARAM/param.pck?withdefaults=1\0";
    let open = s.handle(&mut fs, &req(Opcode::OpenFileRO, 0, 0, 0, path), 0.0).unwrap();
    let expected = encode(&fs.params, Query::of("?withdefaults=1"), DATA_MAX).unwrap();
    assert_eq!(open.data_u32(), Some(expected.len() as u32));
    // A parameter set during the download changes nothing already open.
    fs.params[0].value = PackedValue::Float(99.0);
    assert!(s
        .handle(&mut fs, &req(Opcode::BurstReadFile, 2, 0, 0, &[]), 0.0)
        .is_none());
    let mut got = Vec::new();
    while let Some(frame) = s.burst_frame(&mut fs, 0.0) {
        if frame.opcode == Opcode::Nak as u8 {
            assert_eq!(frame.data, vec![6]);
            break;
        }
        got.extend(frame.data);
    }
    assert_eq!(got, expected);
    let file = decode(&got).unwrap();
    assert_eq!((file.magic, file.entries.len()), (MAGIC_WITH_DEFAULTS, 40));
    let read = s
        .handle(&mut fs, &req(Opcode::ReadFile, 10, 0, 6, &[0; 3]), 0.0)
        .unwrap();
    assert_eq!(read.data, expected[6..9]);
    let w = s.handle(&mut fs, &req(Opcode::WriteFile, 12, 0, 0, b"x"), 0.0).unwrap();
    assert_eq!(nak_code(&w), Some(9), "a download is read-only");
    assert_eq!(
        s.handle(&mut fs, &req(Opcode::TerminateSession, 14, 0, 0, &[]), 0.0)
            .unwrap()
            .opcode,
        128
    );
    assert!(s.take_upload().is_none());
    let bad = s.handle(
        &mut fs,
        &req(Opcode::OpenFileRO, 16, 0, 0, b"@PARAM/param.pck?start=40"),
        0.0,
    );
    assert_eq!(bad.unwrap().data, vec![2, EINVAL], "a query past the last parameter");
    let other = s.handle(&mut fs, &req(Opcode::OpenFileRO, 18, 0, 0, b"@PARAM/other"), 0.0);
    assert_eq!(nak_code(&other.unwrap()), Some(10));
}

#[test]
fn an_upload_is_handed_out_at_its_terminate_and_answered_later() {
    use crate::mav::ftp::{PackedValue, PckError};
    let (mut fs, mut s) = (with_params(), FtpServer::default());
    let mut file = vec![0x1B, 0x67, 1, 0, 0, 0, 4, 7 << 4];
    file.extend(b"PARAM_01");
    file.extend(2.5f32.to_le_bytes());
    file[4] = file.len() as u8;
    let create = s.handle(&mut fs, &req(Opcode::CreateFile, 0, 0, 0, b"@PARAM/param.pck\0"), 0.0);
    assert_eq!(create.unwrap().data_u32(), Some(0));
    for (seq, at) in [(2, 0), (4, 5), (6, 5)] {
        let w = s.handle(&mut fs, &req(Opcode::WriteFile, seq, 0, at, &file[at as usize..]), 0.0);
        assert_eq!(
            w.unwrap().data_u32(),
            Some((file.len() - at as usize) as u32),
            "chunk at {at}"
        );
    }
    assert!(s.take_upload().is_none(), "nothing before the TerminateSession");
    let terminate = req(Opcode::TerminateSession, 8, 0, 0, &[]);
    assert_eq!(s.handle(&mut fs, &terminate, 0.0), None);
    let upload = s.take_upload().unwrap();
    assert_eq!(upload.request, terminate);
    assert_eq!(upload.parsed, Ok(vec![("PARAM_01".into(), PackedValue::Float(2.5))]));
    assert_eq!(
        s.handle(&mut fs, &terminate, 0.1),
        None,
        "repeated while the vehicle applies it"
    );
    assert!(s.take_upload().is_none());
    let ack = s.answer_upload(&terminate, Ok(()));
    assert_eq!((ack.seq, ack.opcode, ack.req_opcode), (9, 128, 1));
    assert_eq!(
        s.handle(&mut fs, &terminate, 0.2),
        Some(ack),
        "the answer again, not a second apply"
    );
    assert_eq!(
        s.answer_upload(&terminate, Err(ErrorCode::FailErrno(EINVAL))).data,
        vec![2, EINVAL]
    );

    // A malformed file is handed out with its fault; a gap and a reset apply nothing.
    s.handle(&mut fs, &req(Opcode::CreateFile, 20, 0, 0, b"/@PARAM/param.pck"), 0.0);
    s.handle(&mut fs, &req(Opcode::WriteFile, 22, 0, 0, &file[..10]), 0.0);
    let gap = s.handle(&mut fs, &req(Opcode::WriteFile, 24, 0, 11, &file[11..]), 0.0);
    assert_eq!(gap.unwrap().data, vec![2, EINVAL]);
    assert_eq!(
        s.handle(&mut fs, &req(Opcode::TerminateSession, 26, 0, 0, &[]), 0.0),
        None
    );
    assert_eq!(s.take_upload().unwrap().parsed, Err(PckError::Truncated(10)));
    s.handle(&mut fs, &req(Opcode::CreateFile, 28, 0, 0, b"@PARAM/param.pck"), 0.0);
    s.handle(&mut fs, &req(Opcode::WriteFile, 30, 0, 0, &file), 0.0);
    s.handle(&mut fs, &req(Opcode::ResetSessions, 32, 0, 0, &[]), 0.0);
    assert!(s.take_upload().is_none(), "a reset upload is dropped");
}

#[test]
fn a_client_making_entries_without_end_gets_enospc_as_on_a_full_card() {
    let mut fs = Storage::new(Vfs::default(), Box::<crate::mav::logs::MemLogStore>::default());
    let mut s = FtpServer::default();
    let name = "n".repeat(200);
    let mut made = 0u32;
    for k in 0..20_000u32 {
        let seq = (2 * k) as u16;
        let op = if k % 2 == 0 {
            Opcode::CreateDirectory
        } else {
            Opcode::CreateFile
        };
        let path = format!("/fs/microsd/{k}{name}");
        let r = s.handle(&mut fs, &req(op, seq, 0, 0, path.as_bytes()), 0.0).unwrap();
        if op == Opcode::CreateFile && r.opcode == Opcode::Ack as u8 {
            // A file stays open in its session: close it as a client does.
            s.handle(
                &mut fs,
                &req(Opcode::TerminateSession, seq.wrapping_add(1), r.session, 0, &[]),
                0.0,
            );
        }
        if let Some(code) = nak_code(&r) {
            assert_eq!((code, r.data.get(1).copied()), (2, Some(ENOSPC)), "entry {k}");
            break;
        }
        made += 1;
    }
    assert!((200..2_000).contains(&made), "{made} entries made before ENOSPC");
}
