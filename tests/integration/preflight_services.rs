//! What MAVSDK's calibration, failure and log-files plugins send (and QGroundControl's sensor
//! page, MAVProxy's `log list`), answered by the vehicle's MAVLink endpoint with virtual clocks
//! as PX4 SITL answers: `[cal]` STATUSTEXTs after the ACK of PREFLIGHT_CALIBRATION, a failure
//! unit without a model refused by name, the empty log list.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::Request;
use rotorpilot::mav::link::VehicleRequest;
use rotorpilot::mav::streams::LinkKind;

/// COMMAND_LONG `command` with MAVSDK's parameters (the unused ones 0).
fn long(command: MavCmd, params: [f32; 7]) -> MavMessage {
    MavMessage::COMMAND_LONG(rotorpilot::mav::gcs::command_long((1, 1), command, params))
}

/// The STATUSTEXTs in `out`, as (severity, text).
fn texts(out: &[(LinkKind, u16, MavMessage)]) -> Vec<(MavSeverity, String)> {
    out.iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::STATUSTEXT(t) => Some((t.severity, t.text.to_str().unwrap().to_string())),
            _ => None,
        })
        .collect()
}

#[test]
fn gyro_calibration_runs_the_cal_protocol_after_its_ack() {
    let mut b = Bench::new();
    b.send(
        Api,
        SDK,
        long(
            MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
    );
    let out = b.out();
    assert!(
        matches!(&out[0].2, MavMessage::COMMAND_ACK(a) if a.result == MavResult::MAV_RESULT_ACCEPTED
        && a.command == MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION)
    );
    let said: Vec<String> = texts(&out).into_iter().map(|(_, t)| t).collect();
    assert_eq!(
        said,
        [
            "[cal] calibration started: 2 gyro",
            "[cal] progress <0>",
            "[cal] progress <100>",
            "[cal] calibration done: gyro"
        ]
    );
    assert!(out.iter().all(|(link, to, _)| (*link, *to) == (Api, SDK)));

    // Level horizon (param5 = 2) likewise.
    b.send(
        Api,
        SDK,
        long(
            MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION,
            [0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
        ),
    );
    let said = texts(&b.out());
    assert_eq!(said.last().unwrap().1, "[cal] calibration done: level");
}

#[test]
fn accel_and_mag_calibration_fail_with_the_reason_and_armed_vehicles_refuse() {
    let mut b = Bench::new();
    for (params, sensor) in [
        ([0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0], "accel"),
        ([0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0], "mag"),
    ] {
        b.send(Api, SDK, long(MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION, params));
        let out = b.out();
        assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
        let said = texts(&out);
        assert_eq!(said[0].1, format!("[cal] calibration started: 2 {sensor}"));
        assert_eq!(
            said.last().unwrap(),
            &(
                MavSeverity::MAV_SEVERITY_CRITICAL,
                format!("[cal] calibration failed: {sensor} not simulated")
            )
        );
    }
    // RC calibration: hardware this vehicle lacks.
    b.send(
        Api,
        SDK,
        long(
            MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION,
            [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        ),
    );
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_UNSUPPORTED]);

    b.state.armed = true;
    b.tick();
    b.out();
    b.send(
        Gcs,
        QGC,
        long(
            MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
    );
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_TEMPORARILY_REJECTED]);
    assert!(texts(&out).iter().all(|(_, t)| !t.starts_with("[cal]")), "{out:?}");
}

#[test]
fn an_optical_flow_failure_is_refused_by_name_and_gps_and_motor_failures_reach_the_vehicle() {
    let mut b = Bench::new();
    // An optical-flow sensor is not simulated: UNSUPPORTED, with the reason.
    b.send(
        Api,
        SDK,
        long(MavCmd::MAV_CMD_INJECT_FAILURE, [5.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
    );
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_UNSUPPORTED]);
    assert_eq!(
        texts(&out),
        vec![(
            MavSeverity::MAV_SEVERITY_WARNING,
            "Failure injection: optical_flow not simulated".to_string()
        )]
    );
    assert!(b.asks().is_empty());

    // MAVSDK's failure.inject(SENSOR_GPS, OFF, instance=0): for the vehicle to answer.
    b.send(
        Api,
        SDK,
        long(MavCmd::MAV_CMD_INJECT_FAILURE, [4.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
    );
    assert!(acks(&b.out()).is_empty(), "the vehicle answers");
    let asks = b.asks();
    let gps_off = "gps:off".parse().unwrap();
    assert!(
        matches!(&asks[..], [ask] if ask.request == VehicleRequest::Commander(Request::InjectSensorFailure(gps_off))),
        "{asks:?}"
    );

    // SYSTEM_MOTOR OFF, motor 1: for the vehicle to answer.
    b.send(
        Api,
        SDK,
        long(MavCmd::MAV_CMD_INJECT_FAILURE, [101.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
    );
    assert!(acks(&b.out()).is_empty(), "the vehicle answers");
    let asks = b.asks();
    assert!(
        matches!(&asks[..], [ask] if ask.request == VehicleRequest::Commander(Request::InjectRotorFailure { rotor: 1, failed: true })),
        "{asks:?}"
    );
}

#[test]
fn the_log_list_is_empty_as_px4_with_no_logs() {
    let mut b = Bench::new();
    let list = MavMessage::LOG_REQUEST_LIST(LOG_REQUEST_LIST_DATA {
        start: 0,
        end: 0xFFFF,
        target_system: 1,
        target_component: 1,
    });
    b.send(Api, SDK, list);
    let out = b.out();
    let [(Api, SDK, MavMessage::LOG_ENTRY(e))] = &out[..] else {
        panic!("{out:?}")
    };
    assert_eq!((e.num_logs, e.last_log_num, e.id, e.size), (0, 0, 0, 0));

    // Addressed to another system: not ours, no answer.
    let elsewhere = MavMessage::LOG_REQUEST_LIST(LOG_REQUEST_LIST_DATA {
        start: 0,
        end: 0xFFFF,
        target_system: 7,
        target_component: 1,
    });
    b.send(Api, SDK, elsewhere);
    assert!(named(&b.out(), "LOG_ENTRY").is_empty());
}
