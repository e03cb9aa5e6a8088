use super::*;
use mavlink::dialects::ardupilotmega::MavCmd;

const GCS: Ids = (255, 190);
const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

fn count(n: u16) -> MISSION_COUNT_DATA {
    MISSION_COUNT_DATA {
        count: n,
        target_system: 1,
        target_component: 1,
        mission_type: MISSION,
        opaque_id: 0,
    }
}

fn item(seq: u16) -> MISSION_ITEM_INT_DATA {
    MISSION_ITEM_INT_DATA {
        seq,
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        ..Default::default()
    }
}

fn requested(out: &[(u8, MavMessage)]) -> Option<u16> {
    match out.first() {
        Some((_, MavMessage::MISSION_REQUEST_INT(r))) => Some(r.seq),
        _ => None,
    }
}

#[test]
fn upload_requests_each_item_and_completes() {
    let mut x = MissionTransfer::<u8>::default();
    let (out, _) = x.on_count(7, GCS, &count(3), 0.0);
    assert_eq!(requested(&out), Some(0));
    assert_eq!(requested(&x.on_item(7, &item(0), 0.01).0), Some(1));
    // Out of sequence (1 was lost): re-request 1.
    assert_eq!(requested(&x.on_item(7, &item(2), 0.02).0), Some(1));
    assert_eq!(requested(&x.on_item(7, &item(1), 0.03).0), Some(2));
    let (out, done) = x.on_item(7, &item(2), 0.04);
    assert!(out.is_empty());
    assert!(matches!(done, Some(Completed::Items(MISSION, ref v)) if v.len() == 3));
    // Another peer is denied while the first one's upload is validated.
    let (out, _) = x.on_count(8, (250, 1), &count(1), 0.05);
    assert!(matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mavtype == MavMissionResult::MAV_MISSION_DENIED));
    let out = x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 0xC0FF_EE00);
    assert!(
        matches!(out[0], (7, MavMessage::MISSION_ACK(ref a)) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED && a.target_system == 255 && a.opaque_id == 0xC0FF_EE00)
    );
    assert!(!x.busy());
}

#[test]
fn a_missing_item_is_asked_for_every_250_ms_until_5_s_of_silence() {
    let mut x = MissionTransfer::<u8>::default();
    x.on_count(7, GCS, &count(2), 0.0);
    assert_eq!(x.tick(0.1), (Vec::new(), false));
    // Twenty re-requests 250 ms apart: far more than the five that gave up before.
    let mut asked = 0;
    let mut t = 0.0;
    while t < PROTOCOL_TIMEOUT_S - 0.01 {
        t += 0.01;
        let (out, timed_out) = x.tick(t);
        assert!(!timed_out, "still waiting at {t:.2} s");
        if let Some(seq) = requested(&out) {
            assert_eq!(seq, 0);
            asked += 1;
        }
    }
    assert_eq!(asked, 19, "one request each 250 ms for 5 s");
    assert!(x.busy());
    // Silence for 5 s: dropped without an ACK (PX4 says "Operation timeout").
    assert_eq!(x.tick(PROTOCOL_TIMEOUT_S + 0.01), (Vec::new(), true));
    assert!(!x.busy());
}

#[test]
fn each_word_from_the_client_restarts_the_protocol_timeout() {
    let mut x = MissionTransfer::<u8>::default();
    x.on_count(7, GCS, &count(3), 0.0);
    x.on_item(7, &item(0), 4.0);
    // 4.9 s after the count but 0.9 s after the item: still under way.
    assert!(!x.tick(4.9).1);
    // A duplicate of item 0 is news from the client too, and asks for nothing.
    assert!(x.on_item(7, &item(0), 8.5).0.is_empty());
    assert!(!x.tick(13.0).1);
    assert!(x.tick(13.6).1);
}

