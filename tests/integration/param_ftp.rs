//! The parameters as `@PARAM/param.pck` over MAVLink FTP against the vehicle's MAVLink endpoint
//! with virtual clocks, as PX4's `test_param_ftp.cpp` uses them through MAVSDK: the packed file
//! downloaded and compared with the PARAM_VALUE list, value for value and type for type; uploads
//! applied as PARAM_SETs (the vehicle asked for each, the change announced on every link, read
//! back), a refused value or a malformed file NAKed with a STATUSTEXT saying why.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::ftp::{decode, Opcode, PackedValue, Payload, MAGIC, MAGIC_WITH_DEFAULTS};
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};
use rotorpilot::mav::param_encoding::packed_params;
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::params::ParamTable;

const ACK: u8 = 128;
const NAK: u8 = 129;

/// An FTP client on the API link (MAVSDK's): its sequence number, and the vehicle's table.
struct Client {
    b: Bench,
    seq: u16,
    vehicle: ParamTable,
}

impl Client {
    fn new() -> Self {
        Self {
            b: Bench::new(),
            seq: 0,
            vehicle: table(),
        }
    }

    /// Sends `op` and returns the FTP replies that came back at once, and the rest.
    fn send(&mut self, op: Opcode, session: u8, offset: u32, data: &[u8]) -> (Vec<Payload>, Vec<MavMessage>) {
        let req = Payload::request(op, self.seq, session, offset, data);
        self.b.send(Api, SDK, req.message((1, 1)));
        self.out()
    }

    /// The FTP replies and the other messages sent since the last call.
    fn out(&mut self) -> (Vec<Payload>, Vec<MavMessage>) {
        let (mut ftp, mut other) = (Vec::new(), Vec::new());
        for (_, _, m) in self.b.out() {
            match m {
                MavMessage::FILE_TRANSFER_PROTOCOL(f) => ftp.push(Payload::decode(&f.payload)),
                m => other.push(m),
            }
        }
        (ftp, other)
    }

    /// The one reply to `op`, the next sequence number taken.
    fn one(&mut self, op: Opcode, session: u8, offset: u32, data: &[u8]) -> Payload {
        let (replies, _) = self.send(op, session, offset, data);
        assert_eq!(replies.len(), 1, "{op:?}: {replies:?}");
        assert_eq!(replies[0].seq, self.seq.wrapping_add(1));
        self.seq = self.seq.wrapping_add(2);
        replies[0].clone()
    }

    /// Downloads `path` by a burst, as MAVSDK does.
    fn download(&mut self, path: &str) -> Vec<u8> {
        let open = self.one(Opcode::OpenFileRO, 0, 0, path.as_bytes());
        assert_eq!(open.opcode, ACK, "{open:?}");
        let (replies, _) = self.send(Opcode::BurstReadFile, 0, 0, &[]);
        assert!(replies.is_empty());
        let (mut bytes, mut wall) = (Vec::new(), self.b.now.wall_s);
        loop {
            wall += 1e-3;
            self.b.at(wall, self.b.now.sim_s);
            for frame in self.out().0 {
                if frame.opcode == NAK {
                    assert_eq!(
                        (frame.data.clone(), bytes.len()),
                        (vec![6], open.data_u32().unwrap() as usize)
                    );
                    self.seq = self.seq.wrapping_add(2);
                    assert_eq!(self.one(Opcode::TerminateSession, 0, 0, &[]).opcode, ACK);
                    return bytes;
                }
                bytes.extend(frame.data);
            }
            assert!(wall < 10.0, "the burst never ended");
        }
    }

    /// Uploads `file` to `@PARAM` in chunks of `chunk` bytes; what came back at once after the
    /// TerminateSession (no reply when the file is read: it waits for the vehicle).
    fn upload(&mut self, file: &[u8], chunk: usize) -> (Vec<Payload>, Vec<MavMessage>) {
        let create = self.one(Opcode::CreateFile, 0, 0, b"@PARAM/param.pck\0");
        assert_eq!(create.opcode, ACK);
        for (k, piece) in file.chunks(chunk).enumerate() {
            let w = self.one(Opcode::WriteFile, create.session, (k * chunk) as u32, piece);
            assert_eq!(w.data_u32(), Some(piece.len() as u32));
        }
        self.send(Opcode::TerminateSession, create.session, 0, &[])
    }

    /// Answers every request the link made of the vehicle as the vehicle does: each PARAM_SET
    /// applied to its table. Returns the (name, value) pairs asked.
    fn serve(&mut self) -> Vec<(String, f64)> {
        let mut asked = Vec::new();
        for ask in self.b.asks() {
            let VehicleRequest::SetParam { name, value } = ask.request else {
                panic!("{:?}", ask.request);
            };
            let result = self.vehicle.set(&name, value, 1e-3);
            let table = std::sync::Arc::new(self.vehicle.clone());
            self.b
                .m
                .handle_reply(self.b.now, ask.token.unwrap(), VehicleReply::Param { result, table });
            asked.push((name, value));
        }
        asked
    }

