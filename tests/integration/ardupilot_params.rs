//! The parameter protocol of an ArduCopter-faced vehicle (docs/ardupilot.md §5.1) through the
//! shipped link machine with virtual clocks: a list opens with Copter's banner and shows every
//! parameter once under Copter's names and units; a set by Copter name asks the vehicle for the
//! setting behind it and echoes the Copter value; reads by name and by index; unknown names are
//! ignored; `@PARAM/param.pck` packs Copter's names; the failsafe enums map onto the settings'
//! codes and Copter codes without a behaviour are refused; `SRn_*` are the links' stream group
//! rates (a set changes the rate on the wire) and `SYSID_THISMAV` the system id; a PX4-faced
//! vehicle is unchanged.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use std::sync::Arc;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::ftp::{decode, Opcode, PackedValue, Payload, MAGIC_WITH_DEFAULTS};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::link::{ToVehicle, VehicleReply, VehicleRequest};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;
use rotorpilot::params::ParamTable;

/// The table of the bench with `MPC_XY_CRUISE` at 10 m/s (ArduCopter's 1000 cm/s).
fn cruising() -> ParamTable {
    let mut t = table();
    t.set("MPC_XY_CRUISE", 10.0, 1e-3).unwrap();
    t
}

fn bench(personality: Personality) -> Bench {
    Bench::with(|c| {
        c.identity = Identity::autopilot(1, 4).with_personality(personality);
        c.params = Arc::new(cruising());
    })
}

fn request_list() -> MavMessage {
    MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
    })
}

fn request_read(name: &str, index: i16) -> MavMessage {
    MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
        param_index: index,
        target_system: 1,
        target_component: 1,
        param_id: param_id(name),
    })
}

fn name(v: &PARAM_VALUE_DATA) -> String {
    v.param_id.to_str().unwrap_or_default().to_string()
}

/// What went out from `from_s` to `to_s` of wall time, a millisecond at a time, in order.
fn run(b: &mut Bench, from_s: f64, to_s: f64) -> Vec<(LinkKind, u16, MavMessage)> {
    let mut out = Vec::new();
    let mut wall_s = from_s;
    while wall_s < to_s {
        wall_s += 0.001;
        b.at(wall_s, wall_s);
        out.extend(b.out());
    }
    out
}

/// The texts of the STATUSTEXTs and the PARAM_VALUEs among `out`, in order.
fn texts_and_values(out: &[(LinkKind, u16, MavMessage)]) -> (Vec<String>, Vec<PARAM_VALUE_DATA>) {
    let (mut texts, mut values) = (Vec::new(), Vec::new());
    for (_, _, m) in out {
        match m {
            MavMessage::STATUSTEXT(t) => texts.push(t.text.to_str().unwrap_or_default().to_string()),
            MavMessage::PARAM_VALUE(v) => values.push(v.clone()),
            _ => {}
        }
    }
    (texts, values)
}

/// The vehicle requests since the last call but the commander's (the RC receiver's sticks and
/// the boot mode, docs/ardupilot.md §8).
fn param_asks(b: &mut Bench) -> Vec<ToVehicle> {
    b.asks()
        .into_iter()
        .filter(|a| !matches!(a.request, VehicleRequest::Commander(_)))
        .collect()
}
/// What the link holds after the table: SYSID_THISMAV, then SR0_* and SR1_* of the bench's two
/// links.
const LINK_HELD: usize = 1 + 2 * 10;

