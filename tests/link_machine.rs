//! The vehicle's MAVLink endpoint (`mav::link::LinkMachine`) driven in-process with virtual
//! time: what a link does over seconds of wall and simulated time is checked in milliseconds,
//! with no socket and no thread. Each test plays a ground station and the vehicle's tick thread.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use mavlink::dialects::common::*;
use mavlink::Message;
use rotorpilot::commander::{Event, FlightMode, Outcome, Request};
use rotorpilot::control::{ControllerGains, ControllerKind};
use rotorpilot::mav::codec::{decode_datagram, encode_v2, frame_message, Inbound};
use rotorpilot::mav::gcs::{command_long, gcs_header};
use rotorpilot::mav::link::{LinkConfig, LinkMachine, Now, ToVehicle, VehicleReply, VehicleRequest};
use rotorpilot::mav::signing::{Signing, SigningKey};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;
use rotorpilot::navigation::Home;
use rotorpilot::params::{ParamTable, VehicleSettings};
use rotorpilot::telemetry::Snapshot;

use LinkKind::{Api, Gcs};

/// The configured remote of the GCS link, of the API link, and a second ground station.
const QGC: u16 = 14550;
const SDK: u16 = 14540;
const OTHER: u16 = 40000;

fn table() -> ParamTable {
    ParamTable::new(&VehicleSettings::new(
        ControllerKind::Geometric,
        ControllerGains::default(),
        None,
    ))
}

/// A vehicle's endpoint, the clocks, and what came out of it.
struct Bench {
    m: LinkMachine<u16>,
    now: Now,
    /// The snapshot the vehicle publishes.
    state: Snapshot,
}

impl Bench {
    fn new() -> Self {
        Self::with(|_| {})
    }

    fn with(adjust: impl FnOnce(&mut LinkConfig<u16>)) -> Self {
        let state = Snapshot::initial(Home::default());
        let mut config = LinkConfig::new(Identity::autopilot(1, 4), vec![(Gcs, QGC), (Api, SDK)], table(), state);
        adjust(&mut config);
        let mut bench = Self {
            m: LinkMachine::new(config),
            now: Now::new(0.0, 0.0),
            state,
        };
        bench.tick();
        bench.out();
        bench
    }

    /// Moves both clocks to (`wall_s`, `sim_s`) and runs the due duties.
    fn at(&mut self, wall_s: f64, sim_s: f64) {
        self.now = Now::new(wall_s, sim_s);
        self.tick();
    }

    fn tick(&mut self) {
        self.state.t_s = self.now.sim_s;
        self.m.handle_state(self.state);
        self.m.handle_timeout(self.now);
    }

    /// `msg` from the ground station at `from` on `link`.
    fn send(&mut self, link: LinkKind, from: u16, msg: MavMessage) {
        let mut bytes = Vec::new();
        encode_v2(gcs_header(0), &msg, &mut bytes);
        self.m.handle_datagram(self.now, link, from, &bytes);
    }

    /// Everything sent since the last call: (link, destination, message), in order.
    fn out(&mut self) -> Vec<(LinkKind, u16, MavMessage)> {
        let mut out = Vec::new();
        while let Some(t) = self.m.poll_transmit() {
            for frame in decode_datagram(&t.bytes) {
                let Inbound::Message { message, .. } = frame else {
                    panic!("not a message: {frame:?}");
                };
                out.push((t.link, t.to, *message));
            }
        }
        out
    }

    /// Where the HEARTBEATs on `link` went since the last call.
    fn heartbeats_to(&mut self, link: LinkKind) -> Vec<u16> {
        let out = self.out();
        named(&out, "HEARTBEAT")
            .iter()
            .filter(|(l, ..)| *l == link)
            .map(|t| t.1)
            .collect()
    }

    /// Every request for the vehicle since the last call.
    fn asks(&mut self) -> Vec<ToVehicle> {
        std::iter::from_fn(|| self.m.poll_vehicle()).collect()
    }
}

fn command(command: MavCmd, param1: f32) -> MavMessage {
    let params = [param1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    MavMessage::COMMAND_LONG(command_long((1, 1), command, params))
}

fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        ..Default::default()
    })
}

fn param_id(name: &str) -> mavlink::types::CharArray<16> {
    let mut id = [0u8; 16];
    id[..name.len()].copy_from_slice(name.as_bytes());
    id.into()
}

fn param_set(name: &str, value: f32) -> MavMessage {
    MavMessage::PARAM_SET(PARAM_SET_DATA {
        param_value: value,
        target_system: 1,
        target_component: 1,
        param_id: param_id(name),
        param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
    })
}

fn named<'a>(out: &'a [(LinkKind, u16, MavMessage)], name: &str) -> Vec<&'a (LinkKind, u16, MavMessage)> {
    out.iter().filter(|(_, _, m)| m.message_name() == name).collect()
}

fn acks(out: &[(LinkKind, u16, MavMessage)]) -> Vec<MavResult> {
    out.iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::COMMAND_ACK(a) => Some(a.result),
            _ => None,
        })
        .collect()
}

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

