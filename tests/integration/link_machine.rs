//! The vehicle's MAVLink endpoint (`mav::link::LinkMachine`) driven in-process with virtual
//! time: what a link does over seconds of wall and simulated time is checked in milliseconds,
//! with no socket and no thread. Each test plays a ground station and the vehicle's tick thread.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use mavlink::Message;
use rotorpilot::commander::{FlightMode, Outcome, Request};
use rotorpilot::guidance::Home;
use rotorpilot::mav::codec::frame_message;
use rotorpilot::mav::gcs::{command_long, gcs_header};
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};
use rotorpilot::mav::signing::{Signing, SigningKey};
use rotorpilot::mav::streams::LinkKind;

#[test]
fn heartbeats_follow_wall_time_simulated_time_and_state_changes() {
    let mut b = Bench::new();
    b.at(0.5, 0.5);
    assert!(named(&b.out(), "HEARTBEAT").is_empty(), "nothing due half a second in");
    b.at(1.0, 1.0);
    let out = b.out();
    let beats = named(&out, "HEARTBEAT");
    assert_eq!(beats.len(), 2, "one per link");
    assert!(beats.iter().any(|(l, to, _)| *l == Gcs && *to == QGC));
    assert!(beats.iter().any(|(l, to, _)| *l == Api && *to == SDK));
    // At ×10, simulated time makes it due after 0.1 s of wall time.
    b.at(1.1, 2.0);
    assert_eq!(named(&b.out(), "HEARTBEAT").len(), 2);
    // At ×0.1, wall time still makes it due every second.
    b.at(2.1, 2.1);
    assert_eq!(named(&b.out(), "HEARTBEAT").len(), 2);
    b.state.armed = true;
    b.state.mode = FlightMode::Takeoff;
    b.at(2.2, 2.2);
    let out = b.out();
    let beats = named(&out, "HEARTBEAT");
    assert_eq!(beats.len(), 2, "a state change is announced at once");
    let MavMessage::HEARTBEAT(hb) = &beats[0].2 else {
        unreachable!()
    };
    assert_eq!(hb.custom_mode, FlightMode::Takeoff.custom_mode());
}

#[test]
fn a_peer_gets_telemetry_until_ten_seconds_of_silence() {
    let mut b = Bench::new();
    b.send(Gcs, OTHER, gcs_heartbeat());
    b.at(1.0, 1.0);
    let to = b.heartbeats_to(Gcs);
    assert_eq!(to.len(), 2);
    assert!(to.contains(&QGC) && to.contains(&OTHER));
    b.at(10.5, 10.5);
    let to = b.heartbeats_to(Gcs);
    assert_eq!(
        to,
        vec![QGC],
        "the silent peer is forgotten, the configured remote stays"
    );
}

#[test]
fn a_command_is_answered_once_with_the_vehicles_outcome_and_repeats_from_the_cache() {
    let mut b = Bench::new();
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    assert!(b.out().is_empty(), "no ACK before the vehicle answered");
    let asks = b.asks();
    assert_eq!(asks.len(), 1);
    assert_eq!(
        asks[0].request,
        VehicleRequest::Commander(Request::Arm { force: false })
    );
    // The retransmission while the vehicle works on it is dropped.
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    assert!(b.asks().is_empty() && b.out().is_empty());
    b.m.handle_reply(b.now, asks[0].token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_ACCEPTED]);
    // A later retransmission gets the remembered result and is not executed again.
    b.at(2.0, 2.0);
    b.out();
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    assert!(b.asks().is_empty());
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_ACCEPTED]);
    // After the window it is a new command.
    b.at(5.5, 5.5);
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    assert_eq!(b.asks().len(), 1);
}