#[test]
fn a_list_opens_with_the_banner_and_shows_every_parameter_once_under_copter_names() {
    let mut b = bench(Personality::ArduPilot);
    let n = table().len() + LINK_HELD;
    b.send(Gcs, QGC, request_list());
    let out = run(&mut b, 0.0, 0.5);
    assert!(out
        .iter()
        .all(|(l, to, m)| matches!(m, MavMessage::HEARTBEAT(_)) || (*l, *to) == (Gcs, QGC)));
    let (texts, values) = texts_and_values(&out);
    assert_eq!(texts, vec!["ArduCopter V4.5.7 (rotorpilot)", "Frame: QUAD/X"]);
    let first_value = out.iter().position(|(_, _, m)| matches!(m, MavMessage::PARAM_VALUE(_)));
    let last_text = out.iter().rposition(|(_, _, m)| matches!(m, MavMessage::STATUSTEXT(_)));
    assert!(last_text < first_value, "the banner goes first");
    assert_eq!(values.len(), n, "every parameter once, no _HASH_CHECK");
    for (i, v) in values.iter().enumerate() {
        assert_eq!((v.param_index as usize, v.param_count as usize), (i, n));
    }
    let names: Vec<String> = values.iter().map(name).collect();
    assert_eq!(
        names[table().len()..][..3],
        ["SYSID_THISMAV", "SR0_RAW_SENS", "SR0_EXT_STAT"]
    );
    assert_eq!(names.last().map(String::as_str), Some("SR1_ADSB"));
    let speed = values.iter().find(|v| name(v) == "WPNAV_SPEED").unwrap();
    assert_eq!(speed.param_value, 1000.0, "cm/s");
    assert_eq!(speed.param_type, MavParamType::MAV_PARAM_TYPE_REAL32);
    for px4 in ["MPC_XY_CRUISE", "RTL_RETURN_ALT", "_HASH_CHECK"] {
        assert!(!names.iter().any(|n| n == px4), "{px4}");
    }
    // Integers are plain numbers: DISARM_DELAY an INT8 of 10, COM_RC_IN_MODE an INT32 of 3.
    let delay = values.iter().find(|v| name(v) == "DISARM_DELAY").unwrap();
    assert_eq!(delay.param_type, MavParamType::MAV_PARAM_TYPE_INT8);
    assert_eq!(delay.param_value, 10.0);
    let rc_in = values.iter().find(|v| name(v) == "COM_RC_IN_MODE").unwrap();
    assert_eq!(
        (rc_in.param_value, rc_in.param_type),
        (3.0, MavParamType::MAV_PARAM_TYPE_INT32)
    );
}

#[test]
fn a_set_by_copter_name_asks_for_the_setting_and_echoes_the_copter_value() {
    let mut b = bench(Personality::ArduPilot);
    b.send(Gcs, OTHER, gcs_heartbeat());
    b.send(Gcs, QGC, param_set("WPNAV_SPEED", 500.0));
    let asks = param_asks(&mut b);
    assert_eq!(asks.len(), 1);
    assert_eq!(
        asks[0].request,
        VehicleRequest::SetParam {
            name: "MPC_XY_CRUISE".into(),
            value: 5.0
        }
    );
    let mut after = cruising();
    let result = after.set("MPC_XY_CRUISE", 5.0, 1e-3);
    let reply = VehicleReply::Param {
        result,
        table: Arc::new(after),
    };
    b.m.handle_reply(b.now, asks[0].token.unwrap(), reply);
    let out = b.out();
    let mut to: Vec<(LinkKind, u16)> = named(&out, "PARAM_VALUE").iter().map(|e| (e.0, e.1)).collect();
    to.sort_unstable_by_key(|t| (t.0 == Api, t.1));
    assert_eq!(
        to,
        vec![(Gcs, QGC), (Gcs, OTHER), (Api, SDK)],
        "once to every peer of every link"
    );
    let MavMessage::PARAM_VALUE(echo) = &named(&out, "PARAM_VALUE")[0].2 else {
        unreachable!()
    };
    assert_eq!((name(echo).as_str(), echo.param_value), ("WPNAV_SPEED", 500.0));
    assert_eq!(echo.param_index, u16::MAX, "index -1, as ArduCopter announces a set");
    let at = b.now.wall_s;
    let later = run(&mut b, at, at + 0.05);
    assert!(named(&later, "PARAM_VALUE").is_empty(), "no second announcement");
    // A read afterwards: by name (index -1) and by index, from the vehicle's new table.
    b.send(Gcs, QGC, request_read("WPNAV_SPEED", -1));
    let out = b.out();
    let [(_, QGC, MavMessage::PARAM_VALUE(by_name))] = &out[..] else {
        panic!("{out:?}");
    };
    assert_eq!((by_name.param_value, by_name.param_index), (500.0, u16::MAX));
    let index = table().index_of("MPC_XY_CRUISE").unwrap() as i16;
    b.send(Gcs, QGC, request_read("", index));
    let out = b.out();
    let [(_, QGC, MavMessage::PARAM_VALUE(by_index))] = &out[..] else {
        panic!("{out:?}");
    };
    assert_eq!(name(by_index), "WPNAV_SPEED");
    assert_eq!((by_index.param_value, by_index.param_index), (500.0, index as u16));
}

