//! Fence and rally plans as ArduCopter takes and stores them, and what its mission shows while
//! flown (docs/ardupilot.md §6), on a vehicle presented as ArduCopter (`mav::link::LinkMachine`
//! in-process, virtual time): MISSION_REQUEST for every plan type, a fence polygon round trip
//! stored without height, a malformed polygon refused with MISSION_ERROR and Copter's warnings,
//! rally points taken under Copter's rule ("Rally points received"), an AMSL rally point refused,
//! the download's `current` flag as Copter sets it, MISSION_CURRENT naming no plan, and the
//! mission's return item shown as AUTO.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{FlightMode, MissionState, Outcome, Request};
use rotorpilot::guidance::{Home, RallyRule};
use rotorpilot::mav::gcs::command_long;
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;

const FENCE: MavMissionType = MavMissionType::MAV_MISSION_TYPE_FENCE;
const RALLY: MavMissionType = MavMissionType::MAV_MISSION_TYPE_RALLY;
const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;
const LAT: i32 = -353_632_610;
const LON: i32 = 1_491_652_300;

fn copter() -> Bench {
    let mut b = Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot));
    b.state.home = Home {
        lat_deg: -35.363_261,
        lon_deg: 149.165_230,
        alt_amsl_m: 584.0,
    };
    b.tick();
    b.out();
    b
}

fn item(seq: u16, command: MavCmd, mission_type: MavMissionType, dlat: i32, param1: f32) -> MISSION_ITEM_INT_DATA {
    MISSION_ITEM_INT_DATA {
        seq,
        command,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        x: LAT + dlat,
        y: LON + i32::from(seq % 2) * 1000,
        z: 15.6,
        param1,
        target_system: 1,
        target_component: 1,
        mission_type,
        ..Default::default()
    }
}

/// Uploads `items` answering each MISSION_REQUEST (ArduCopter never asks with the INT form);
/// the replies after the last item and the vehicle's asks.
fn upload(b: &mut Bench, mission_type: MavMissionType, items: &[MISSION_ITEM_INT_DATA]) -> Vec<MavMessage> {
    let count = MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 1,
        mission_type,
        opaque_id: 0,
    };
    b.send(LinkKind::Gcs, QGC, MavMessage::MISSION_COUNT(count));
    loop {
        let out: Vec<MavMessage> = b.out().into_iter().map(|(_, _, m)| m).collect();
        assert!(
            !out.iter().any(|m| matches!(m, MavMessage::MISSION_REQUEST_INT(_))),
            "{out:?}"
        );
        let next = out.iter().find_map(|m| match m {
            MavMessage::MISSION_REQUEST(r) => Some(r.seq),
            _ => None,
        });
        match next {
            Some(seq) => b.send(
                LinkKind::Gcs,
                QGC,
                MavMessage::MISSION_ITEM_INT(items[usize::from(seq)].clone()),
            ),
            None => return out,
        }
    }
}

/// The vehicle takes what it was asked; the MISSION_ACK result and the texts that follow.
fn take(b: &mut Bench) -> (Option<MavMissionResult>, Vec<String>, Vec<Request>) {
    let asks = b.asks();
    let mut requests = Vec::new();
    for ask in asks {
        let (VehicleRequest::Commander(r), Some(token)) = (&ask.request, ask.token) else {
            continue;
        };
        requests.push(r.clone());
        b.m.handle_reply(b.now, token, VehicleReply::Outcome(Outcome::Accepted));
    }
    let out: Vec<MavMessage> = b.out().into_iter().map(|(_, _, m)| m).collect();
    let (ack, texts) = acked(&out);
    (ack, texts, requests)
}

fn acked(out: &[MavMessage]) -> (Option<MavMissionResult>, Vec<String>) {
    let ack = out.iter().find_map(|m| match m {
        MavMessage::MISSION_ACK(a) => Some(a.mavtype),
        _ => None,
    });
    let texts = out
        .iter()
        .filter_map(|m| match m {
            MavMessage::STATUSTEXT(t) => {
                let end = t.text.iter().position(|&c| c == 0).unwrap_or(t.text.len());
                Some(String::from_utf8_lossy(&t.text[..end]).into_owned())
            }
            _ => None,
        })
        .collect();
    (ack, texts)
}

