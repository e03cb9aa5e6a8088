//! The mission protocol as ArduCopter runs it (docs/ardupilot.md §6), on a vehicle presented as
//! ArduCopter (`mav::link::LinkMachine` in-process, virtual time): DroneKit's upload
//! (MISSION_REQUEST asked, MISSION_ITEM answered, "Flight plan received"), the commander flying
//! items 1.., downloads with home in slot 0 in the form asked for, seqs reported from 1, AUTO's
//! take-off rule and AUTO kept at the mission's end; PX4's face unchanged.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::MissionState as MavMissionState;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{Event, FlightMode, MissionState, Outcome, Request};
use rotorpilot::guidance::{Home, MissionItem};
use rotorpilot::mav::gcs::{command_long, gcs_header};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;

const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

/// ArduPilot SITL's home (CMAC), away from PX4's default, so that home can be told apart.
fn cmac() -> Home {
    Home {
        lat_deg: -35.363_261,
        lon_deg: 149.165_230,
        alt_amsl_m: 584.0,
    }
}

/// A vehicle presented as ArduCopter, its home at CMAC.
fn copter() -> Bench {
    let mut b = Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot));
    b.state.home = cmac();
    b.tick();
    b.out();
    b
}

/// A MISSION_ITEM as DroneKit's `Command` sends it: `north_m` north of CMAC, `z` in `frame`.
fn dronekit_item(seq: u16, command: MavCmd, frame: MavFrame, north_m: f64, z: f32) -> MISSION_ITEM_DATA {
    let home = cmac();
    MISSION_ITEM_DATA {
        x: (home.lat_deg + north_m / 111_195.0) as f32,
        y: home.lon_deg as f32,
        z,
        seq,
        command,
        target_system: 1,
        target_component: 0,
        frame,
        autocontinue: 1,
        ..Default::default()
    }
}

/// DroneKit's mission: its copy of home (slot 0), a take-off to 10 m, three waypoints, RTL.
fn dronekit_mission() -> Vec<MISSION_ITEM_DATA> {
    let rel = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT;
    let wp = MavCmd::MAV_CMD_NAV_WAYPOINT;
    vec![
        dronekit_item(0, wp, MavFrame::MAV_FRAME_GLOBAL, 0.0, 584.0),
        dronekit_item(1, MavCmd::MAV_CMD_NAV_TAKEOFF, rel, 0.0, 10.0),
        dronekit_item(2, wp, rel, 20.0, 10.0),
        dronekit_item(3, wp, rel, 40.0, 15.0),
        dronekit_item(4, wp, rel, 60.0, 10.0),
        dronekit_item(
            5,
            MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH,
            MavFrame::MAV_FRAME_MISSION,
            0.0,
            0.0,
        ),
    ]
}

fn text_of(m: &MavMessage) -> Option<(MavSeverity, String)> {
    match m {
        MavMessage::STATUSTEXT(t) => {
            let end = t.text.iter().position(|&b| b == 0).unwrap_or(t.text.len());
            Some((t.severity, String::from_utf8_lossy(&t.text[..end]).into_owned()))
        }
        _ => None,
    }
}