#[test]
fn unknown_names_get_nothing_and_bad_values_are_refused_in_copter_units() {
    let mut b = bench(Personality::ArduPilot);
    for unknown in ["MPC_XY_CRUISE", "_HASH_CHECK", "SR2_EXTRA1", "NAV_DLL_ACT"] {
        b.send(Gcs, QGC, param_set(unknown, 1.0));
        b.send(Gcs, QGC, request_read(unknown, -1));
        assert!(b.out().is_empty(), "{unknown}");
        assert!(param_asks(&mut b).is_empty(), "{unknown}");
    }
    b.send(Gcs, QGC, param_set("WPNAV_SPEED", 5000.0));
    assert!(param_asks(&mut b).is_empty(), "refused before the vehicle is asked");
    let out = b.out();
    let [(_, QGC, MavMessage::PARAM_VALUE(v)), (_, QGC, MavMessage::STATUSTEXT(t))] = &out[..] else {
        panic!("{out:?}");
    };
    assert_eq!(v.param_value, 1000.0, "unchanged");
    assert_eq!(t.text.to_str().unwrap(), "WPNAV_SPEED: 5000 outside [50, 3000]");
    // An integer parameter set by its plain number (not PX4's bytes).
    b.send(Gcs, QGC, param_set("RTL_ALT", 2000.0));
    let asks = param_asks(&mut b);
    assert_eq!(
        asks[0].request,
        VehicleRequest::SetParam {
            name: "RTL_RETURN_ALT".into(),
            value: 20.0
        }
    );
}

#[test]
fn the_packed_parameter_file_carries_copter_names_types_and_defaults() {
    let mut b = bench(Personality::ArduPilot);
    let open = Payload::request(Opcode::OpenFileRO, 0, 0, 0, b"@PARAM/param.pck?withdefaults=1");
    b.send(Api, SDK, open.message((1, 1)));
    let opened = ftp_replies(&mut b).remove(0);
    let size = opened.data_u32().unwrap() as usize;
    let mut bytes = Vec::new();
    let mut k = 2;
    while bytes.len() < size {
        let read = Payload::request(Opcode::ReadFile, k, opened.session, bytes.len() as u32, &[0; 239]);
        b.send(Api, SDK, read.message((1, 1)));
        let reply = ftp_replies(&mut b).remove(0);
        assert_eq!(reply.opcode, 128, "{reply:?}");
        bytes.extend(reply.data);
        k += 2;
    }
    let file = decode(&bytes).unwrap();
    assert_eq!(file.magic, MAGIC_WITH_DEFAULTS);
    let count = table().len() + LINK_HELD;
    assert_eq!((file.entries.len(), usize::from(file.total)), (count, count));
    let find = |n: &str| file.entries.iter().find(|e| e.name == n);
    let speed = find("WPNAV_SPEED").unwrap();
    assert_eq!(speed.value, PackedValue::Float(1000.0));
    assert_eq!(speed.default, None, "Copter's default is the value");
    let delay = find("DISARM_DELAY").unwrap();
    assert_eq!(delay.value, PackedValue::Int32(10), "an int8, widened by the reader");
    assert!(find("MPC_XY_CRUISE").is_none());
    let sysid = find("SYSID_THISMAV").unwrap();
    assert_eq!(
        (sysid.value, sysid.default),
        (PackedValue::Int32(1), None),
        "an int16, Copter's 1"
    );
    assert_eq!(find("SR0_POSITION").unwrap().value, PackedValue::Int32(0));
}

/// The only PARAM_VALUE among `out`, and where it went.
fn values_of(out: &[(LinkKind, u16, MavMessage)]) -> Vec<(LinkKind, u16, PARAM_VALUE_DATA)> {
    out.iter()
        .filter_map(|(l, to, m)| match m {
            MavMessage::PARAM_VALUE(v) => Some((*l, *to, v.clone())),
            _ => None,
        })
        .collect()
}

fn texts_of(out: &[(LinkKind, u16, MavMessage)]) -> Vec<String> {
    texts_and_values(out).0
}

fn request_data_stream(stream: MavDataStream, rate_hz: u16) -> MavMessage {
    MavMessage::REQUEST_DATA_STREAM(REQUEST_DATA_STREAM_DATA {
        req_message_rate: rate_hz,
        target_system: 1,
        target_component: 1,
        req_stream_id: stream,
        start_stop: 1,
    })
}

/// GLOBAL_POSITION_INTs on `link` during the second of both clocks from `from_s`, 5 ms a step.
fn positions_in_a_second(b: &mut Bench, link: LinkKind, from_s: f64) -> usize {
    let times = (0..200).map(|k| from_s + f64::from(k) * 0.005).map(|t| (t, t));
    b.count_sent("GLOBAL_POSITION_INT", link, times)
}

