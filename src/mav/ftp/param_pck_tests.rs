use super::*;

fn f(name: &str, value: f32, default: f32) -> PackedParam {
    PackedParam {
        name: name.into(),
        value: PackedValue::Float(value),
        default: PackedValue::Float(default),
    }
}

fn i(name: &str, value: i32, default: i32) -> PackedParam {
    PackedParam {
        name: name.into(),
        value: PackedValue::Int32(value),
        default: PackedValue::Int32(default),
    }
}

/// PX4's own test set, plus 300 generated names.
fn params() -> Vec<PackedParam> {
    let mut p = vec![
        f("MPC_XY_P", 0.95, 0.95),
        f("MPC_XY_VEL_P_ACC", 1.8, 1.8),
        f("MPC_Z_P", 1.2, 1.0),
        i("SYS_AUTOSTART", 4001, 0),
        i("SYS_HITL", 0, 0),
        i("A", -1, -1),
        f("ABCDEFGHIJKLMNOP", 2.0, 2.0),
        f("ABCDEFGHIJKLMNOQ", 3.0, 2.0),
        i("B", 7, 7),
    ];
    p.extend((0..300).map(|k| i(&format!("GEN_{k:03}_X"), k, if k % 3 == 0 { 0 } else { k })));
    p
}

fn query(path: &str) -> Query {
    Query::of(path)
}

/// The file offset of each entry's value: after its type, name byte and new characters.
fn value_offsets(bytes: &[u8]) -> Vec<(usize, usize)> {
    let (mut at, mut out) = (HEADER_LEN, Vec::new());
    while at < bytes.len() {
        if bytes[at] == 0 {
            at += 1;
            continue;
        }
        let data = 4 * (1 + usize::from(bytes[at] & HAS_DEFAULT != 0));
        let value_at = at + 2 + usize::from(bytes[at + 1] >> 4) + 1;
        out.push((value_at, data));
        at = value_at + data;
    }
    out
}

#[test]
fn a_download_decodes_to_the_parameters_in_order() {
    let p = params();
    let bytes = encode(&p, query(PARAM_FILE), 239).unwrap();
    assert_eq!(&bytes[..6], &[0x1B, 0x67, 53, 1, 53, 1], "magic, 309 entries of 309");
    let file = decode(&bytes).unwrap();
    assert_eq!((file.magic, usize::from(file.total)), (MAGIC, p.len()));
    assert_eq!(file.entries.len(), p.len());
    for (e, p) in file.entries.iter().zip(&p) {
        assert_eq!((&e.name, e.value, e.default), (&p.name, p.value, None));
    }
    // The name byte: "MPC_XY_VEL_P_ACC" shares 7 characters with "MPC_XY_P", the 16-character
    // "ABCDEFGHIJKLMNOQ" 15 with the one before it.
    assert_eq!(bytes[6 + 1], (8 - 1) << 4, "the first name shares nothing");
    let second = 6 + 2 + 8 + 4;
    assert_eq!(bytes[second + 1], 7 | ((9 - 1) << 4));
    assert_eq!(&bytes[second + 2..second + 11], b"VEL_P_ACC");
    let k = bytes.windows(2).position(|w| w == [4, 15]).unwrap();
    assert_eq!(bytes[k + 2], b'Q');
}

#[test]
fn defaults_follow_values_that_differ_from_them() {
    let p = params();
    let bytes = encode(&p, query("@PARAM/param.pck?withdefaults=1"), 239).unwrap();
    let file = decode(&bytes).unwrap();
    assert_eq!(file.magic, MAGIC_WITH_DEFAULTS);
    for (e, p) in file.entries.iter().zip(&p) {
        assert_eq!(e.value, p.value);
        let differs = p.value.bits() != p.default.bits();
        assert_eq!(e.default, differs.then_some(p.default), "{}", p.name);
    }
    let z = file.entries.iter().find(|e| e.name == "MPC_Z_P").unwrap();
    assert_eq!(z.default, Some(PackedValue::Float(1.0)));
    let k = bytes.windows(2).position(|w| w == [0x14, 4 | (2 << 4)]).unwrap();
    assert_eq!(&bytes[k + 2..k + 5], b"Z_P", "type 4 with the default flag");
}

#[test]
fn no_value_straddles_a_block() {
    for path in [PARAM_FILE, "@PARAM/param.pck?withdefaults=1"] {
        for block in [16, 239] {
            let bytes = encode(&params(), query(path), block).unwrap();
            assert_eq!(decode(&bytes).unwrap().entries.len(), params().len());
            for (at, len) in value_offsets(&bytes) {
                assert_eq!(at / block, (at + len - 1) / block, "{path} block {block} at {at}");
            }
        }
    }
}

