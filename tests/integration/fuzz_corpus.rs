//! The committed seed corpus of the cargo-fuzz targets (`fuzz/corpus/<target>/seed-*`,
//! docs/fuzzing.md) is what this file generates: real MAVLink datagrams encoded with the codec, the
//! shipped airframes and scenarios, and parameter files. The test fails when a seed is missing
//! or stale; `ROTORPILOT_WRITE_FUZZ_CORPUS=1 cargo test --release --test integration fuzz_corpus::` rewrites them.
#![allow(clippy::unwrap_used, clippy::expect_used)]
// QGC still sends SET_MODE, MAVSDK GLOBAL_RELATIVE_ALT_INT and PING, all deprecated in the dialect.
#![allow(deprecated)]

use std::path::{Path, PathBuf};

use mavlink::dialects::ardupilotmega::{
    AttitudeTargetTypemask, MavCmd, MavDataStream, MavFrame, MavMessage, MavMissionType, MavModeFlag, MavParamType,
    MavType, PositionTargetTypemask, COMMAND_INT_DATA, FILE_TRANSFER_PROTOCOL_DATA, HEARTBEAT_DATA, MISSION_ACK_DATA,
    MISSION_CLEAR_ALL_DATA, MISSION_COUNT_DATA, MISSION_REQUEST_INT_DATA, MISSION_REQUEST_LIST_DATA,
    PARAM_REQUEST_LIST_DATA, PARAM_REQUEST_READ_DATA, PARAM_SET_DATA, PING_DATA, REQUEST_DATA_STREAM_DATA,
    SET_ATTITUDE_TARGET_DATA, SET_MODE_DATA, SET_POSITION_TARGET_GLOBAL_INT_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
    TIMESYNC_DATA,
};
use rotorpilot::mav::codec::{decode_datagram, encode_v2, Inbound};
use rotorpilot::mav::gcs::{command_long, gcs_header};

use crate::support;
use support::{attitude_target, mission_item};

const NAN: f32 = f32::NAN;

/// One datagram of MAVLink 2 frames from the ground station, sequence numbers counting up.
fn datagram(messages: &[MavMessage]) -> Vec<u8> {
    let mut buf = Vec::new();
    for (i, m) in messages.iter().enumerate() {
        encode_v2(gcs_header(i as u8), m, &mut buf);
    }
    buf
}

fn command(command: MavCmd, p: [f32; 7]) -> MavMessage {
    MavMessage::COMMAND_LONG(command_long((1, 1), command, p))
}

fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        mavtype: MavType::MAV_TYPE_GCS,
        ..Default::default()
    })
}

fn arm() -> MavMessage {
    command(
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        [1.0, 0.0, NAN, NAN, NAN, NAN, NAN],
    )
}

fn takeoff(amsl_m: f32) -> MavMessage {
    command(MavCmd::MAV_CMD_NAV_TAKEOFF, [NAN, 0.0, 0.0, NAN, NAN, NAN, amsl_m])
}

fn param_id(name: &str) -> mavlink::types::CharArray<16> {
    let mut id = [0u8; 16];
    id[..name.len()].copy_from_slice(name.as_bytes());
    id.into()
}

fn local_target(mask: u16, frame: MavFrame) -> MavMessage {
    MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        x: 1.0,
        y: 2.0,
        z: -3.0,
        vx: 0.5,
        vz: -0.5,
        yaw: 0.3,
        yaw_rate: 0.1,
        type_mask: PositionTargetTypemask::from_bits_truncate(mask),
        coordinate_frame: frame,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    })
}