#[test]
fn stream_rates_are_the_links_sr_parameters() {
    let mut b = bench(Personality::ArduPilot);
    b.send(Gcs, QGC, gcs_heartbeat());
    b.send(Gcs, QGC, request_read("SR0_POSITION", -1));
    let read = values_of(&b.out());
    assert_eq!(read.len(), 1);
    assert_eq!(
        (read[0].2.param_value, read[0].2.param_type),
        (0.0, MavParamType::MAV_PARAM_TYPE_INT16),
        "Copter's SRn_* are 0"
    );
    // MAVProxy's REQUEST_DATA_STREAM ALL shows in SR0_* (not SR1_*, another link; not PARAMS).
    b.send(Gcs, QGC, request_data_stream(MavDataStream::MAV_DATA_STREAM_ALL, 4));
    for (param, rate) in [
        ("SR0_POSITION", 4.0),
        ("SR0_EXTRA3", 4.0),
        ("SR0_PARAMS", 0.0),
        ("SR1_POSITION", 0.0),
    ] {
        b.send(Gcs, QGC, request_read(param, -1));
        assert_eq!(values_of(&b.out())[0].2.param_value, rate, "{param}");
    }
    assert_eq!(positions_in_a_second(&mut b, Gcs, 0.0), 4);
    // A set of SR0_POSITION sets the group's rate on the wire, without asking the vehicle.
    b.send(Gcs, QGC, param_set("SR0_POSITION", 10.0));
    assert!(param_asks(&mut b).is_empty());
    let echo = values_of(&b.out());
    let mut to: Vec<(LinkKind, u16)> = echo.iter().map(|e| (e.0, e.1)).collect();
    to.sort_unstable_by_key(|t| (t.0 == Api, t.1));
    assert_eq!(
        to,
        vec![(Gcs, QGC), (Api, SDK)],
        "announced to every peer of every link"
    );
    assert_eq!(
        (name(&echo[0].2).as_str(), echo[0].2.param_value),
        ("SR0_POSITION", 10.0)
    );
    assert_eq!(echo[0].2.param_index, u16::MAX);
    assert_eq!(positions_in_a_second(&mut b, Gcs, 1.0), 10);
    assert_eq!(
        positions_in_a_second(&mut b, Api, 2.0),
        0,
        "SR1_POSITION is another link's"
    );
    b.send(Api, SDK, param_set("SR1_POSITION", 2.0));
    b.out();
    assert_eq!(positions_in_a_second(&mut b, Api, 3.0), 2);
    b.send(Gcs, QGC, param_set("SR0_POSITION", 0.0));
    b.out();
    assert_eq!(positions_in_a_second(&mut b, Gcs, 4.0), 0);
    // A rate Copter's INT16 cannot hold is refused, the value as it is.
    b.send(Gcs, QGC, param_set("SR0_POSITION", -1.0));
    let out = b.out();
    assert_eq!(values_of(&out)[0].2.param_value, 0.0);
    assert_eq!(texts_of(&out), vec!["SR0_POSITION: -1 outside [0, 32767]"]);
}

#[test]
fn sysid_thismav_shows_the_system_id_and_cannot_change_it() {
    let mut b = Bench::with(|c| {
        c.identity = Identity::autopilot(7, 4).with_personality(Personality::ArduPilot);
        c.params = Arc::new(cruising());
    });
    let read_sysid = MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
        param_index: -1,
        target_system: 7,
        target_component: 1,
        param_id: param_id("SYSID_THISMAV"),
    });
    b.send(Gcs, QGC, read_sysid.clone());
    let read = values_of(&b.out());
    assert_eq!(
        (read[0].2.param_value, read[0].2.param_type),
        (7.0, MavParamType::MAV_PARAM_TYPE_INT16)
    );
    let set = |value: f32| {
        MavMessage::PARAM_SET(PARAM_SET_DATA {
            param_value: value,
            target_system: 7,
            target_component: 1,
            param_id: param_id("SYSID_THISMAV"),
            param_type: MavParamType::MAV_PARAM_TYPE_INT16,
        })
    };
    b.send(Gcs, QGC, set(3.0));
    let out = b.out();
    assert_eq!(values_of(&out)[0].2.param_value, 7.0, "unchanged");
    assert_eq!(texts_of(&out), vec!["SYSID_THISMAV: fixed at start (--sysid)"]);
    b.send(Gcs, QGC, set(7.0));
    let out = b.out();
    assert_eq!(values_of(&out)[0].2.param_value, 7.0, "the id it has: echoed");
    assert!(texts_of(&out).is_empty());
    assert!(param_asks(&mut b).is_empty());
}