#[test]
fn duplicates_are_ignored_and_a_gap_is_asked_for_at_once() {
    let mut x = MissionTransfer::<u8>::default();
    x.on_count(7, GCS, &count(4), 0.0);
    assert_eq!(requested(&x.on_item(7, &item(0), 0.01).0), Some(1));
    // Item 0 again (duplicated on the way, or the request for it was sent twice): nothing.
    assert!(x.on_item(7, &item(0), 0.02).0.is_empty());
    // The count again, once items came: a duplicate, nothing changes.
    assert_eq!(x.on_count(7, GCS, &count(4), 0.03), (Vec::new(), None));
    // Item 2 before 1: 1 was lost, ask for it now.
    assert_eq!(requested(&x.on_item(7, &item(2), 0.04).0), Some(1));
    assert_eq!(requested(&x.on_item(7, &item(1), 0.05).0), Some(2));
    assert_eq!(requested(&x.on_item(7, &item(2), 0.06).0), Some(3));
    let (_, done) = x.on_item(7, &item(3), 0.07);
    assert!(matches!(done, Some(Completed::Items(MISSION, ref v)) if v.len() == 4));
}

#[test]
fn a_count_repeated_before_the_first_item_is_asked_for_again() {
    let mut x = MissionTransfer::<u8>::default();
    assert_eq!(requested(&x.on_count(7, GCS, &count(2), 0.0).0), Some(0));
    // The request was lost and the client sends its count again.
    assert_eq!(requested(&x.on_count(7, GCS, &count(2), 1.5).0), Some(0));
}

#[test]
fn the_last_item_repeated_after_the_final_ack_gets_the_ack_again() {
    let mut x = MissionTransfer::<u8>::default();
    x.on_count(7, GCS, &count(2), 0.0);
    x.on_item(7, &item(0), 0.01);
    // Repeated while the vehicle validates: the ACK is on its way, nothing else.
    let (_, done) = x.on_item(7, &item(1), 0.02);
    assert!(done.is_some());
    assert_eq!(x.on_item(7, &item(1), 0.03), (Vec::new(), None));
    let first = x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 42);
    // The ACK was lost: the client repeats item 1, five times, and gets the same ACK each time.
    for k in 0..5 {
        let (again, done) = x.on_item(7, &item(1), 1.5 * f64::from(k + 1));
        assert_eq!(again, first, "repeat {k}");
        assert_eq!(done, None, "stored once");
    }
    // Only for its client and its last item.
    assert!(x.on_item(8, &item(1), 9.0).0.is_empty());
    assert!(x.on_item(7, &item(0), 9.0).0.is_empty());
    // A refusal is repeated as a refusal.
    x.on_count(7, GCS, &count(1), 10.0);
    x.on_item(7, &item(0), 10.01);
    let refused = x.finish(MavMissionResult::MAV_MISSION_INVALID_SEQUENCE, 0);
    assert_eq!(x.on_item(7, &item(0), 11.0).0, refused);
    // A new upload forgets the old answer.
    x.on_count(7, GCS, &count(3), 12.0);
    assert_eq!(requested(&x.on_item(7, &item(0), 12.1).0), Some(1));
}

#[test]
fn count_zero_and_clear_all_clear_the_plan_of_their_type() {
    let mut x = MissionTransfer::<u8>::default();
    let (_, done) = x.on_count(7, GCS, &count(0), 0.0);
    assert_eq!(done, Some(Completed::Cleared(MISSION)));
    let all = MavMissionType::MAV_MISSION_TYPE_ALL;
    let (out, done) = x.on_clear(7, GCS, all);
    assert_eq!(done, Some(Completed::Cleared(all)));
    assert!(matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mission_type == all));
}

/// The mission_type of a mission-protocol reply and its result or seq.
fn typed(msg: &MavMessage) -> Option<(MavMissionType, u32)> {
    match msg {
        MavMessage::MISSION_ACK(a) => Some((a.mission_type, a.mavtype as u32)),
        MavMessage::MISSION_REQUEST_INT(r) => Some((r.mission_type, u32::from(r.seq))),
        _ => None,
    }
}