/// DroneKit's `commands.upload()` of `items`: MISSION_CLEAR_ALL, MISSION_COUNT, then each
/// MISSION_REQUEST answered with MISSION_ITEM (DroneKit listens for nothing else). Returns the
/// requests' (seq, target) and the mission the commander was asked to fly; the vehicle takes it.
fn dronekit_upload(b: &mut Bench, items: &[MISSION_ITEM_DATA]) -> (Vec<(u16, u8, u8)>, Vec<MissionItem>) {
    let clear = MISSION_CLEAR_ALL_DATA {
        target_system: 1,
        target_component: 0,
        mission_type: MISSION,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_CLEAR_ALL(clear));
    let cleared = b.out().into_iter().any(
        |(_, _, m)| matches!(m, MavMessage::MISSION_ACK(a) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED),
    );
    assert!(cleared);
    b.asks();
    let count = MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 0,
        mission_type: MISSION,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    let mut requests = Vec::new();
    loop {
        let out = b.out();
        assert!(
            !out.iter()
                .any(|(_, _, m)| matches!(m, MavMessage::MISSION_REQUEST_INT(_))),
            "ArduCopter never asks with MISSION_REQUEST_INT: {out:?}"
        );
        let next = out.iter().find_map(|(_, _, m)| match m {
            MavMessage::MISSION_REQUEST(r) => Some(r.clone()),
            _ => None,
        });
        let Some(r) = next else { break };
        assert_eq!(r.mission_type, MISSION);
        requests.push((r.seq, r.target_system, r.target_component));
        b.send(Gcs, QGC, MavMessage::MISSION_ITEM(items[usize::from(r.seq)].clone()));
    }
    let asks = b.asks();
    let [ask] = &asks[..] else { panic!("{asks:?}") };
    let VehicleRequest::Commander(Request::SetMission(mission)) = &ask.request else {
        panic!("{ask:?}")
    };
    let flown = mission.items.clone();
    b.m.handle_reply(b.now, ask.token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
    (requests, flown)
}

/// Asks for every item of the mission, with MISSION_REQUEST_INT (`int_form`) or MISSION_REQUEST;
/// returns the count and the replies.
fn download(b: &mut Bench, int_form: bool) -> (u16, Vec<MavMessage>) {
    let list = MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 0,
        mission_type: MISSION,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_REQUEST_LIST(list));
    let count = b.out().into_iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_COUNT(c) => Some(c.count),
        _ => None,
    });
    let count = count.expect("MISSION_COUNT");
    let replies = (0..count)
        .map(|seq| {
            let ask = if int_form {
                MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
                    seq,
                    target_system: 1,
                    target_component: 0,
                    mission_type: MISSION,
                })
            } else {
                MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
                    seq,
                    target_system: 1,
                    target_component: 0,
                    mission_type: MISSION,
                })
            };
            b.send(Gcs, QGC, ask);
            let mut out = b.out();
            assert_eq!(out.len(), 1, "{out:?}");
            out.remove(0).2
        })
        .collect();
    (count, replies)
}

#[test]
fn dronekit_uploads_with_mission_item_and_the_commander_flies_items_1_on() {
    let mut b = copter();
    let items = dronekit_mission();
    let (requests, flown) = dronekit_upload(&mut b, &items);
    let header = gcs_header(0);
    let expected: Vec<(u16, u8, u8)> = (0..6)
        .map(|seq| (seq, header.system_id as u8, header.component_id))
        .collect();
    assert_eq!(
        requests, expected,
        "each item asked for once, from whoever sent the count"
    );
    assert_eq!(flown.len(), 5, "items 1..5");
    assert!(matches!(flown[0], MissionItem::Takeoff { height_m } if (height_m - 10.0).abs() < 1e-6));
    let MissionItem::Waypoint { pos_w, .. } = flown[1] else {
        panic!("{:?}", flown[1])
    };
    // MISSION_ITEM's float degrees hold a position to a metre or so (f32 at 149°: 1.5e-5°).
    assert!(
        (pos_w.x - 20.0).abs() < 1.0 && pos_w.y.abs() < 1.0 && (pos_w.z + 10.0).abs() < 1e-3,
        "{pos_w:?}"
    );
    assert_eq!(flown[4], MissionItem::ReturnToLaunch);
    // Stored once taken: "Flight plan received", then MISSION_ACK ACCEPTED.
    let out = b.out();
    let said: Vec<_> = out.iter().filter_map(|(_, _, m)| text_of(m)).collect();
    assert_eq!(
        said,
        vec![(MavSeverity::MAV_SEVERITY_INFO, "Flight plan received".to_string())]
    );
    let text_at = out.iter().position(|(_, _, m)| text_of(m).is_some()).unwrap();
    let ack_at = out
        .iter()
        .position(|(_, _, m)| {
            matches!(m, MavMessage::MISSION_ACK(a) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED && a.mission_type == MISSION)
        })
        .expect("MISSION_ACK ACCEPTED");
    assert!(text_at < ack_at, "the text first");
    assert_eq!(b.m.stored_mission().len(), 6, "the home slot is stored too");
    assert_eq!(b.m.stored_mission()[2].x, (f64::from(items[2].x) * 1e7).round() as i32);
}