    /// The PARAM_VALUE of a PARAM_REQUEST_READ of `name`.
    fn read(&mut self, name: &str) -> PARAM_VALUE_DATA {
        let read = PARAM_REQUEST_READ_DATA {
            param_index: -1,
            target_system: 1,
            target_component: 1,
            param_id: param_id(name),
        };
        self.b.send(Api, SDK, MavMessage::PARAM_REQUEST_READ(read));
        match &self.out().1[..] {
            [MavMessage::PARAM_VALUE(v)] => v.clone(),
            other => panic!("{other:?}"),
        }
    }
}

/// A packed file as a client uploads it: magic 0x671B, the total its length, no prefix sharing.
fn packed(entries: &[(&str, PackedValue)]) -> Vec<u8> {
    let mut body = Vec::new();
    for (name, value) in entries {
        let kind = if matches!(value, PackedValue::Int32(_)) { 3 } else { 4 };
        body.extend([kind, ((name.len() - 1) as u8) << 4]);
        body.extend(name.as_bytes());
        body.extend(value.bits().to_le_bytes());
    }
    let mut out = Vec::new();
    for word in [MAGIC, entries.len() as u16, (6 + body.len()) as u16] {
        out.extend(word.to_le_bytes());
    }
    out.extend(body);
    out
}

fn texts(messages: &[MavMessage]) -> Vec<String> {
    messages
        .iter()
        .filter_map(|m| match m {
            MavMessage::STATUSTEXT(t) => Some(t.text.to_str().unwrap().to_string()),
            _ => None,
        })
        .collect()
}

#[test]
fn the_download_is_the_param_value_list_with_the_defaults_that_differ() {
    let mut c = Client::new();
    c.b.send(Gcs, QGC, param_set("MIS_TAKEOFF_ALT", 3.0));
    c.serve();
    c.out();
    c.b.send(
        Api,
        SDK,
        MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 1,
        }),
    );
    // By index: the change is announced on every link meanwhile.
    let mut listed = std::collections::BTreeMap::new();
    for k in 1..1000 {
        c.b.at(k as f64 * 1e-3, 0.0);
        listed.extend(c.out().1.into_iter().filter_map(|m| match m {
            MavMessage::PARAM_VALUE(v) if v.param_index != u16::MAX => Some((v.param_index, v)),
            _ => None,
        }));
    }
    let listed: Vec<PARAM_VALUE_DATA> = listed.into_values().collect();
    assert_eq!(listed.len(), c.vehicle.len());
    assert!(listed.len() > 100, "PX4's case needs more than 100");
    let file = decode(&c.download("@PARAM/param.pck?withdefaults=1")).unwrap();
    assert_eq!(
        (file.magic, usize::from(file.total)),
        (MAGIC_WITH_DEFAULTS, listed.len())
    );
    for (entry, v) in file.entries.iter().zip(&listed) {
        assert_eq!(entry.name, v.param_id.to_str().unwrap());
        assert_eq!(entry.value.bits(), v.param_value.to_bits(), "{}", entry.name);
        let int = v.param_type == MavParamType::MAV_PARAM_TYPE_INT32;
        assert_eq!(matches!(entry.value, PackedValue::Int32(_)), int, "{}", entry.name);
        let changed = entry.name == "MIS_TAKEOFF_ALT";
        assert_eq!(
            entry.default,
            changed.then_some(PackedValue::Float(2.5)),
            "{}",
            entry.name
        );
    }
    let plain = decode(&c.download("@PARAM/param.pck")).unwrap();
    assert_eq!(plain.magic, MAGIC);
    assert!(plain.entries.iter().all(|e| e.default.is_none()));
}

