//! What QGroundControl asks of a vehicle after AUTOPILOT_VERSION, answered by the vehicle's MAVLink
//! endpoint with virtual clocks: PROTOCOL_VERSION, then the standard modes (AVAILABLE_MODES one
//! index at a time as QGC's `StandardModes` asks, or all at once) and CURRENT_MODE.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::FlightMode;

/// REQUEST_MESSAGE for message `id` with `param2`.
fn request(id: f32, param2: f32) -> MavMessage {
    let params = [id, param2, 0.0, 0.0, 0.0, 0.0, 0.0];
    MavMessage::COMMAND_LONG(rotorpilot::mav::gcs::command_long(
        (1, 1),
        MavCmd::MAV_CMD_REQUEST_MESSAGE,
        params,
    ))
}

#[test]
fn protocol_version_says_mavlink_2_by_either_request() {
    let mut b = Bench::new();
    for ask in [
        request(300.0, 0.0),
        command(MavCmd::MAV_CMD_REQUEST_PROTOCOL_VERSION, 1.0),
    ] {
        b.send(Gcs, QGC, ask);
        let out = b.out();
        assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
        let [(_, to, MavMessage::PROTOCOL_VERSION(v))] = &named(&out, "PROTOCOL_VERSION")[..] else {
            panic!("{out:?}")
        };
        assert_eq!((*to, v.version, v.min_version, v.max_version), (QGC, 200, 100, 200));
    }
}

#[test]
fn the_modes_come_one_index_at_a_time_as_qgc_asks_and_all_at_once() {
    let mut b = Bench::new();
    let mut modes = Vec::new();
    let mut index = 1;
    loop {
        b.send(Gcs, QGC, request(435.0, index as f32));
        let out = b.out();
        assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED], "index {index}");
        let [(_, _, MavMessage::AVAILABLE_MODES(m))] = &named(&out, "AVAILABLE_MODES")[..] else {
            panic!("{out:?}")
        };
        assert_eq!(m.mode_index, index);
        modes.push(m.clone());
        if index == m.number_modes {
            break;
        }
        index += 1;
    }
    let flown: Vec<FlightMode> = modes
        .iter()
        .map(|m| FlightMode::from_custom_mode(m.custom_mode).unwrap())
        .collect();
    assert_eq!(flown, FlightMode::selectable());
    let hold = &modes[4];
    assert_eq!(hold.mode_name.to_str().unwrap(), "Hold");
    assert_eq!(hold.standard_mode, MavStandardMode::MAV_STANDARD_MODE_NON_STANDARD);
    assert_eq!(modes[1].standard_mode, MavStandardMode::MAV_STANDARD_MODE_ALTITUDE_HOLD);
    assert_eq!(modes[2].standard_mode, MavStandardMode::MAV_STANDARD_MODE_POSITION_HOLD);

    // One past the last: denied, nothing sent (PX4's answer).
    b.send(Gcs, QGC, request(435.0, modes.len() as f32 + 1.0));
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_DENIED]);
    assert!(named(&out, "AVAILABLE_MODES").is_empty());

    // All at once: the ACK, then every mode in order.
    b.send(Gcs, QGC, request(435.0, 0.0));
    let out = b.out();
    assert!(matches!(out[0].2, MavMessage::COMMAND_ACK(_)), "{out:?}");
    let all: Vec<AVAILABLE_MODES_DATA> = named(&out, "AVAILABLE_MODES")
        .iter()
        .map(|(_, _, m)| match m {
            MavMessage::AVAILABLE_MODES(m) => m.clone(),
            _ => unreachable!(),
        })
        .collect();
    assert_eq!(all, modes);
}

#[test]
fn current_mode_is_streamed_at_half_a_hertz_and_sent_on_request() {
    let mut b = Bench::new();
    let times = (1..=80).map(|k| f64::from(k) * 0.05).map(|t| (t, t));
    let seen = b.count_sent("CURRENT_MODE", Gcs, times);
    assert_eq!(seen, 2, "4 s at 0.5 Hz");
    b.state.mode = FlightMode::ReturnToLaunch;
    b.m.handle_state(b.state);
    b.send(Gcs, QGC, request(436.0, 0.0));
    let out = b.out();
    let [(_, _, MavMessage::CURRENT_MODE(m))] = &named(&out, "CURRENT_MODE")[..] else {
        panic!("{out:?}")
    };
    assert_eq!(m.custom_mode, FlightMode::ReturnToLaunch.custom_mode());
    assert_eq!(m.intended_custom_mode, m.custom_mode);
    assert_eq!(m.standard_mode, MavStandardMode::MAV_STANDARD_MODE_SAFE_RECOVERY);
}

#[test]
fn system_time_goes_to_the_api_link_at_1_hz_from_the_wall_clock_and_on_request() {
    // Wall time 0 is 2026-12-02 00:00:00 UTC, as a signing timestamp.
    let unix_s: u64 = 1_795_996_800;
    let mut b = Bench::with(|config| config.signing_epoch = (unix_s - 1_420_070_400) * 100_000);
    let seconds = (1..=10).map(|k| (f64::from(k), f64::from(k)));
    assert_eq!(
        b.count_sent("SYSTEM_TIME", Api, seconds.clone()),
        10,
        "onboard mode: 1 Hz"
    );
    assert_eq!(
        b.count_sent("SYSTEM_TIME", Gcs, seconds.map(|(w, s)| (w + 10.0, s + 10.0))),
        0
    );
    b.at(25.5, 25.5);
    b.out();
    b.send(Gcs, QGC, request(2.0, f32::NAN));
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
    let [(_, _, MavMessage::SYSTEM_TIME(t))] = &named(&out, "SYSTEM_TIME")[..] else {
        panic!("{out:?}")
    };
    assert_eq!(t.time_unix_usec, (unix_s * 1_000_000) + 25_500_000);
}

#[test]
fn the_events_protocol_says_there_are_none_and_answers_requests_with_unavailable() {
    let mut b = Bench::new();
    let every_3_s = (1..=9).map(|k| (f64::from(k), f64::from(k)));
    assert_eq!(b.count_sent("CURRENT_EVENT_SEQUENCE", Gcs, every_3_s), 3);
    b.send(
        Gcs,
        QGC,
        MavMessage::REQUEST_EVENT(REQUEST_EVENT_DATA {
            first_sequence: 0,
            last_sequence: 4,
            target_system: 1,
            target_component: 1,
        }),
    );
    let out = b.out();
    let [(_, to, MavMessage::RESPONSE_EVENT_ERROR(e))] = &named(&out, "RESPONSE_EVENT_ERROR")[..] else {
        panic!("{out:?}")
    };
    assert_eq!(*to, QGC);
    assert_eq!(
        (e.sequence, e.reason),
        (0, MavEventErrorReason::MAV_EVENT_ERROR_REASON_UNAVAILABLE)
    );
}