#[test]
fn a_lost_item_is_asked_for_again_after_a_second_with_mission_request() {
    let mut b = copter();
    let count = MISSION_COUNT_DATA {
        count: 2,
        target_system: 1,
        target_component: 0,
        mission_type: MISSION,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    assert_eq!(named(&b.out(), "MISSION_REQUEST").len(), 1);
    // DroneKit's answer is lost: asked again after 1 s, not before.
    let asked = b.count_sent("MISSION_REQUEST", Gcs, (1..=15).map(|k| (f64::from(k) * 0.1, 0.0)));
    assert_eq!(asked, 1);
    assert_eq!(b.count_sent("MISSION_REQUEST_INT", Gcs, [(2.0, 0.0)]), 0);
}

#[test]
fn downloads_give_home_in_slot_0_in_the_form_asked_for() {
    let mut b = copter();
    // Nothing uploaded: home alone.
    let (count, replies) = download(&mut b, false);
    assert_eq!(count, 1);
    let MavMessage::MISSION_ITEM(home) = &replies[0] else {
        panic!("{replies:?}")
    };
    assert_eq!(
        (home.seq, home.command, home.frame),
        (0, MavCmd::MAV_CMD_NAV_WAYPOINT, MavFrame::MAV_FRAME_GLOBAL)
    );
    let at = cmac();
    assert_eq!((home.x, home.y, home.z), (at.lat_deg as f32, at.lon_deg as f32, 584.0));
    let items = dronekit_mission();
    dronekit_upload(&mut b, &items);
    b.out();
    // The home slot follows the vehicle's home, whatever was uploaded there.
    b.state.home.alt_amsl_m = 590.0;
    b.tick();
    b.out();
    // DroneKit's `commands.download()`: MISSION_REQUEST, MISSION_ITEMs.
    let (count, replies) = download(&mut b, false);
    assert_eq!(count, 6, "the home slot and five items");
    let got: Vec<MISSION_ITEM_DATA> = replies
        .iter()
        .map(|m| match m {
            MavMessage::MISSION_ITEM(i) => i.clone(),
            other => panic!("DroneKit accepts only MISSION_ITEM: {other:?}"),
        })
        .collect();
    assert_eq!((got[0].frame, got[0].z), (MavFrame::MAV_FRAME_GLOBAL, 590.0));
    for (back, sent) in got.iter().zip(&items).skip(1) {
        let key = |i: &MISSION_ITEM_DATA| (i.seq, i.command, i.frame, i.x, i.y, i.z);
        assert_eq!(key(back), key(sent));
        assert_eq!(
            (back.target_system, back.target_component),
            (255, gcs_header(0).component_id)
        );
    }
    // MAVProxy and QGroundControl: MISSION_REQUEST_INT, MISSION_ITEM_INTs.
    let (count, replies) = download(&mut b, true);
    assert_eq!(count, 6);
    let MavMessage::MISSION_ITEM_INT(home) = &replies[0] else {
        panic!("{replies:?}")
    };
    assert_eq!((home.x, home.y, home.z), (-353_632_610, 1_491_652_300, 590.0));
    let MavMessage::MISSION_ITEM_INT(takeoff) = &replies[1] else {
        panic!("{replies:?}")
    };
    assert_eq!(
        (takeoff.seq, takeoff.command, takeoff.z),
        (1, MavCmd::MAV_CMD_NAV_TAKEOFF, 10.0)
    );
    assert!(replies.iter().all(|m| matches!(m, MavMessage::MISSION_ITEM_INT(_))));
}

/// The seq of the MISSION_CURRENT and MISSION_ITEM_REACHED in `out`.
fn seqs(out: &[(LinkKind, u16, MavMessage)]) -> (Option<u16>, Option<u16>) {
    let current = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_CURRENT(c) => Some(c.seq),
        _ => None,
    });
    let reached = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_ITEM_REACHED(r) => Some(r.seq),
        _ => None,
    });
    (current, reached)
}