#[test]
fn a_parameter_list_is_paced_at_one_per_millisecond() {
    let mut b = Bench::new();
    let n = table().len();
    b.send(
        Gcs,
        QGC,
        MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 1,
        }),
    );
    b.at(0.0095, 0.0095);
    assert_eq!(named(&b.out(), "PARAM_VALUE").len(), 10, "t = 0, 1, …, 9 ms");
    let mut indices = Vec::new();
    let mut wall_s = 0.0095;
    while wall_s < 0.2 {
        wall_s += 0.001;
        b.at(wall_s, wall_s);
        indices.extend(b.out().into_iter().filter_map(|(_, _, m)| match m {
            MavMessage::PARAM_VALUE(p) => Some(p.param_index),
            _ => None,
        }));
    }
    assert_eq!(indices, (10..n as u16).collect::<Vec<_>>());
}

#[test]
fn a_parameter_set_waits_for_the_vehicle_and_is_echoed_to_every_peer() {
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
            table: Box::new(after),
        },
    );
    let out = b.out();
    let echoes = named(&out, "PARAM_VALUE");
    let mut to: Vec<u16> = echoes.iter().map(|e| e.1).collect();
    to.sort_unstable();
    assert_eq!(to, vec![QGC, OTHER]);
    assert!(matches!(&echoes[0].2, MavMessage::PARAM_VALUE(p) if p.param_value == 5.0));
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

#[test]
fn link_loss_needs_silence_in_wall_and_simulated_time_and_fires_once() {
    let mut b = Bench::new();
    let mut after = table();
    after.set("NAV_DLL_ACT", 2.0, 1e-3).unwrap();
    b.send(Gcs, QGC, param_set("NAV_DLL_ACT", 2.0));
    let token = b.asks()[0].token.unwrap();
    b.m.handle_reply(
        b.now,
        token,
        VehicleReply::Param {
            result: Ok(0),
            table: Box::new(after),
        },
    );
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(9.9, 9.9);
    assert!(b.asks().is_empty());
    b.at(12.0, 5.0);
    assert!(b.asks().is_empty(), "simulated time is still within COM_DL_LOSS_T");
    b.at(12.1, 10.1);
    let asks = b.asks();
    assert_eq!(asks.len(), 1);
    assert_eq!(asks[0].request, VehicleRequest::Commander(Request::GcsLinkLost));
    assert_eq!(asks[0].token, None, "no answer is awaited");
    b.at(13.0, 11.0);
    assert!(b.asks().is_empty(), "once per loss");
    // The reaction comes back as a commander event, announced on every link like every event.
    b.m.handle_event(b.now, Event::Failsafe("GCS link lost: returning".into()));
    let out = b.out();
    let texts = named(&out, "STATUSTEXT");
    let said = |m: &MavMessage| {
        matches!(m, MavMessage::STATUSTEXT(t) if t.severity == MavSeverity::MAV_SEVERITY_CRITICAL
            && t.text.to_str().unwrap() == "GCS link lost: returning")
    };
    assert!(
        texts.iter().any(|(link, to, m)| (*link, *to) == (Gcs, QGC) && said(m)),
        "{texts:?}"
    );
    // A heartbeat ends the loss; the next silence fires again.
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(13.1, 11.1);
    b.at(23.2, 21.2);
    assert_eq!(b.asks().len(), 1);
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
    let mut count = 0;
    for k in 1..=200 {
        let wall_s = f64::from(k) * 0.005;
        b.at(wall_s, wall_s * 0.5);
        count += named(&b.out(), "ATTITUDE").iter().filter(|(l, ..)| *l == Gcs).count();
    }
    assert!((7..=9).contains(&count), "{count} ATTITUDE in 0.5 simulated seconds");
}

#[test]
fn the_offboard_stream_is_alive_for_the_commander_until_com_of_loss_t_of_wall_time_silence() {
    let mut b = Bench::new();
    let setpoint = || {
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            target_system: 1,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            z: -3.0,
            ..Default::default()
        })
    };
    let wall = |alive| VehicleRequest::Commander(Request::OffboardStreamInWallTime { alive });
    b.send(Api, SDK, setpoint());
    let asks: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert!(matches!(
        asks[0],
        VehicleRequest::Commander(Request::OffboardSetpoint { .. })
    ));
    assert_eq!(asks[1], wall(true), "the stream started");
    // Simulated time racing ahead does not matter; wall time does.
    b.at(0.9, 40.0);
    b.send(Api, SDK, setpoint());
    assert_eq!(b.asks().len(), 1, "only the setpoint: the stream is still alive");
    b.at(1.85, 80.0);
    assert!(
        b.asks().is_empty(),
        "0.95 s of wall-time silence is within COM_OF_LOSS_T"
    );
    b.at(1.95, 80.0);
    assert_eq!(
        b.asks().into_iter().map(|a| a.request).collect::<Vec<_>>(),
        vec![wall(false)]
    );
    b.at(5.0, 90.0);
    assert!(b.asks().is_empty(), "said once");
}