#[test]
fn start_and_count_pick_a_range() {
    let p = params();
    let bytes = encode(&p, query("@PARAM/param.pck?start=2&count=3"), 239).unwrap();
    let file = decode(&bytes).unwrap();
    assert_eq!(usize::from(file.total), p.len());
    let names: Vec<&str> = file.entries.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["MPC_Z_P", "SYS_AUTOSTART", "SYS_HITL"]);
    assert_eq!(bytes[7] & 0x0F, 0, "the first entry shares nothing");
    let last = encode(&p, query(&format!("@PARAM/param.pck?start={}", p.len() - 1)), 239).unwrap();
    assert_eq!(decode(&last).unwrap().entries[0].name, "GEN_299_X");
    assert_eq!(query("@PARAM/param.pck?unknown=1&withdefaults=1").with_defaults, 1);
    for bad in ["withdefaults=2", "count=65535", "start=100000", "start=309"] {
        let r = encode(&p, query(&format!("@PARAM/param.pck?{bad}")), 239);
        assert!(matches!(r, Err(PckError::Query(_))), "{bad}: {r:?}");
    }
    assert!(matches!(encode(&p, Query::default(), 0), Err(PckError::Query(_))));
    assert!(is_param_path("@PARAM/param.pck") && is_param_path("/@PARAM/param.pck?withdefaults=1"));
    for not in ["@PARAM/param.pckx", "@PARAM/other", "/fs/microsd/param.pck", "@PARAM"] {
        assert!(!is_param_path(not), "{not}");
    }
}

#[test]
fn names_of_sixteen_characters_pack_and_longer_ones_do_not() {
    let sixteen = [f("ABCDEFGHIJKLMNOP", 1.0, 1.0), f("ABCDEFGHIJKLMNOP", 2.0, 2.0)];
    let bytes = encode(&sixteen, Query::default(), 239).unwrap();
    let file = decode(&bytes).unwrap();
    assert_eq!(
        file.entries[1].name, "ABCDEFGHIJKLMNOP",
        "a repeated name shares 15, sends 1"
    );
    assert_eq!(bytes[6 + 2 + 16 + 4 + 1], 15);
    for bad in ["ABCDEFGHIJKLMNOPQ", "", "SPACE NAME", "CAFÉ"] {
        let r = encode(&[f(bad, 1.0, 1.0)], Query::default(), 239);
        assert_eq!(r, Err(PckError::Name(bad.into())));
    }
}

/// An upload as a client packs it: magic 0x671B, total = file length.
fn upload(entries: &[(u8, &str, &[u8])]) -> Vec<u8> {
    let (mut body, mut previous) = (Vec::new(), "");
    for (kind, name, value) in entries {
        let (common, new) = prefix(previous, name).unwrap();
        body.extend([*kind, common as u8 | (((new - 1) as u8) << 4)]);
        body.extend(&name.as_bytes()[common..]);
        body.extend(*value);
        previous = name;
    }
    let mut out = Vec::new();
    for word in [MAGIC, entries.len() as u16, (HEADER_LEN + body.len()) as u16] {
        out.extend(word.to_le_bytes());
    }
    out.extend(body);
    out
}

#[test]
fn uploads_widen_small_integers_and_keep_floats() {
    let bytes = upload(&[
        (4, "MPC_XY_P", &1.5f32.to_le_bytes()),
        (1, "SYS_HITL", &[0xFF]),
        (2, "SYS_AUTOSTART", &(-300i16).to_le_bytes()),
        (3, "SYS_AUTOCONFIG", &4002i32.to_le_bytes()),
    ]);
    assert_eq!(
        parse_upload(&bytes).unwrap(),
        vec![
            ("MPC_XY_P".into(), PackedValue::Float(1.5)),
            ("SYS_HITL".into(), PackedValue::Int32(-1)),
            ("SYS_AUTOSTART".into(), PackedValue::Int32(-300)),
            ("SYS_AUTOCONFIG".into(), PackedValue::Int32(4002)),
        ]
    );
    assert_eq!(PackedValue::Int32(-1).bits(), u32::MAX);
    assert_eq!(PackedValue::Float(1.5).as_f64(), 1.5);
}

#[test]
fn malformed_uploads_are_refused_with_the_reason() {
    let ok = upload(&[
        (4, "MPC_Z_P", &4f32.to_le_bytes()),
        (3, "SYS_HITL", &2i32.to_le_bytes()),
    ]);
    assert!(parse_upload(&ok).is_ok());
    let mut defaults_magic = ok.clone();
    defaults_magic[..2].copy_from_slice(&MAGIC_WITH_DEFAULTS.to_le_bytes());
    assert_eq!(parse_upload(&defaults_magic), Err(PckError::Defaults));
    let mut flagged = ok.clone();
    flagged[6] |= HAS_DEFAULT;
    assert!(parse_upload(&flagged).is_err());
    let mut truncated = ok.clone();
    truncated.truncate(ok.len() - 3);
    assert_eq!(parse_upload(&truncated), Err(PckError::Truncated(truncated.len())));
    let mut long = ok.clone();
    long.push(0);
    assert_eq!(
        parse_upload(&long),
        Err(PckError::Length {
            header: ok.len(),
            actual: ok.len() + 1
        })
    );
    let mut count = ok.clone();
    count[2] = 3;
    assert_eq!(parse_upload(&count), Err(PckError::Count { header: 3, found: 2 }));
    let mut kind = ok.clone();
    kind[6] = 5;
    assert_eq!(parse_upload(&kind), Err(PckError::Type { offset: 6, byte: 5 }));
    let mut shares = ok.clone();
    shares[7] |= 1;
    assert_eq!(
        parse_upload(&shares),
        Err(PckError::BadName(6)),
        "nothing before to share"
    );
    assert_eq!(parse_upload(&[0x1B, 0x67, 0]), Err(PckError::Truncated(3)));
    assert_eq!(parse_upload(&[1, 2, 0, 0, 6, 0]), Err(PckError::Magic(0x0201)));
    assert_eq!(parse_upload(&upload(&[])), Ok(vec![]), "an empty upload sets nothing");
}