#[test]
fn a_refusal_is_the_ack_then_the_reason_in_that_order() {
    let mut b = Bench::new();
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_NAV_LAND, 0.0));
    let token = b.asks()[0].token.unwrap();
    b.m.handle_reply(b.now, token, VehicleReply::Outcome(Outcome::Denied("Not armed".into())));
    let out = b.out();
    let names: Vec<&str> = out.iter().map(|(_, _, m)| m.message_name()).collect();
    assert_eq!(names, ["COMMAND_ACK", "STATUSTEXT"]);
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_DENIED]);
    // A full inbox is TEMPORARILY_REJECTED, saying why.
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH, 0.0));
    let token = b.asks()[0].token.unwrap();
    b.m.handle_reply(b.now, token, VehicleReply::Busy);
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_TEMPORARILY_REJECTED]);
    assert!(matches!(&out[1].2, MavMessage::STATUSTEXT(t) if t.text.to_str().unwrap() == "Vehicle busy"));
}

#[test]
fn every_request_message_is_answered_with_the_message() {
    let mut b = Bench::new();
    for _ in 0..2 {
        b.send(Api, SDK, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0));
        let out = b.out();
        assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_ACCEPTED]);
        assert_eq!(named(&out, "AUTOPILOT_VERSION").len(), 1);
        assert!(out.iter().all(|(l, to, _)| *l == Api && *to == SDK));
    }
    assert!(b.asks().is_empty(), "a request for a message never reaches the vehicle");
}

/// The PARAM_VALUE indices sent from `from_s` to `to_s` of wall time, a millisecond at a time.
fn param_indices(b: &mut Bench, from_s: f64, to_s: f64) -> Vec<u16> {
    let mut indices = Vec::new();
    let mut wall_s = from_s;
    while wall_s < to_s {
        wall_s += 0.001;
        b.at(wall_s, wall_s);
        indices.extend(b.out().into_iter().filter_map(|(_, _, m)| match m {
            MavMessage::PARAM_VALUE(p) => Some(p.param_index),
            _ => None,
        }));
    }
    indices
}

fn param_request_list() -> MavMessage {
    MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
    })
}

#[test]
fn a_parameter_list_is_paced_at_one_per_millisecond_after_px4s_hash() {
    let mut b = Bench::new();
    let n = table().len();
    b.send(Gcs, QGC, param_request_list());
    b.at(0.0095, 0.0095);
    let first = b.out();
    let values = named(&first, "PARAM_VALUE");
    assert_eq!(values.len(), 10, "t = 0, 1, …, 9 ms");
    let is_hash = |m: &MavMessage| matches!(m, MavMessage::PARAM_VALUE(p) if p.param_id.to_str() == Ok("_HASH_CHECK") && p.param_index == u16::MAX);
    assert!(is_hash(&values[0].2), "the hash goes first: {:?}", values[0]);
    assert_eq!(param_indices(&mut b, 0.0095, 0.2), (9..n as u16).collect::<Vec<_>>());
}

#[test]
fn a_hash_check_param_set_stops_the_list_as_a_cached_ground_station_asks() {
    let mut b = Bench::new();
    b.send(Gcs, QGC, param_request_list());
    b.at(0.0045, 0.0045);
    assert_eq!(named(&b.out(), "PARAM_VALUE").len(), 5);
    b.send(Gcs, QGC, param_set("_HASH_CHECK", 0.0));
    assert!(b.asks().is_empty(), "nothing for the vehicle");
    assert!(param_indices(&mut b, 0.0045, 0.2).is_empty(), "the list stopped");
    // Asked by name, the hash comes alone.
    b.send(
        Gcs,
        QGC,
        MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
            param_index: -1,
            target_system: 1,
            target_component: 1,
            param_id: param_id("_HASH_CHECK"),
        }),
    );
    let out = b.out();
    assert!(
        matches!(&out[..], [(_, QGC, MavMessage::PARAM_VALUE(p))] if p.param_index == u16::MAX),
        "{out:?}"
    );
}

