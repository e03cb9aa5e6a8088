//! The plan ids as PX4 gives them (`mav::link::LinkMachine` in-process, with virtual time): each
//! plan's id is a CRC-32 (reflected 0xEDB88320, from 0, no final inversion) chained over its items'
//! packed 32-byte structs; it comes back as `opaque_id` in the upload's final MISSION_ACK and in
//! the MISSION_COUNT of a download, and MISSION_CURRENT names all three (`mission_id`,
//! `fence_id`, `rally_points_id`), 0 for no plan, with PX4's mission mode and state.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{Event, FlightMode, MissionState as Progress, Outcome};
use rotorpilot::guidance::Home;
use rotorpilot::mav::link::VehicleReply;

const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;
const FENCE: MavMissionType = MavMissionType::MAV_MISSION_TYPE_FENCE;
const RALLY: MavMissionType = MavMissionType::MAV_MISSION_TYPE_RALLY;

/// The CRC of the definition, bit by bit, continued from `crc`.
fn crc(data: &[u8], mut crc: u32) -> u32 {
    for b in data {
        crc ^= u32::from(*b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    crc
}

/// PX4's id of `items`: the CRC over frame, command, autocontinue, param1..4, x, y, z packed
/// little-endian, item after item from 0.
fn expected_id(items: &[MISSION_ITEM_INT_DATA]) -> u32 {
    items.iter().fold(0, |state, i| {
        let mut b = vec![i.frame as u8];
        b.extend((i.command as u16).to_le_bytes());
        b.push(i.autocontinue);
        for f in [i.param1, i.param2, i.param3, i.param4] {
            b.extend(f.to_le_bytes());
        }
        b.extend(i.x.to_le_bytes());
        b.extend(i.y.to_le_bytes());
        b.extend(i.z.to_le_bytes());
        crc(&b, state)
    })
}

/// An item of plan `mission_type` (`dlat` [1e-7°] north of home), `alt` [m] above home.
fn item(mission_type: MavMissionType, seq: u16, command: MavCmd, dlat: i32, alt: f32) -> MISSION_ITEM_INT_DATA {
    let home = Home::default();
    MISSION_ITEM_INT_DATA {
        seq,
        command,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        x: (home.lat_deg * 1e7) as i32 + dlat,
        y: (home.lon_deg * 1e7) as i32,
        z: alt,
        autocontinue: 1,
        target_system: 1,
        target_component: 1,
        mission_type,
        ..Default::default()
    }
}

/// Uploads `items` of plan `mission_type`, the vehicle taking it; the final MISSION_ACK's
/// (result, opaque_id).
fn upload(b: &mut Bench, mission_type: MavMissionType, items: &[MISSION_ITEM_INT_DATA]) -> (MavMissionResult, u32) {
    let count = MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 1,
        mission_type,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    loop {
        let out = b.out();
        if let Some(a) = out.iter().find_map(|(_, _, m)| match m {
            MavMessage::MISSION_ACK(a) => Some(a.clone()),
            _ => None,
        }) {
            return (a.mavtype, a.opaque_id);
        }
        let asked = out.iter().find_map(|(_, _, m)| match m {
            MavMessage::MISSION_REQUEST_INT(r) => Some(r.seq),
            _ => None,
        });
        match asked {
            Some(seq) => b.send(Gcs, QGC, MavMessage::MISSION_ITEM_INT(items[usize::from(seq)].clone())),
            None => {
                for ask in b.asks() {
                    let now = b.now;
                    b.m.handle_reply(now, ask.token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
                }
            }
        }
    }
}

/// The MISSION_COUNT a download of plan `mission_type` starts with: (count, opaque_id).
fn download_count(b: &mut Bench, mission_type: MavMissionType) -> (u16, u32) {
    let list = MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
        mission_type,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_REQUEST_LIST(list));
    let out = b.out();
    let count = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_COUNT(c) => Some((c.count, c.opaque_id)),
        _ => None,
    });
    count.unwrap()
}

/// MISSION_CURRENT, asked for with REQUEST_MESSAGE.
fn mission_current(b: &mut Bench) -> MISSION_CURRENT_DATA {
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 42.0));
    let out = b.out();
    let m = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_CURRENT(m) => Some(m.clone()),
        _ => None,
    });
    m.unwrap()
}