#[test]
fn an_upload_is_applied_as_param_sets_announced_and_read_back() {
    let mut c = Client::new();
    let file = packed(&[
        ("MIS_TAKEOFF_ALT", PackedValue::Float(4.0)),
        ("NOPE_PARAM", PackedValue::Float(1.0)),
        ("NAV_DLL_ACT", PackedValue::Int32(2)),
    ]);
    assert!(
        c.upload(&file, 20).0.is_empty(),
        "the TerminateSession waits for the vehicle"
    );
    let terminate_seq = c.seq;
    assert!(
        c.send(Opcode::TerminateSession, 0, 0, &[]).0.is_empty(),
        "repeated meanwhile: ignored"
    );
    let asked = c.serve();
    let names: Vec<&str> = asked.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["MIS_TAKEOFF_ALT", "NOPE_PARAM", "NAV_DLL_ACT"],
        "in file order, as PARAM_SETs"
    );
    assert_eq!((asked[0].1, asked[2].1), (4.0, 2.0));
    let (replies, other) = c.out();
    assert_eq!(replies.len(), 1);
    let ack = &replies[0];
    assert_eq!((ack.opcode, ack.req_opcode, ack.seq), (ACK, 1, terminate_seq + 1));
    assert_eq!(texts(&other), ["param.pck: 1 unknown skipped: NOPE_PARAM"]);
    let (again, _) = c.send(Opcode::TerminateSession, 0, 0, &[]);
    assert_eq!(again, replies, "a lost ACK is sent again");
    // The changes go to every peer of every link 5 ms later, as a PARAM_SET's do.
    let at = c.b.now.wall_s;
    c.b.at(at + 0.006, c.b.now.sim_s);
    let announced: Vec<(LinkKind, String)> =
        c.b.out()
            .into_iter()
            .filter_map(|(link, _, m)| match m {
                MavMessage::PARAM_VALUE(v) => Some((link, v.param_id.to_str().unwrap().to_string())),
                _ => None,
            })
            .collect();
    assert_eq!(announced.len(), 4, "{announced:?}");
    assert!(announced.contains(&(Gcs, "NAV_DLL_ACT".into())) && announced.contains(&(Api, "MIS_TAKEOFF_ALT".into())));
    assert_eq!(c.read("MIS_TAKEOFF_ALT").param_value, 4.0);
    assert_eq!(c.read("NAV_DLL_ACT").param_value.to_bits(), 2);
    // The next download packs the table as it now is.
    c.seq = c.seq.wrapping_add(2);
    let file = decode(&c.download("@PARAM/param.pck")).unwrap();
    let alt = file.entries.iter().find(|e| e.name == "MIS_TAKEOFF_ALT").unwrap();
    assert_eq!(alt.value, PackedValue::Float(4.0));
}

#[test]
fn a_whole_download_uploads_back_within_the_vehicle_s_inbox() {
    let mut c = Client::new();
    let mut file = c.download("@PARAM/param.pck");
    let n = decode(&file).unwrap().entries.len();
    let len = file.len() as u16;
    file[4..6].copy_from_slice(&len.to_le_bytes());
    assert!(c.upload(&file, 239).0.is_empty());
    let mut asked = 0;
    for _ in 0..n {
        let batch = c.serve().len();
        assert!(
            batch <= 32,
            "at most 32 PARAM_SETs wait for the vehicle at once: {batch}"
        );
        asked += batch;
        if batch == 0 {
            break;
        }
    }
    assert_eq!(asked, n, "every parameter asked once");
    let (replies, other) = c.out();
    assert_eq!((replies.len(), replies[0].opcode), (1, ACK), "{:?}", texts(&other));
    assert_eq!(
        packed_params(&c.vehicle),
        packed_params(&table()),
        "every value set to what it was"
    );
}

#[test]
fn refused_values_and_malformed_files_are_naked_with_the_reason() {
    let mut c = Client::new();
    let file = packed(&[
        ("MIS_TAKEOFF_ALT", PackedValue::Float(5000.0)),
        ("NAV_DLL_ACT", PackedValue::Int32(3)),
    ]);
    assert!(c.upload(&file, 239).0.is_empty());
    assert_eq!(c.serve().len(), 2);
    let (replies, other) = c.out();
    assert_eq!((replies[0].opcode, replies[0].data.clone()), (NAK, vec![2, 22]));
    assert_eq!(texts(&other), ["MIS_TAKEOFF_ALT: 5000 outside [0.5, 1000]"]);
    assert_eq!(
        c.read("MIS_TAKEOFF_ALT").param_value,
        2.5,
        "the refused value left as it was"
    );
    assert_eq!(
        c.read("NAV_DLL_ACT").param_value.to_bits(),
        3,
        "the other applied, as PARAM_SETs are"
    );

    let mut with_defaults = packed(&[("MIS_TAKEOFF_ALT", PackedValue::Float(3.0))]);
    with_defaults[..2].copy_from_slice(&MAGIC_WITH_DEFAULTS.to_le_bytes());
    c.seq = c.seq.wrapping_add(2);
    let (replies, other) = c.upload(&with_defaults, 239);
    assert_eq!(
        (replies[0].opcode, replies[0].data.clone()),
        (NAK, vec![2, 22]),
        "at once"
    );
    assert_eq!(texts(&other), ["param.pck: defaults in an upload"]);
    assert!(c.b.asks().is_empty(), "nothing asked of the vehicle");
    c.seq = c.seq.wrapping_add(2);
    let mut short = packed(&[("MIS_TAKEOFF_ALT", PackedValue::Float(3.0))]);
    short.pop();
    let (replies, other) = c.upload(&short, 239);
    assert_eq!(replies[0].opcode, NAK);
    assert_eq!(texts(&other), [format!("param.pck: truncated at byte {}", short.len())]);
    assert!(c.b.asks().is_empty());
}