#[test]
fn a_parameter_set_waits_for_the_vehicle_is_echoed_to_every_peer_and_announced_on_every_link() {
    let mut b = Bench::new();
    b.send(Gcs, OTHER, gcs_heartbeat());
    b.send(Gcs, QGC, param_set("MIS_TAKEOFF_ALT", 5.0));
    let asks = b.asks();
    assert_eq!(
        asks[0].request,
        VehicleRequest::SetParam {
            name: "MIS_TAKEOFF_ALT".into(),
            value: 5.0
        }
    );
    let mut after = table();
    let result = after.set("MIS_TAKEOFF_ALT", 5.0, 1e-3);
    b.m.handle_reply(
        b.now,
        asks[0].token.unwrap(),
        VehicleReply::Param {
            result,
            table: std::sync::Arc::new(after),
        },
    );
    let out = b.out();
    let echoes = named(&out, "PARAM_VALUE");
    let mut to: Vec<u16> = echoes.iter().map(|e| e.1).collect();
    to.sort_unstable();
    assert_eq!(to, vec![QGC, OTHER]);
    assert!(matches!(&echoes[0].2, MavMessage::PARAM_VALUE(p) if p.param_value == 5.0));
    // 5 ms later, as PX4 does, the change goes to every peer of every link unasked (MAVSDK's
    // Failure plugin learns SYS_FAILURE_EN that way), once.
    let at = b.now.wall_s;
    b.at(at + 0.004, b.now.sim_s);
    assert!(named(&b.out(), "PARAM_VALUE").is_empty(), "not before 5 ms");
    b.at(at + 0.006, b.now.sim_s);
    let out = b.out();
    let mut to: Vec<(LinkKind, u16)> = named(&out, "PARAM_VALUE").iter().map(|e| (e.0, e.1)).collect();
    to.sort_unstable_by_key(|t| (t.0 == Api, t.1));
    assert_eq!(to, vec![(Gcs, QGC), (Gcs, OTHER), (Api, SDK)]);
    b.at(at + 1.0, b.now.sim_s);
    assert!(named(&b.out(), "PARAM_VALUE").is_empty(), "announced once");
    // A read afterwards gives the new value: the link keeps the vehicle's table.
    b.send(
        Gcs,
        QGC,
        MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
            param_index: -1,
            target_system: 1,
            target_component: 1,
            param_id: param_id("MIS_TAKEOFF_ALT"),
        }),
    );
    assert!(matches!(&b.out()[0].2, MavMessage::PARAM_VALUE(p) if p.param_value == 5.0));
}

fn mission_item(seq: u16, x: i32) -> MavMessage {
    MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
        seq,
        x,
        y: 85_000_000,
        z: 10.0,
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        target_system: 1,
        target_component: 1,
        autocontinue: 1,
        ..Default::default()
    })
}

#[test]
fn a_mission_upload_is_stored_once_the_vehicle_took_it_and_re_requests_missing_items() {
    let mut b = Bench::new();
    b.send(
        Gcs,
        QGC,
        MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: 2,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        }),
    );
    let requested = |out: &[(LinkKind, u16, MavMessage)]| -> Vec<u16> {
        out.iter()
            .filter_map(|(_, _, m)| match m {
                MavMessage::MISSION_REQUEST_INT(r) => Some(r.seq),
                _ => None,
            })
            .collect()
    };
    assert_eq!(requested(&b.out()), vec![0]);
    // Silence: item 0 is asked for again after 0.25 s of wall time.
    b.at(0.3, 0.3);
    assert_eq!(requested(&b.out()), vec![0]);
    let home_lat = (Home::default().lat_deg * 1e7) as i32;
    b.send(Gcs, QGC, mission_item(0, home_lat));
    assert_eq!(requested(&b.out()), vec![1]);
    b.send(Gcs, QGC, mission_item(1, home_lat + 100));
    assert!(
        named(&b.out(), "MISSION_ACK").is_empty(),
        "the vehicle has not taken it yet"
    );
    let asks = b.asks();
    assert!(matches!(&asks[0].request, VehicleRequest::Commander(Request::SetMission(m)) if m.len() == 2));
    assert!(b.m.stored_mission().is_empty());
    b.m.handle_reply(b.now, asks[0].token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
    let out = b.out();
    assert!(matches!(&out[0].2, MavMessage::MISSION_ACK(a) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED));
    assert_eq!(b.m.stored_mission().len(), 2);
}

