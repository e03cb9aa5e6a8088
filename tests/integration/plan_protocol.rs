//! The fence and rally plans over the mission protocol (`mav::link::LinkMachine` in-process, with
//! virtual time): a QGC-style upload reaches the commander as zones or rally points and is stored
//! once the vehicle took it, a refused upload leaves the stored plan as it was, downloads give the
//! items back, and MISSION_CLEAR_ALL clears one plan or all three.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{Outcome, Request};
use rotorpilot::guidance::Home;
use rotorpilot::mav::link::{ToVehicle, VehicleReply, VehicleRequest};

const FENCE: MavMissionType = MavMissionType::MAV_MISSION_TYPE_FENCE;
const RALLY: MavMissionType = MavMissionType::MAV_MISSION_TYPE_RALLY;
const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

/// An item of plan `mission_type` at (`dlat`, `dlon`) [1e-7°] from home in MAV_FRAME_GLOBAL.
fn item(
    mission_type: MavMissionType,
    seq: u16,
    command: MavCmd,
    dlat: i32,
    dlon: i32,
    p1: f32,
) -> MISSION_ITEM_INT_DATA {
    let home = Home::default();
    MISSION_ITEM_INT_DATA {
        seq,
        command,
        frame: MavFrame::MAV_FRAME_GLOBAL,
        x: (home.lat_deg * 1e7) as i32 + dlat,
        y: (home.lon_deg * 1e7) as i32 + dlon,
        param1: p1,
        target_system: 1,
        target_component: 1,
        mission_type,
        ..Default::default()
    }
}

/// QGC's fence: a 4-vertex inclusion polygon (±20 m) then an exclusion circle of 3 m.
fn qgc_fence() -> Vec<MISSION_ITEM_INT_DATA> {
    let incl = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
    let corners = [(-1800, -2700), (1800, -2700), (1800, 2700), (-1800, 2700)];
    let mut items: Vec<_> = (0u16..)
        .zip(corners)
        .map(|(k, (a, b))| item(FENCE, k, incl, a, b, 4.0))
        .collect();
    items.push(item(FENCE, 4, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION, 900, 0, 3.0));
    items
}

/// Uploads `items` of plan `mission_type` as a ground station does, answering every request;
/// returns the requests the vehicle got and the MISSION_ACKs sent meanwhile.
fn upload(b: &mut Bench, mission_type: MavMissionType, items: &[MISSION_ITEM_INT_DATA]) -> (Vec<ToVehicle>, Vec<Ack>) {
    let count = MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 1,
        mission_type,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    let mut acked = Vec::new();
    loop {
        let out = b.out();
        acked.extend(acks_in(&out));
        let next = out.iter().find_map(|(_, _, m)| match m {
            MavMessage::MISSION_REQUEST_INT(r) => Some(r.clone()),
            _ => None,
        });
        let Some(r) = next else { break };
        assert_eq!(r.mission_type, mission_type, "requests carry the plan's type");
        b.send(
            Gcs,
            QGC,
            MavMessage::MISSION_ITEM_INT(items[usize::from(r.seq)].clone()),
        );
    }
    (b.asks(), acked)
}

/// A MISSION_ACK's (type, result).
type Ack = (MavMissionType, MavMissionResult);

fn acks_in(out: &[(rotorpilot::mav::streams::LinkKind, u16, MavMessage)]) -> Vec<Ack> {
    let acks = out.iter().filter_map(|(_, _, m)| match m {
        MavMessage::MISSION_ACK(a) => Some((a.mission_type, a.mavtype)),
        _ => None,
    });
    acks.collect()
}

/// The MISSION_ACKs sent since the last look.
fn acks(b: &mut Bench) -> Vec<Ack> {
    let out = b.out();
    acks_in(&out)
}

/// Downloads plan `mission_type`.
fn download(b: &mut Bench, mission_type: MavMissionType) -> Vec<MISSION_ITEM_INT_DATA> {
    let list = MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
        mission_type,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_REQUEST_LIST(list));
    let count = b.out().iter().find_map(|(_, _, m)| match m {
        MavMessage::MISSION_COUNT(c) if c.mission_type == mission_type => Some(c.count),
        _ => None,
    });
    (0..count.unwrap())
        .map(|seq| {
            let ask = MISSION_REQUEST_INT_DATA {
                seq,
                target_system: 1,
                target_component: 1,
                mission_type,
            };
            b.send(Gcs, QGC, MavMessage::MISSION_REQUEST_INT(ask));
            let got = b.out().into_iter().find_map(|(_, _, m)| match m {
                MavMessage::MISSION_ITEM_INT(i) => Some(i),
                _ => None,
            });
            got.unwrap()
        })
        .collect()
}