fn download(b: &mut Bench, mission_type: MavMissionType, seq: u16) -> MISSION_ITEM_DATA {
    let ask = MISSION_REQUEST_DATA {
        seq,
        target_system: 1,
        target_component: 1,
        mission_type,
    };
    b.send(LinkKind::Gcs, QGC, MavMessage::MISSION_REQUEST(ask));
    match b.out().remove(0).2 {
        MavMessage::MISSION_ITEM(m) => m,
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_fence_polygon_round_trips_without_height_and_a_malformed_one_is_refused() {
    let mut b = copter();
    let vertex = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
    let mut items: Vec<_> = (0..4)
        .map(|s| item(s, vertex, FENCE, [-900, 900, 900, -900][usize::from(s)], 4.0))
        .collect();
    items.push(item(4, MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT, FENCE, 0, 0.0));
    upload(&mut b, FENCE, &items);
    let (ack, _, requests) = take(&mut b);
    assert_eq!(ack, Some(MavMissionResult::MAV_MISSION_ACCEPTED));
    let [Request::SetGeofence(fence)] = &requests[..] else {
        panic!("{requests:?}")
    };
    assert_eq!(
        fence.zones.len(),
        1,
        "the polygon; the return point is kept, not a zone"
    );
    let v = download(&mut b, FENCE, 2);
    assert_eq!(
        (v.command, v.param1, v.frame, v.z),
        (vertex, 4.0, MavFrame::MAV_FRAME_GLOBAL, 0.0)
    );
    assert!((f64::from(v.x) - f64::from(LAT + 900) * 1e-7).abs() < 1e-5);

    // Three vertices of a four-vertex polygon: refused once complete, nothing asked.
    let out = upload(&mut b, FENCE, &items[..3]);
    let (ack, texts) = acked(&out);
    assert_eq!(ack, Some(MavMissionResult::MAV_MISSION_ERROR));
    assert_eq!(texts, ["Incorrect item count", "Fence validation failed"]);
    assert!(b.asks().is_empty());
    let short: Vec<_> = (0..2).map(|s| item(s, vertex, FENCE, 0, 2.0)).collect();
    let (ack, texts) = acked(&upload(&mut b, FENCE, &short));
    assert_eq!(
        (ack, texts[0].as_str()),
        (Some(MavMissionResult::MAV_MISSION_ERROR), "Invalid vertex count (2)")
    );
    assert_eq!(download(&mut b, FENCE, 2).param1, 4.0, "the stored fence stays");
}

#[test]
fn rally_points_are_taken_under_copters_rule_and_amsl_ones_refused() {
    let mut b = copter();
    let rally_point = MavCmd::MAV_CMD_NAV_RALLY_POINT;
    let items = [
        item(0, rally_point, RALLY, 1800, 0.0),
        item(1, rally_point, RALLY, -1800, 0.0),
    ];
    upload(&mut b, RALLY, &items);
    let (ack, texts, requests) = take(&mut b);
    assert_eq!(ack, Some(MavMissionResult::MAV_MISSION_ACCEPTED));
    assert_eq!(texts, ["Rally points received"]);
    let [Request::SetRallyPoints(rally)] = &requests[..] else {
        panic!("{requests:?}")
    };
    assert_eq!(rally.rule, RallyRule::COPTER);
    assert!(
        (rally.points_w[0].x - 20.0).abs() < 0.1 && (rally.points_w[0].z + 15.0).abs() < 1e-6,
        "whole metres"
    );
    let back = download(&mut b, RALLY, 1);
    assert_eq!((back.z, back.frame), (15.0, MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT));

    let mut amsl = items[0].clone();
    amsl.frame = MavFrame::MAV_FRAME_GLOBAL_INT;
    let (ack, texts) = acked(&upload(&mut b, RALLY, &[amsl]));
    assert_eq!(ack, Some(MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME));
    assert!(texts.is_empty(), "{texts:?}");
}

#[test]
fn the_current_flag_names_the_command_id_and_the_return_item_shows_auto() {
    let mut b = copter();
    let mut items = vec![item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, MISSION, 0, 0.0)];
    items.push(item(1, MavCmd::MAV_CMD_NAV_TAKEOFF, MISSION, 0, 0.0));
    items.extend((2..17).map(|s| item(s, MavCmd::MAV_CMD_NAV_WAYPOINT, MISSION, i32::from(s) * 100, 0.0)));
    items.push(item(17, MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH, MISSION, 0, 0.0));
    items[17].frame = MavFrame::MAV_FRAME_MISSION;
    upload(&mut b, MISSION, &items);
    take(&mut b);
    // Never started: no item is current.
    assert!((0..18).all(|s| download(&mut b, MISSION, s).current == 0));
    // At seq 16 (the commander's 15): every NAV_WAYPOINT (16) is flagged, home's included.
    let auto = command_long((1, 1), MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    b.send(LinkKind::Gcs, QGC, MavMessage::COMMAND_LONG(auto));
    b.asks();
    b.state.mode = FlightMode::Mission;
    (b.state.mission_seq, b.state.mission_total, b.state.mission_state) = (15, 17, MissionState::Active);
    b.tick();
    b.out();
    let flags: Vec<u8> = (0..18).map(|s| download(&mut b, MISSION, s).current).collect();
    assert_eq!(flags[..3], [1, 0, 1]);
    assert_eq!(flags[17], 0, "the return item (20)");
    // MISSION_CURRENT names no plan (ArduCopter 4.5).
    b.send(LinkKind::Gcs, QGC, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 42.0));
    let current = b.out().into_iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_CURRENT(c) => Some(c),
        _ => None,
    });
    let current = current.expect("MISSION_CURRENT");
    assert_eq!((current.seq, current.mission_id, current.fence_id), (16, 0, 0));
    // The return item flown: the commander returns, the HEARTBEAT still says AUTO.
    b.state.mode = FlightMode::ReturnToLaunch;
    (b.state.mission_seq, b.state.mission_state) = (16, MissionState::Complete);
    b.at(5.0, 5.0);
    let modes = custom_modes(&b.out());
    assert!(!modes.is_empty() && modes.iter().all(|m| *m == 3), "{modes:?}");
    // An RTL asked for shows RTL.
    let rtl = command_long((1, 1), MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 6.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    b.send(LinkKind::Gcs, QGC, MavMessage::COMMAND_LONG(rtl));
    b.asks();
    b.at(7.0, 7.0);
    let out = b.out();
    assert!(named(&out, "HEARTBEAT")
        .iter()
        .all(|(_, _, m)| matches!(m, MavMessage::HEARTBEAT(hb) if hb.custom_mode == 6)));
}