#[test]
fn with_a_key_only_signed_frames_pass_and_every_frame_out_is_signed() {
    let key = SigningKey::from_passphrase("link machine");
    let epoch = 1_000_000_000;
    let mut b = Bench::with(|c| {
        c.signing = Signing::new(Some(key.clone()), epoch);
        c.signing_epoch = epoch;
    });
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    assert!(b.asks().is_empty(), "an unsigned command is dropped");
    assert_eq!(b.m.signing_dropped(), 1);
    // Signed with the key at the link's clock, it passes.
    let mut gcs = Signing::new(Some(key), epoch);
    let mut frame = frame_message(gcs_header(0), &command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0));
    gcs.seal(&mut frame, 0, epoch + 10);
    b.m.handle_datagram(b.now, Gcs, QGC, frame.raw_bytes());
    assert_eq!(b.asks().len(), 1);
    b.at(1.0, 1.0);
    let mut sent = 0;
    while let Some(t) = b.m.poll_transmit() {
        assert_eq!(t.bytes[2] & 1, 1, "MAVLINK_IFLAG_SIGNED set on every frame out");
        sent += 1;
    }
    assert!(sent > 0);
}

#[test]
fn setup_signing_waits_for_the_key_file_and_says_so() {
    let mut b = Bench::with(|c| c.key_store = true);
    b.send(
        Gcs,
        QGC,
        MavMessage::SETUP_SIGNING(SETUP_SIGNING_DATA {
            initial_timestamp: 5,
            target_system: 1,
            target_component: 1,
            secret_key: [7u8; 32],
        }),
    );
    let stored = b.m.poll_store().expect("the key goes to the key file");
    assert_eq!(stored.key, Some(SigningKey::from_bytes([7u8; 32])));
    assert!(b.out().is_empty(), "nothing said before the file is written");
    b.m.handle_stored(b.now, Ok(()));
    let out = b.out();
    assert!(
        matches!(&out[0].2, MavMessage::STATUSTEXT(t) if t.text.to_str().unwrap() == "Signing enabled; key stored")
    );
    assert_eq!(out[0].0, Gcs);
}

#[test]
fn stream_rates_count_simulated_time() {
    let mut b = Bench::new();
    // The GCS link streams ATTITUDE at 15 Hz: 15 per simulated second whatever the wall clock.
    let times = (1..=200)
        .map(|k| f64::from(k) * 0.005)
        .map(|wall_s| (wall_s, wall_s * 0.5));
    let count = b.count_sent("ATTITUDE", Gcs, times);
    assert!((7..=9).contains(&count), "{count} ATTITUDE in 0.5 simulated seconds");
}

#[test]
fn ground_truth_streams_on_request_as_px4_sitl_serves_it() {
    use rotorpilot::math::{UnitQuat, Vec3};
    use rotorpilot::sitl::PlantTruth;
    let mut b = Bench::new();
    b.state.truth = Some(PlantTruth {
        pos_w: Vec3::new(10.0, 0.0, -5.0),
        vel_w: Vec3::new(1.0, 0.0, 0.0),
        q_wb: UnitQuat::identity(),
        omega_b: Vec3::zeros(),
        on_ground: false,
        external_force_w: Vec3::zeros(),
        external_torque_b: Vec3::zeros(),
        accel_w: Vec3::zeros(),
        wind_w: Vec3::zeros(),
        drag_force_w: Vec3::zeros(),
    });
    // Off by default.
    let times = (1..=100).map(|k| (f64::from(k) * 0.01, f64::from(k) * 0.01));
    assert_eq!(b.count_sent("HIL_STATE_QUATERNION", Api, times), 0);
    // MAVSDK's set_rate_ground_truth(15): SET_MESSAGE_INTERVAL 115 at 66 667 µs.
    let params = [115.0, 66_667.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    b.send(
        Api,
        SDK,
        MavMessage::COMMAND_LONG(command_long((1, 1), MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, params)),
    );
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_ACCEPTED]);
    let times = (101..=200).map(|k| (f64::from(k) * 0.01, f64::from(k) * 0.01));
    let count = b.count_sent("HIL_STATE_QUATERNION", Api, times);
    assert!((14..=16).contains(&count), "{count} in a second");
    b.at(2.1, 2.1);
    let out = b.out();
    let truth = named(&out, "HIL_STATE_QUATERNION");
    let Some((_, _, MavMessage::HIL_STATE_QUATERNION(t))) = truth.first() else {
        panic!("no ground truth: {out:?}")
    };
    let home = Home::default();
    assert!((f64::from(t.lat) / 1e7 - home.lat_deg - (10.0 / 6_371_000f64).to_degrees()).abs() < 2e-7);
    assert_eq!((t.alt, t.vx), (((home.alt_amsl_m + 5.0) * 1000.0).round() as i32, 100));
}

