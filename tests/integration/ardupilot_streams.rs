//! The telemetry of an ArduCopter-faced vehicle (docs/mavlink.md §5.1) through the shipped link
//! machine with virtual time: nothing periodic but HEARTBEAT until a ground station asks, then
//! the asked groups at the asked rate, on the link that asked; a PX4-faced vehicle does not offer
//! ArduPilot's own messages.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use std::collections::BTreeMap;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use mavlink::Message;
use rotorpilot::math::{UnitQuat, Vec3};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;
use rotorpilot::sitl::PlantTruth;

fn ardupilot() -> Bench {
    let mut b = Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot));
    b.state.truth = Some(PlantTruth {
        pos_w: Vec3::zeros(),
        vel_w: Vec3::zeros(),
        q_wb: UnitQuat::identity(),
        omega_b: Vec3::zeros(),
        on_ground: true,
        external_force_w: Vec3::zeros(),
        external_torque_b: Vec3::zeros(),
        accel_w: Vec3::zeros(),
        wind_w: Vec3::zeros(),
        drag_force_w: Vec3::zeros(),
    });
    b
}

/// How many of each message went out on `link` while both clocks ran from `from_s` to `to_s` [s]
/// in 5 ms steps.
fn sent_between(b: &mut Bench, link: LinkKind, from_s: f64, to_s: f64) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    let steps = ((to_s - from_s) / 0.005).round() as usize;
    for k in 1..=steps {
        let t = from_s + k as f64 * 0.005;
        b.at(t, t);
        for (l, _, msg) in b.out() {
            if l == link {
                *counts.entry(msg.message_name().to_string()).or_insert(0) += 1;
            }
        }
    }
    counts
}

fn request_data_stream(stream: MavDataStream, rate_hz: u16, start: bool) -> MavMessage {
    MavMessage::REQUEST_DATA_STREAM(REQUEST_DATA_STREAM_DATA {
        req_message_rate: rate_hz,
        target_system: 1,
        target_component: 1,
        req_stream_id: stream,
        start_stop: u8::from(start),
    })
}

#[test]
fn an_ardupilot_vehicle_streams_only_what_was_asked_for() {
    let mut b = ardupilot();
    for link in [Gcs, Api] {
        let quiet = sent_between(
            &mut b,
            link,
            3.0 * f64::from(link == Api),
            3.0 + 3.0 * f64::from(link == Api),
        );
        assert_eq!(
            quiet.keys().collect::<Vec<_>>(),
            vec!["HEARTBEAT"],
            "{link:?}: {quiet:?}"
        );
        assert!((2..=4).contains(&quiet["HEARTBEAT"]), "{link:?}: 1 Hz, {quiet:?}");
    }
    // MAVProxy's request: every group at 4 Hz, on the GCS link.
    b.send(
        Gcs,
        QGC,
        request_data_stream(MavDataStream::MAV_DATA_STREAM_ALL, 4, true),
    );
    let asked = sent_between(&mut b, Gcs, 6.0, 8.0);
    for name in [
        "ATTITUDE",
        "GLOBAL_POSITION_INT",
        "LOCAL_POSITION_NED",
        "VFR_HUD",
        "SYS_STATUS",
        "GPS_RAW_INT",
        "EKF_STATUS_REPORT",
        "AHRS",
        "AHRS2",
        "SIMSTATE",
        "RAW_IMU",
        "SCALED_PRESSURE",
        "POWER_STATUS",
        "MEMINFO",
        "NAV_CONTROLLER_OUTPUT",
        "RC_CHANNELS",
        "SERVO_OUTPUT_RAW",
        "BATTERY_STATUS",
        "SYSTEM_TIME",
        "VIBRATION",
        "MISSION_CURRENT",
    ] {
        let n = asked.get(name).copied().unwrap_or(0);
        assert!((7..=9).contains(&n), "{name}: {n} in 2 s, not 4 Hz ({asked:?})");
    }
    for px4_only in [
        "EXTENDED_SYS_STATE",
        "HIGHRES_IMU",
        "CURRENT_MODE",
        "CURRENT_EVENT_SEQUENCE",
    ] {
        assert!(!asked.contains_key(px4_only), "{px4_only}: not in ArduCopter's groups");
    }
    assert!(
        !asked.contains_key("POSITION_TARGET_GLOBAL_INT"),
        "no position target on the ground"
    );
    let other = sent_between(&mut b, Api, 8.0, 9.0);
    assert_eq!(
        other.keys().collect::<Vec<_>>(),
        vec!["HEARTBEAT"],
        "the API link was not asked"
    );
    // A stop ends them.
    b.send(
        Gcs,
        QGC,
        request_data_stream(MavDataStream::MAV_DATA_STREAM_ALL, 4, false),
    );
    let stopped = sent_between(&mut b, Gcs, 9.0, 11.0);
    assert_eq!(stopped.keys().collect::<Vec<_>>(), vec!["HEARTBEAT"], "{stopped:?}");
}

#[test]
fn one_group_at_its_rate() {
    let mut b = ardupilot();
    b.send(
        Gcs,
        QGC,
        request_data_stream(MavDataStream::MAV_DATA_STREAM_EXTRA1, 10, true),
    );
    let extra1 = sent_between(&mut b, Gcs, 0.0, 2.0);
    let names: Vec<&str> = extra1.keys().map(String::as_str).collect();
    assert_eq!(names, vec!["AHRS2", "ATTITUDE", "HEARTBEAT", "SIMSTATE"]);
    assert!((19..=21).contains(&extra1["ATTITUDE"]), "10 Hz: {extra1:?}");
}

#[test]
fn ardupilots_own_messages_are_not_offered_by_px4() {
    let ack_of = |b: &mut Bench| {
        b.out()
            .into_iter()
            .find_map(|(_, _, m)| match m {
                MavMessage::COMMAND_ACK(a) => Some(a.result),
                _ => None,
            })
            .expect("an ACK")
    };
    let mut px4 = Bench::new();
    px4.send(Gcs, QGC, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 178.0));
    assert_eq!(ack_of(&mut px4), MavResult::MAV_RESULT_DENIED);
    px4.send(Gcs, QGC, command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, 27.0));
    assert_eq!(ack_of(&mut px4), MavResult::MAV_RESULT_DENIED);
    let mut ap = ardupilot();
    ap.send(Gcs, QGC, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 178.0));
    let out = ap.out();
    assert_eq!(named(&out, "AHRS2").len(), 1);
    assert!(out.iter().any(|(_, _, m)| matches!(
        m,
        MavMessage::COMMAND_ACK(a) if a.result == MavResult::MAV_RESULT_ACCEPTED
    )));
}