#[test]
fn each_plan_is_named_by_px4s_crc_in_the_ack_the_count_and_mission_current() {
    let mut b = Bench::new();
    let none = mission_current(&mut b);
    assert_eq!((none.mission_id, none.fence_id, none.rally_points_id), (0, 0, 0));
    assert_eq!(
        (none.total, none.mission_state, none.mission_mode),
        (u16::MAX, MissionState::MISSION_STATE_NO_MISSION, 2)
    );

    let wp = MavCmd::MAV_CMD_NAV_WAYPOINT;
    let mission = [item(MISSION, 0, wp, 900, 10.0), item(MISSION, 1, wp, 1800, 12.5)];
    let rally = [item(RALLY, 0, MavCmd::MAV_CMD_NAV_RALLY_POINT, -4500, 0.0)];
    let circle = MISSION_ITEM_INT_DATA {
        param1: 50.0,
        ..item(FENCE, 0, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 0.0)
    };
    let ids = [
        expected_id(&mission),
        expected_id(std::slice::from_ref(&circle)),
        expected_id(&rally),
    ];
    assert!(ids.iter().all(|id| *id != 0) && ids[0] != ids[1]);
    let accepted = MavMissionResult::MAV_MISSION_ACCEPTED;
    assert_eq!(upload(&mut b, MISSION, &mission), (accepted, ids[0]));
    assert_eq!(upload(&mut b, FENCE, &[circle]), (accepted, ids[1]));
    assert_eq!(upload(&mut b, RALLY, &rally), (accepted, ids[2]));
    assert_eq!(download_count(&mut b, MISSION), (2, ids[0]));
    assert_eq!(download_count(&mut b, FENCE), (1, ids[1]));
    assert_eq!(download_count(&mut b, RALLY), (1, ids[2]));
    let m = mission_current(&mut b);
    assert_eq!([m.mission_id, m.fence_id, m.rally_points_id], ids);

    // Cleared, a plan's id is 0 again (the ACK of a clear carries none).
    b.send(
        Gcs,
        QGC,
        MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
            target_system: 1,
            target_component: 1,
            mission_type: FENCE,
        }),
    );
    let out = b.out();
    assert!(out
        .iter()
        .any(|(_, _, m)| matches!(m, MavMessage::MISSION_ACK(a) if a.mission_type == FENCE && a.opaque_id == 0)));
    b.tick();
    let m = mission_current(&mut b);
    assert_eq!([m.mission_id, m.fence_id, m.rally_points_id], [ids[0], 0, ids[2]]);
    assert_eq!(download_count(&mut b, FENCE), (0, 0));
}

#[test]
fn mission_current_follows_px4s_mission_mode_and_state() {
    let mut b = Bench::new();
    let state_of = |b: &mut Bench, mode, seq, progress| {
        b.state.mode = mode;
        b.state.mission_seq = seq;
        b.state.mission_total = 2;
        b.state.mission_state = progress;
        b.tick();
        let m = mission_current(b);
        (m.mission_state, m.mission_mode, m.total)
    };
    use MissionState::*;
    assert_eq!(
        state_of(&mut b, FlightMode::Loiter, 0, Progress::NotStarted),
        (MISSION_STATE_NOT_STARTED, 2, 2)
    );
    assert_eq!(
        state_of(&mut b, FlightMode::Mission, 0, Progress::Active),
        (MISSION_STATE_ACTIVE, 1, 2)
    );
    // The announcement of a new current item carries the same state.
    let now = b.now;
    b.m.handle_event(now, Event::MissionItemReached(0));
    b.m.handle_event(now, Event::MissionCurrent(1));
    let out = b.out();
    let announced = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_CURRENT(m) => Some((m.seq, m.mission_state, m.mission_mode)),
        _ => None,
    });
    assert_eq!(announced, Some((1, MISSION_STATE_ACTIVE, 1)));
    assert_eq!(
        state_of(&mut b, FlightMode::Loiter, 1, Progress::Paused),
        (MISSION_STATE_PAUSED, 2, 2)
    );
    assert_eq!(
        state_of(&mut b, FlightMode::Loiter, 1, Progress::Complete),
        (MISSION_STATE_COMPLETE, 2, 2)
    );
}
