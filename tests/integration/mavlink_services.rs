//! Requests over UDP on ephemeral ports that a ground station repeats or qualifies: information
//! requests are answered every time (not from the duplicate-command cache), and every mission
//! protocol reply carries the mission type of the request it answers.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::support;

use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavMessage, MavMissionResult, MavMissionType, MavResult, MISSION_CLEAR_ALL_DATA, MISSION_COUNT_DATA,
    MISSION_REQUEST_LIST_DATA,
};
use support::Autopilot;

/// The first autopilot HEARTBEAT within 3 s (the link is up).
fn connected(v: &Autopilot) -> bool {
    v.wait(Duration::from_secs(3), |h, m| {
        (h.component_id == 1 && matches!(m, MavMessage::HEARTBEAT(_))).then_some(())
    })
    .is_some()
}

fn command_long(command: MavCmd, param1: f32) -> MavMessage {
    let params = [param1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    MavMessage::COMMAND_LONG(rotorpilot::mav::gcs::command_long((1, 1), command, params))
}

/// What [`count_answers`] counts.
enum Answer {
    Ack(MavResult),
    Version,
}

/// (COMMAND_ACKs ACCEPTED for `command`, AUTOPILOT_VERSIONs) received within `timeout`, stopping
/// early once `wanted` of each arrived.
fn count_answers(v: &Autopilot, command: MavCmd, wanted: usize, timeout: Duration) -> (usize, usize) {
    let (mut acks, mut versions) = (0, 0);
    let end = Instant::now() + timeout;
    while acks < wanted || versions < wanted {
        let got = v.wait(end.saturating_duration_since(Instant::now()), |_, m| match m {
            MavMessage::COMMAND_ACK(a) if a.command == command => Some(Answer::Ack(a.result)),
            MavMessage::AUTOPILOT_VERSION(_) => Some(Answer::Version),
            _ => None,
        });
        match got {
            Some(Answer::Ack(MavResult::MAV_RESULT_ACCEPTED)) => acks += 1,
            Some(Answer::Ack(_)) => {}
            Some(Answer::Version) => versions += 1,
            None => break,
        }
    }
    (acks, versions)
}

#[test]
fn a_repeated_request_message_is_answered_every_time() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(connected(&v));
    // MAVSDK asks for AUTOPILOT_VERSION twice, 0.5 s apart, with the same parameters: within the
    // 3 s duplicate window, but each ask gets the ACK and the message.
    v.send(&command_long(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0));
    std::thread::sleep(Duration::from_millis(400));
    v.send(&command_long(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0));
    assert_eq!(
        count_answers(&v, MavCmd::MAV_CMD_REQUEST_MESSAGE, 2, Duration::from_secs(2)),
        (2, 2),
        "two ACCEPTED ACKs and two AUTOPILOT_VERSIONs"
    );
    // The older dedicated request, twice back to back.
    #[allow(deprecated)]
    let capabilities = MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES;
    v.send(&command_long(capabilities, 1.0));
    v.send(&command_long(capabilities, 1.0));
    assert_eq!(count_answers(&v, capabilities, 2, Duration::from_secs(2)), (2, 2));
}

/// (mission_type, result) of the next MISSION_ACK, or (mission_type, count) of a MISSION_COUNT
/// when `count` is set, within 1 s.
fn mission_reply(v: &Autopilot, count: bool) -> Option<(MavMissionType, u32)> {
    v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::MISSION_ACK(a) if !count => Some((a.mission_type, a.mavtype as u32)),
        MavMessage::MISSION_COUNT(c) if count => Some((c.mission_type, u32::from(c.count))),
        _ => None,
    })
}

#[test]
fn mission_replies_carry_the_mission_type_of_the_request() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(connected(&v));
    let fence = MavMissionType::MAV_MISSION_TYPE_FENCE;
    let rally = MavMissionType::MAV_MISSION_TYPE_RALLY;
    let accepted = MavMissionResult::MAV_MISSION_ACCEPTED as u32;

    // A fence upload asks for the fence's first item.
    v.send(&MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: 4,
        target_system: 1,
        target_component: 1,
        mission_type: fence,
        opaque_id: 0,
    }));
    let first = v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::MISSION_REQUEST_INT(r) => Some((r.mission_type, r.seq)),
        _ => None,
    });
    assert_eq!(first, Some((fence, 0)));

    // A rally download is an empty rally plan.
    v.send(&MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
        mission_type: rally,
    }));
    assert_eq!(mission_reply(&v, true), Some((rally, 0)));

    // Clearing the fence (which ends its upload) is accepted as a fence, the mission as a mission.
    let clear = |mission_type| {
        MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
            target_system: 1,
            target_component: 1,
            mission_type,
        })
    };
    v.send(&clear(fence));
    assert_eq!(mission_reply(&v, false), Some((fence, accepted)));
    v.send(&clear(MavMissionType::MAV_MISSION_TYPE_MISSION));
    assert_eq!(
        mission_reply(&v, false),
        Some((MavMissionType::MAV_MISSION_TYPE_MISSION, accepted))
    );
}