#[test]
fn failsafe_codes_map_onto_the_settings_and_the_others_are_refused() {
    let mut b = bench(Personality::ArduPilot);
    // FS_GCS_ENABLE 1 (RTL) is NAV_DLL_ACT 2 (return), as the setting's code.
    b.send(Gcs, QGC, param_set("FS_GCS_ENABLE", 1.0));
    let asks = param_asks(&mut b);
    assert_eq!(
        asks[0].request,
        VehicleRequest::SetParam {
            name: "NAV_DLL_ACT".into(),
            value: 2.0
        }
    );
    let mut after = cruising();
    let result = after.set("NAV_DLL_ACT", 2.0, 1e-3);
    let reply = VehicleReply::Param {
        result,
        table: Arc::new(after),
    };
    b.m.handle_reply(b.now, asks[0].token.unwrap(), reply);
    let echo = values_of(&b.out());
    assert_eq!(
        (name(&echo[0].2).as_str(), echo[0].2.param_value),
        ("FS_GCS_ENABLE", 1.0)
    );
    assert_eq!(echo[0].2.param_type, MavParamType::MAV_PARAM_TYPE_INT8);
    // SmartRTL-or-RTL has no behaviour of its own here: refused, the value as it is.
    for (param, value, why) in [
        ("FS_GCS_ENABLE", 3.0, "FS_GCS_ENABLE: 3 not emulated (0, 1, 5 or 7)"),
        ("FENCE_ACTION", 3.0, "FENCE_ACTION: 3 not emulated (0, 1, 2 or 4)"),
        ("ARMING_CHECK", 64.0, "ARMING_CHECK: 64 not emulated (0 or 1)"),
    ] {
        b.send(Gcs, QGC, param_set(param, value));
        assert!(param_asks(&mut b).is_empty(), "{param}");
        let out = b.out();
        assert_eq!(values_of(&out).len(), 1, "{param}: the value as it is");
        assert_eq!(texts_of(&out), vec![why]);
    }
    for (param, value, setting, setting_value) in [
        ("FENCE_ENABLE", 1.0, "RP_GF_ENABLE", 1.0),
        ("ARMING_CHECK", 0.0, "RP_ARM_CHECKS", 0.0),
        ("FS_THR_ENABLE", 3.0, "NAV_RCL_ACT", 3.0),
        ("BATT_FS_CRT_ACT", 2.0, "COM_LOW_BAT_ACT", 3.0),
        ("FS_EKF_ACTION", 2.0, "COM_POSCTL_NAVL", 0.0),
    ] {
        b.send(Gcs, QGC, param_set(param, value));
        let asks = param_asks(&mut b);
        assert_eq!(
            asks[0].request,
            VehicleRequest::SetParam {
                name: setting.into(),
                value: setting_value
            },
            "{param}"
        );
    }
}

fn ftp_replies(b: &mut Bench) -> Vec<Payload> {
    b.out()
        .into_iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::FILE_TRANSFER_PROTOCOL(f) => Some(Payload::decode(&f.payload)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_px4_vehicle_keeps_px4_names_bytes_and_hash() {
    let mut b = bench(Personality::Px4);
    b.send(Gcs, QGC, request_list());
    let (texts, values) = texts_and_values(&run(&mut b, 0.0, 0.5));
    assert!(texts.is_empty(), "no banner");
    assert_eq!(values.len(), table().len() + 1);
    assert_eq!(name(&values[0]), "_HASH_CHECK");
    let cruise = values.iter().find(|v| name(v) == "MPC_XY_CRUISE").unwrap();
    assert_eq!(cruise.param_value, 10.0);
    assert!(!values.iter().any(|v| name(v) == "WPNAV_SPEED"));
    let rc_in = values.iter().find(|v| name(v) == "COM_RC_IN_MODE").unwrap();
    assert_eq!(rc_in.param_value.to_bits(), 3, "INT32 byte-wise");
    b.send(Gcs, QGC, param_set("WPNAV_SPEED", 500.0));
    let asks = param_asks(&mut b);
    assert_eq!(
        asks[0].request,
        VehicleRequest::SetParam {
            name: "WPNAV_SPEED".into(),
            value: 500.0
        },
        "a name the vehicle answers is unknown"
    );
}