fn took(b: &mut Bench, ask: &ToVehicle) {
    b.m.handle_reply(b.now, ask.token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
}

#[test]
fn a_qgc_fence_reaches_the_commander_and_downloads_back_as_uploaded() {
    let mut b = Bench::new();
    let fence = qgc_fence();
    let (asks, _) = upload(&mut b, FENCE, &fence);
    let VehicleRequest::Commander(Request::SetGeofence(zones)) = &asks[0].request else {
        panic!("{asks:?}")
    };
    assert_eq!(zones.zones.len(), 2);
    assert!(zones.zones[0].inclusion && !zones.zones[1].inclusion);
    assert!(acks(&mut b).is_empty(), "ACKed once the vehicle took it");
    took(&mut b, &asks[0]);
    assert_eq!(acks(&mut b), vec![(FENCE, MavMissionResult::MAV_MISSION_ACCEPTED)]);
    assert_eq!(b.m.stored_plan(FENCE).len(), 5);
    assert!(b.m.stored_mission().is_empty(), "the mission is another plan");
    let back = download(&mut b, FENCE);
    let strip = |i: &MISSION_ITEM_INT_DATA| (i.seq, i.command, i.frame, i.x, i.y, i.param1, i.mission_type);
    assert_eq!(
        back.iter().map(strip).collect::<Vec<_>>(),
        fence.iter().map(strip).collect::<Vec<_>>()
    );
}

#[test]
fn a_refused_fence_upload_leaves_the_stored_fence_and_names_the_item() {
    let mut b = Bench::new();
    let (asks, _) = upload(&mut b, FENCE, &qgc_fence());
    took(&mut b, &asks[0]);
    b.out();
    // A polygon of two vertices: ERROR (as PX4), announced, the stored fence unchanged.
    let incl = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
    let two = [item(FENCE, 0, incl, 0, 0, 2.0), item(FENCE, 1, incl, 100, 0, 2.0)];
    let count = MISSION_COUNT_DATA {
        count: 2,
        target_system: 1,
        target_component: 1,
        mission_type: FENCE,
        opaque_id: 0,
    };
    b.send(Gcs, QGC, MavMessage::MISSION_COUNT(count));
    b.send(Gcs, QGC, MavMessage::MISSION_ITEM_INT(two[0].clone()));
    b.send(Gcs, QGC, MavMessage::MISSION_ITEM_INT(two[1].clone()));
    assert!(b.asks().is_empty(), "nothing for the vehicle");
    let out = b.out();
    let text = out.iter().find_map(|(_, _, m)| match m {
        MavMessage::STATUSTEXT(t) => Some(
            String::from_utf8_lossy(&t.text.to_vec())
                .trim_end_matches('\0')
                .to_string(),
        ),
        _ => None,
    });
    assert_eq!(text.as_deref(), Some("Fence item 0 refused: MAV_MISSION_ERROR"));
    let refused = out.iter().any(|(_, _, m)| {
        matches!(m, MavMessage::MISSION_ACK(a) if a.mission_type == FENCE && a.mavtype == MavMissionResult::MAV_MISSION_ERROR)
    });
    assert!(refused, "{out:?}");
    assert_eq!(b.m.stored_plan(FENCE).len(), 5);
    // A waypoint in a rally plan: UNSUPPORTED.
    let wp = item(RALLY, 0, MavCmd::MAV_CMD_NAV_WAYPOINT, 0, 0, 0.0);
    let (asks, acked) = upload(&mut b, RALLY, &[wp]);
    assert!(asks.is_empty());
    assert_eq!(acked, vec![(RALLY, MavMissionResult::MAV_MISSION_UNSUPPORTED)]);
}

#[test]
fn rally_points_upload_and_clear_all_empties_every_plan() {
    let mut b = Bench::new();
    let point = |seq, dlat| item(RALLY, seq, MavCmd::MAV_CMD_NAV_RALLY_POINT, dlat, 0, 0.0);
    let (asks, _) = upload(&mut b, RALLY, &[point(0, 4500), point(1, -4500)]);
    let VehicleRequest::Commander(Request::SetRallyPoints(rally)) = &asks[0].request else {
        panic!("{asks:?}")
    };
    assert!((rally.points_w[0].x - 50.04).abs() < 0.01 && (rally.points_w[1].x + 50.04).abs() < 0.01);
    took(&mut b, &asks[0]);
    let (asks, _) = upload(&mut b, FENCE, &qgc_fence());
    took(&mut b, &asks[0]);
    assert_eq!(download(&mut b, RALLY).len(), 2);
    // Clearing the rally points leaves the fence.
    let clear = |mission_type| {
        MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
            target_system: 1,
            target_component: 1,
            mission_type,
        })
    };
    b.out();
    b.send(Gcs, QGC, clear(RALLY));
    assert_eq!(acks(&mut b), vec![(RALLY, MavMissionResult::MAV_MISSION_ACCEPTED)]);
    let asks = b.asks();
    assert!(
        matches!(&asks[..], [a] if a.request == VehicleRequest::Commander(Request::SetRallyPoints(Default::default())))
    );
    assert!(b.m.stored_plan(RALLY).is_empty() && b.m.stored_plan(FENCE).len() == 5);
    // MAV_MISSION_TYPE_ALL: mission, fence and rally, each emptied in the commander.
    let all = MavMissionType::MAV_MISSION_TYPE_ALL;
    b.send(Gcs, QGC, clear(all));
    assert_eq!(acks(&mut b), vec![(all, MavMissionResult::MAV_MISSION_ACCEPTED)]);
    let emptied: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert_eq!(
        emptied,
        vec![
            VehicleRequest::Commander(Request::SetMission(Default::default())),
            VehicleRequest::Commander(Request::SetGeofence(Default::default())),
            VehicleRequest::Commander(Request::SetRallyPoints(Default::default())),
        ]
    );
    assert!([MISSION, FENCE, RALLY].iter().all(|t| b.m.stored_plan(*t).is_empty()));
}