#[test]
fn reported_seqs_count_the_home_slot() {
    let mut b = copter();
    dronekit_upload(&mut b, &dronekit_mission());
    b.state.mode = FlightMode::Mission;
    b.state.mission_seq = 2;
    b.state.mission_total = 5;
    b.state.mission_state = MissionState::Active;
    b.tick();
    b.out();
    let ask = command_long(
        (1, 1),
        MavCmd::MAV_CMD_REQUEST_MESSAGE,
        [42.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    );
    b.send(Gcs, QGC, MavMessage::COMMAND_LONG(ask));
    let out = b.out();
    assert_eq!(seqs(&out), (Some(3), None), "the commander's item 2 is seq 3");
    let MavMessage::MISSION_CURRENT(c) = &named(&out, "MISSION_CURRENT")[0].2 else {
        unreachable!()
    };
    assert_eq!(
        (c.total, c.mission_state, c.mission_mode),
        (5, MavMissionState::MISSION_STATE_ACTIVE, 1)
    );
    b.m.handle_event(b.now, Event::MissionItemReached(1));
    assert_eq!(seqs(&b.out()), (None, Some(2)));
    b.m.handle_event(b.now, Event::MissionCurrent(3));
    assert_eq!(seqs(&b.out()), (Some(4), None));
    // MISSION_SET_CURRENT 4 is the commander's item 3.
    let set = MISSION_SET_CURRENT_DATA {
        seq: 4,
        target_system: 1,
        target_component: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_SET_CURRENT(set));
    let asks: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert_eq!(
        asks,
        vec![VehicleRequest::Commander(Request::SetMissionCurrent {
            seq: Some(3),
            reset: false
        })]
    );
}

#[test]
fn auto_on_the_ground_needs_a_takeoff_and_stays_auto_at_the_missions_end() {
    let mut b = copter();
    let mut items = dronekit_mission();
    items.remove(1);
    for (k, item) in items.iter_mut().enumerate() {
        item.seq = k as u16;
    }
    dronekit_upload(&mut b, &items);
    b.out();
    b.state.armed = true;
    b.tick();
    b.out();
    let auto = command_long((1, 1), MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    b.send(Gcs, QGC, MavMessage::COMMAND_LONG(auto));
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_FAILED]);
    let said: Vec<_> = out.iter().filter_map(|(_, _, m)| text_of(m)).collect();
    assert_eq!(
        said,
        vec![(
            MavSeverity::MAV_SEVERITY_CRITICAL,
            "Auto: Missing Takeoff Cmd".to_string()
        )]
    );
    assert!(b.asks().is_empty(), "the commander is not asked");
    // With the take-off first, AUTO is asked of the commander.
    dronekit_upload(&mut b, &dronekit_mission());
    b.out();
    let auto = command_long((1, 1), MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 3.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    b.send(Gcs, QGC, MavMessage::COMMAND_LONG(auto));
    let asks: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert_eq!(
        asks,
        vec![VehicleRequest::Commander(Request::SelectMode(FlightMode::Mission))]
    );
    // The mission flown to its end: the commander holds, the HEARTBEAT still says AUTO.
    b.state.mode = FlightMode::Loiter;
    b.state.mission_state = MissionState::Complete;
    b.at(5.0, 5.0);
    let modes = custom_modes(&b.out());
    assert!(!modes.is_empty() && modes.iter().all(|m| *m == 3), "{modes:?}");
}

#[test]
fn px4_keeps_its_own_mission_protocol() {
    let mut b = Bench::new();
    let count = MISSION_COUNT_DATA {
        count: 1,
        target_system: 1,
        target_component: 1,
        mission_type: MISSION,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    let out = b.out();
    assert_eq!(
        (
            named(&out, "MISSION_REQUEST_INT").len(),
            named(&out, "MISSION_REQUEST").len()
        ),
        (1, 0)
    );
    // A MISSION_ITEM is no upload item for PX4.
    let item = MISSION_ITEM_DATA {
        target_system: 1,
        target_component: 1,
        ..dronekit_item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, MavFrame::MAV_FRAME_GLOBAL, 0.0, 0.0)
    };
    b.send(Gcs, QGC, MavMessage::MISSION_ITEM(item));
    assert!(b.asks().is_empty());
    b.at(10.0, 10.0);
    b.out();
    // No home slot; MISSION_REQUEST answered with MISSION_ITEM_INT.
    let list = MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
        mission_type: MISSION,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_REQUEST_LIST(list));
    assert!(b
        .out()
        .iter()
        .any(|(_, _, m)| matches!(m, MavMessage::MISSION_COUNT(c) if c.count == 0)));
    b.send(Gcs, QGC, request_item_0());
    assert!(matches!(
        &b.out()[..],
        [(_, _, MavMessage::MISSION_ACK(a))] if a.mavtype == MavMissionResult::MAV_MISSION_INVALID_SEQUENCE
    ));
    b.m.handle_event(b.now, Event::MissionItemReached(1));
    assert_eq!(seqs(&b.out()), (None, Some(1)), "PX4 reports the commander's numbers");
}

/// MISSION_REQUEST of item 0 for 1/1.
fn request_item_0() -> MavMessage {
    MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
        seq: 0,
        target_system: 1,
        target_component: 1,
        mission_type: MISSION,
    })
}