/// SERIAL_CONTROL opening a shell (RESPOND) with `text` typed.
fn shell_line(text: &str) -> MavMessage {
    let mut data = [0u8; 70];
    data[..text.len()].copy_from_slice(text.as_bytes());
    MavMessage::SERIAL_CONTROL(SERIAL_CONTROL_DATA {
        device: SerialControlDev::SERIAL_CONTROL_DEV_SHELL,
        flags: SerialControlFlag::SERIAL_CONTROL_FLAG_RESPOND | SerialControlFlag::SERIAL_CONTROL_FLAG_EXCLUSIVE,
        count: text.len() as u8,
        data,
        ..Default::default()
    })
}

#[test]
fn five_thousand_addresses_writing_once_get_no_more_telemetry_and_leave_nothing_behind() {
    use rotorpilot::mav::link::{MAX_PEERS, PEER_TIMEOUT_S};
    let mut b = Bench::new();
    b.at(0.5, 0.5);
    b.out();
    // One second of telemetry to the configured ground station alone.
    let alone = (1..=100).map(|k| (0.5 + 0.01 * f64::from(k), 0.5 + 0.01 * f64::from(k)));
    let per_second_alone = b.count_sent("ATTITUDE", Gcs, alone);
    assert!(per_second_alone > 0);
    // 5 000 source ports each send a heartbeat, open a shell and ask for the parameter list.
    for k in 0..5_000u16 {
        let from = 50_000 + k;
        b.send(Gcs, from, gcs_heartbeat());
        b.send(Gcs, from, shell_line("ver\n"));
        b.send(
            Gcs,
            from,
            MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
                target_system: 1,
                target_component: 1,
            }),
        );
    }
    let held = b.m.held_for_clients();
    assert!(held.peers <= MAX_PEERS, "{held:?}");
    assert!(
        held.shells <= MAX_PEERS + 1 && held.param_lists <= MAX_PEERS + 1,
        "{held:?}"
    );
    b.out();
    // Telemetry goes to the remote and at most MAX_PEERS peers, not to 5 000 addresses.
    let during = (1..=100).map(|k| (1.5 + 0.01 * f64::from(k), 1.5 + 0.01 * f64::from(k)));
    let per_second_flooded = b.count_sent("ATTITUDE", Gcs, during);
    assert!(
        per_second_flooded <= (1 + MAX_PEERS) * (per_second_alone + 1),
        "{per_second_flooded} ATTITUDE/s against {per_second_alone} for one ground station"
    );
    // Once they are silent, they are forgotten with their shells and lists.
    b.at(3.0 + PEER_TIMEOUT_S, 3.0 + PEER_TIMEOUT_S);
    b.out();
    let held = b.m.held_for_clients();
    assert_eq!((held.peers, held.shells, held.param_lists), (0, 0, 0), "{held:?}");
    // The configured ground station is served as before.
    b.at(4.5 + PEER_TIMEOUT_S, 4.5 + PEER_TIMEOUT_S);
    assert_eq!(b.heartbeats_to(Gcs), vec![QGC]);
}