/// The MAVLink seeds: typical ground-station traffic, one datagram each.
fn mavlink_seeds() -> Vec<(&'static str, Vec<u8>)> {
    let set_mode = |main: f32, sub: f32| command(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, main, sub, NAN, NAN, NAN, NAN]);
    let mut v1 = Vec::new();
    mavlink::write_v1_msg(&mut v1, gcs_header(0), &command(MavCmd::MAV_CMD_NAV_LAND, [NAN; 7])).unwrap();
    mavlink::write_v1_msg(&mut v1, gcs_header(0), &gcs_heartbeat()).unwrap();
    vec![
        ("heartbeat", datagram(&[gcs_heartbeat()])),
        (
            "arm_takeoff_land",
            datagram(&[
                gcs_heartbeat(),
                arm(),
                takeoff(NAN),
                takeoff(493.0),
                command(MavCmd::MAV_CMD_NAV_LAND, [NAN; 7]),
                command(
                    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                    [0.0, 21196.0, NAN, NAN, NAN, NAN, NAN],
                ),
            ]),
        ),
        (
            "set_modes",
            datagram(&[
                set_mode(3.0, 0.0),
                set_mode(4.0, 3.0),
                set_mode(4.0, 5.0),
                set_mode(1.0, 0.0),
                command(
                    MavCmd::MAV_CMD_DO_SET_STANDARD_MODE,
                    [1.0, NAN, NAN, NAN, NAN, NAN, NAN],
                ),
                MavMessage::SET_MODE(SET_MODE_DATA {
                    custom_mode: (4 << 16) | (6 << 24),
                    target_system: 1,
                    base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
                }),
            ]),
        ),
        (
            "offboard_local",
            datagram(&[
                local_target(2552, MavFrame::MAV_FRAME_LOCAL_NED),
                set_mode(6.0, 0.0),
                arm(),
                local_target(2503, MavFrame::MAV_FRAME_LOCAL_NED),
                local_target(1479, MavFrame::MAV_FRAME_BODY_NED),
                local_target(3135, MavFrame::MAV_FRAME_LOCAL_NED),
            ]),
        ),
        (
            "offboard_global_attitude",
            datagram(&[
                MavMessage::SET_POSITION_TARGET_GLOBAL_INT(SET_POSITION_TARGET_GLOBAL_INT_DATA {
                    lat_int: 473_977_500,
                    lon_int: 85_455_900,
                    alt: 5.0,
                    type_mask: PositionTargetTypemask::from_bits_truncate(2552),
                    coordinate_frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                    target_system: 1,
                    target_component: 1,
                    ..Default::default()
                }),
                set_mode(6.0, 0.0),
                arm(),
                attitude_target([1.0, 0.0, 0.0, 0.0], 0.6),
                MavMessage::SET_ATTITUDE_TARGET(SET_ATTITUDE_TARGET_DATA {
                    body_yaw_rate: 0.5,
                    thrust: 0.5,
                    type_mask: AttitudeTargetTypemask::from_bits_truncate(128),
                    target_system: 1,
                    target_component: 1,
                    ..Default::default()
                }),
            ]),
        ),
        (
            "mission_upload_start",
            datagram(&[
                MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
                    count: 4,
                    target_system: 1,
                    target_component: 1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                    opaque_id: 0,
                }),
                mission_item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, 0, 3.0),
                mission_item(1, MavCmd::MAV_CMD_NAV_WAYPOINT, 100, 3.0),
                mission_item(2, MavCmd::MAV_CMD_NAV_LOITER_TIME, 200, 4.0),
                mission_item(3, MavCmd::MAV_CMD_NAV_LAND, 0, 0.0),
                arm(),
                command(MavCmd::MAV_CMD_MISSION_START, [0.0, 0.0, NAN, NAN, NAN, NAN, NAN]),
            ]),
        ),
        (
            "mission_download_clear",
            datagram(&[
                MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
                    target_system: 1,
                    target_component: 1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                }),
                MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
                    seq: 0,
                    target_system: 1,
                    target_component: 1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                }),
                MavMessage::MISSION_ACK(MISSION_ACK_DATA::default()),
                MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
                    target_system: 1,
                    target_component: 1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                }),
            ]),
        ),
        (
            "params",
            datagram(&[
                MavMessage::PARAM_SET(PARAM_SET_DATA {
                    param_value: f32::from_bits(2),
                    target_system: 1,
                    target_component: 1,
                    param_id: param_id("RP_CTRL"),
                    param_type: MavParamType::MAV_PARAM_TYPE_INT32,
                }),
                MavMessage::PARAM_SET(PARAM_SET_DATA {
                    param_value: 5.0,
                    target_system: 1,
                    target_component: 1,
                    param_id: param_id("MIS_TAKEOFF_ALT"),
                    param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
                }),
                MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
                    param_index: -1,
                    target_system: 1,
                    target_component: 1,
                    param_id: param_id("RP_EST_ORDER"),
                }),
                MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
                    target_system: 1,
                    target_component: 1,
                }),
            ]),
        ),
        (
            "services",
            datagram(&[
                MavMessage::PING(PING_DATA {
                    time_usec: 1,
                    seq: 2,
                    target_system: 0,
                    target_component: 0,
                }),
                MavMessage::TIMESYNC(TIMESYNC_DATA {
                    tc1: 0,
                    ts1: 12345,
                    ..Default::default()
                }),
                command(MavCmd::MAV_CMD_REQUEST_MESSAGE, [148.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
                command(MavCmd::MAV_CMD_REQUEST_MESSAGE, [242.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
                command(
                    MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                    [30.0, 20_000.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                ),
                command(
                    MavCmd::MAV_CMD_GET_MESSAGE_INTERVAL,
                    [30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                ),
                MavMessage::REQUEST_DATA_STREAM(REQUEST_DATA_STREAM_DATA {
                    req_message_rate: 10,
                    target_system: 1,
                    target_component: 1,
                    req_stream_id: MavDataStream::MAV_DATA_STREAM_POSITION,
                    start_stop: 1,
                }),
                MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
                    target_system: 1,
                    target_component: 1,
                    target_network: 0,
                    payload: [0; 251],
                }),
            ]),
        ),
        (
            "reposition_speed_home_rtl",
            datagram(&[
                arm(),
                takeoff(NAN),
                MavMessage::COMMAND_INT(COMMAND_INT_DATA {
                    param1: 2.0,
                    param4: NAN,
                    x: 473_977_600,
                    y: 85_456_000,
                    z: 6.0,
                    command: MavCmd::MAV_CMD_DO_REPOSITION,
                    target_system: 1,
                    target_component: 1,
                    frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                    ..Default::default()
                }),
                command(MavCmd::MAV_CMD_DO_CHANGE_SPEED, [1.0, 3.0, -1.0, 0.0, 0.0, 0.0, 0.0]),
                command(
                    MavCmd::MAV_CMD_DO_SET_HOME,
                    [0.0, 0.0, 0.0, 0.0, 47.3978, 8.5456, 490.0],
                ),
                command(MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH, [NAN; 7]),
            ]),
        ),
        ("mavlink1_land", v1),
    ]
}

/// `datagram` in the fuzz target's framed form: `F`, then (message id u16 LE, payload length,
/// payload) per MAVLink 2 frame.
fn framed(datagram: &[u8]) -> Vec<u8> {
    let mut reader = mavlink::MavlinkReader::with_capacity(0, datagram);
    let mut out = vec![b'F'];
    while let Ok(mavlink::MAVLinkMessageRaw::V2(raw)) = reader.read_any_raw_message::<MavMessage>() {
        out.extend_from_slice(&(raw.message_id() as u16).to_le_bytes());
        out.push(raw.payload_length());
        out.extend_from_slice(raw.payload());
    }
    out
}

/// The QGroundControl-style and plain parameter-file seeds.
fn param_file_seeds() -> Vec<(&'static str, Vec<u8>)> {
    let qgc = "# Onboard parameters for Vehicle 1\n#\n# Stack: PX4\n# Vehicle: Multi-Rotor\n# Version: 0.1.0\n#\n\
               # Vehicle-Id Component-Id Name Value Type\n\
               1\t1\tMIS_TAKEOFF_ALT\t5.000000000000000000\t9\n\
               1\t1\tMPC_XY_CRUISE\t3.000000000000000000\t9\n\
               1\t1\tNAV_DLL_ACT\t2\t6\n\
               1\t1\tRP_CTRL\t2\t6\n\
               1\t1\tRP_EST_ORDER\t3\t6\n\
               1\t1\tRP_EST_WP\t1.500000000000000000\t9\n";
    let plain =
        "# plain NAME VALUE lines\nRP_COMP 1   # compensate\nRP_GEO_KP_X 6.5\nCOM_OF_LOSS_T 0.5\nMPC_TILTMAX_AIR 35\n";
    vec![("qgc", qgc.into()), ("plain", plain.into())]
}

/// Every `.toml` file of `dir` as `(stem, bytes)`.
fn toml_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            (
                p.file_stem().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    out.sort();
    out
}

/// Every seed file: path under `fuzz/corpus` and content.
fn seeds(root: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for (name, bytes) in mavlink_seeds() {
        out.push((
            PathBuf::from(format!("mavlink_ingest/seed-framed-{name}.bin")),
            framed(&bytes),
        ));
        out.push((PathBuf::from(format!("mavlink_ingest/seed-{name}.bin")), bytes));
    }
    for (name, bytes) in toml_files(&root.join("airframes")) {
        out.push((PathBuf::from(format!("airframe_parse/seed-{name}.toml")), bytes));
    }
    for (name, bytes) in toml_files(&root.join("scenarios")) {
        out.push((PathBuf::from(format!("scenario_parse/seed-{name}.toml")), bytes));
    }
    for (name, bytes) in param_file_seeds() {
        out.push((PathBuf::from(format!("param_file_parse/seed-{name}.params")), bytes));
    }
    out
}

#[test]
fn mavlink_seeds_are_whole_known_messages() {
    for (name, bytes) in mavlink_seeds() {
        let frames = decode_datagram(&bytes);
        assert!(!frames.is_empty(), "{name}: no frame");
        for f in &frames {
            assert!(matches!(f, Inbound::Message { .. }), "{name}: {f:?}");
        }
    }
}

#[test]
fn fuzz_seed_corpus_is_current() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let corpus = root.join("fuzz/corpus");
    let write = std::env::var_os("ROTORPILOT_WRITE_FUZZ_CORPUS").is_some_and(|v| v == "1");
    let mut stale = Vec::new();
    for (path, bytes) in seeds(root) {
        let file = corpus.join(&path);
        if write {
            std::fs::create_dir_all(file.parent().unwrap()).unwrap();
            std::fs::write(&file, &bytes).unwrap();
        } else if std::fs::read(&file).ok().as_deref() != Some(&bytes[..]) {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "fuzz seed corpus missing or stale: {stale:?}; rewrite it with \
         ROTORPILOT_WRITE_FUZZ_CORPUS=1 cargo test --release --test integration fuzz_corpus::"
    );
}