#[test]
fn fence_and_rally_uploads_run_as_their_own_type() {
    let fence = MavMissionType::MAV_MISSION_TYPE_FENCE;
    let rally = MavMissionType::MAV_MISSION_TYPE_RALLY;
    let typed_count = |mission_type, n| MISSION_COUNT_DATA {
        mission_type,
        ..count(n)
    };
    let mut x = MissionTransfer::<u8>::default();
    let (out, _) = x.on_count(7, GCS, &typed_count(fence, 2), 0.0);
    assert_eq!(typed(&out[0].1), Some((fence, 0)), "MISSION_REQUEST_INT 0 of the fence");
    // A mission item does not fill a fence upload; a fence item does.
    assert!(x.on_item(7, &item(0), 0.01).0.is_empty());
    let fence_item = |seq| MISSION_ITEM_INT_DATA {
        mission_type: fence,
        ..item(seq)
    };
    assert_eq!(typed(&x.on_item(7, &fence_item(0), 0.02).0[0].1), Some((fence, 1)));
    let (_, done) = x.on_item(7, &fence_item(1), 0.03);
    assert!(matches!(done, Some(Completed::Items(t, ref v)) if t == fence && v.len() == 2));
    let accepted = MavMissionResult::MAV_MISSION_ACCEPTED as u32;
    assert_eq!(
        typed(&x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 1)[0].1),
        Some((fence, accepted))
    );
    // Clearing rally by count 0 is a rally clear.
    let (out, done) = x.on_count(7, GCS, &typed_count(rally, 0), 0.0);
    assert_eq!(typed(&out[0].1), Some((rally, accepted)));
    assert_eq!(done, Some(Completed::Cleared(rally)));
    // A stalled rally upload is asked for as rally.
    x.on_count(7, GCS, &typed_count(rally, 1), 0.0);
    for k in 1..=5 {
        assert_eq!(typed(&x.tick(0.26 * f64::from(k)).0[0].1), Some((rally, 0)));
    }
    assert!(x.tick(10.0).1);
    // Another type (ALL) cannot be uploaded.
    let all = MavMissionType::MAV_MISSION_TYPE_ALL;
    let (out, done) = x.on_count(7, GCS, &typed_count(all, 3), 0.0);
    let unsupported = MavMissionResult::MAV_MISSION_UNSUPPORTED as u32;
    assert_eq!((typed(&out[0].1), done), (Some((all, unsupported)), None));
    assert!(!x.busy());
}

#[test]
#[allow(deprecated)] // MISSION_REQUEST: what ArduCopter asks with
fn arducopter_asks_for_mission_items_with_mission_request_each_second() {
    use crate::mav::identity::Personality;
    let copter_requested = |out: &[(u8, MavMessage)]| match out.first() {
        Some((7, MavMessage::MISSION_REQUEST(r))) => Some((r.seq, r.target_system, r.target_component)),
        _ => None,
    };
    let mut x = MissionTransfer::<u8>::new(Personality::ArduPilot);
    let (out, _) = x.on_count(7, GCS, &count(3), 0.0);
    assert_eq!(copter_requested(&out), Some((0, 255, 190)), "to whoever sent the count");
    assert_eq!(copter_requested(&x.on_item(7, &item(0), 0.1).0), Some((1, 255, 190)));
    // A lost item is asked for again after a second, not 250 ms.
    assert!(x.tick(0.9).0.is_empty());
    assert_eq!(copter_requested(&x.tick(1.1).0), Some((1, 255, 190)));
    assert!(x.tick(1.6).0.is_empty());
    assert_eq!(
        copter_requested(&x.on_item(7, &item(2), 1.7).0),
        Some((1, 255, 190)),
        "a gap"
    );
    assert_eq!(copter_requested(&x.on_item(7, &item(1), 1.8).0), Some((2, 255, 190)));
    let (_, done) = x.on_item(7, &item(2), 1.9);
    assert!(matches!(done, Some(Completed::Items(MISSION, ref v)) if v.len() == 3));
    // A fence upload is asked for alike (ArduCopter's MissionItemProtocol serves every type).
    x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 0);
    let fence = MISSION_COUNT_DATA {
        mission_type: MavMissionType::MAV_MISSION_TYPE_FENCE,
        ..count(1)
    };
    let (out, _) = x.on_count(7, GCS, &fence, 2.0);
    assert!(
        matches!(out[0].1, MavMessage::MISSION_REQUEST(ref r) if r.seq == 0 && r.mission_type == fence.mission_type)
    );
    assert!(x.tick(2.3).0.is_empty(), "a second, not 250 ms");
    assert!(matches!(x.tick(3.1).0[..], [(7, MavMessage::MISSION_REQUEST(_))]));
}
