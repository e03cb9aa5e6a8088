//! The MAVLink protocols of `rotorpilot run` over UDP on ephemeral ports: the mode machine
//! (DO_SET_MODE, SET_MODE, heartbeat), the parameter protocol, the mission protocol and the
//! offboard setpoint-loss failsafe.
#![allow(clippy::unwrap_used, clippy::expect_used)]
// QGC still sends SET_MODE and MAVSDK GLOBAL_RELATIVE_ALT_INT, both deprecated in the dialect.
#![allow(deprecated)]

use crate::support;

use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMessage, MavMissionResult, MavMissionType, MavModeFlag, MavParamType, MavResult,
    PositionTargetTypemask, MISSION_COUNT_DATA, MISSION_REQUEST_LIST_DATA, PARAM_REQUEST_READ_DATA, PARAM_SET_DATA,
    SET_MODE_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use support::{mission_item, Autopilot};

const POSCTL: u32 = 3 << 16;
const AUTO_LOITER: u32 = (4 << 16) | (3 << 24);
const OFFBOARD: u32 = 6 << 16;
const NAN: f32 = f32::NAN;

/// The custom_mode of the next autopilot heartbeat satisfying `pick` within `timeout`.
fn heartbeat_mode(v: &Autopilot, timeout: Duration, pick: impl Fn(u32) -> bool) -> Option<u32> {
    v.wait(timeout, |h, m| match m {
        MavMessage::HEARTBEAT(hb) if h.component_id == 1 && pick(hb.custom_mode) => Some(hb.custom_mode),
        _ => None,
    })
}

fn set_mode(v: &mut Autopilot, main: f32, sub: f32) -> Option<MavResult> {
    v.command_with(
        MavCmd::MAV_CMD_DO_SET_MODE,
        [1.0, main, sub, NAN, NAN, NAN, NAN],
        (1, 1),
    )
}

/// PARAM_VALUE for `name` after `send`: (value, type, count, index).
fn param_reply(v: &Autopilot, name: &str) -> Option<(f32, MavParamType, u16, u16)> {
    v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::PARAM_VALUE(p) if p.param_id.to_str().ok() == Some(name) => {
            Some((p.param_value, p.param_type, p.param_count, p.param_index))
        }
        _ => None,
    })
}

fn param_set(v: &mut Autopilot, name: &str, value: f32, param_type: MavParamType) {
    v.send(&MavMessage::PARAM_SET(PARAM_SET_DATA {
        param_value: value,
        target_system: 1,
        target_component: 1,
        param_id: name.into(),
        param_type,
    }));
}

#[test]
fn mode_machine_through_both_set_mode_encodings() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(heartbeat_mode(&v, Duration::from_secs(3), |_| true).is_some());
    assert_eq!(set_mode(&mut v, 3.0, 0.0), Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        heartbeat_mode(&v, Duration::from_secs(2), |m| m == POSCTL),
        Some(POSCTL)
    );
    let refused = [
        (1.0, 0.0, MavResult::MAV_RESULT_TEMPORARILY_REJECTED, "MANUAL"),
        (4.0, 4.0, MavResult::MAV_RESULT_TEMPORARILY_REJECTED, "no mission"),
        (6.0, 0.0, MavResult::MAV_RESULT_TEMPORARILY_REJECTED, "no setpoints"),
        (9.0, 0.0, MavResult::MAV_RESULT_DENIED, "unknown"),
    ];
    for (main, sub, result, why) in refused {
        assert_eq!(set_mode(&mut v, main, sub), Some(result), "{why}");
    }
    v.send(&MavMessage::SET_MODE(SET_MODE_DATA {
        custom_mode: AUTO_LOITER,
        target_system: 1,
        base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
    }));
    assert_eq!(
        heartbeat_mode(&v, Duration::from_secs(2), |m| m == AUTO_LOITER),
        Some(AUTO_LOITER)
    );
}

#[test]
fn parameter_protocol_reads_sets_and_refuses() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(heartbeat_mode(&v, Duration::from_secs(3), |_| true).is_some());
    v.send(&MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
        param_index: -1,
        target_system: 1,
        target_component: 1,
        param_id: "MIS_TAKEOFF_ALT".into(),
    }));
    let (value, kind, count, index) = param_reply(&v, "MIS_TAKEOFF_ALT").expect("read by name");
    assert_eq!((value, kind, index), (2.5, MavParamType::MAV_PARAM_TYPE_REAL32, 0));
    assert_eq!(usize::from(count), rotorpilot::params::rows().count());
    v.send(&MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
        param_index: 7,
        target_system: 1,
        target_component: 1,
        param_id: "".into(),
    }));
    let (value, kind, _, _) = param_reply(&v, "RP_CTRL").expect("read by index");
    assert_eq!((value.to_bits(), kind), (0, MavParamType::MAV_PARAM_TYPE_INT32));

    // INT32 byte-wise: the bits of 2 in the float field.
    param_set(&mut v, "RP_CTRL", f32::from_bits(2), MavParamType::MAV_PARAM_TYPE_INT32);
    let (value, _, _, _) = param_reply(&v, "RP_CTRL").expect("echo");
    assert_eq!(value.to_bits(), 2);
    param_set(&mut v, "MIS_TAKEOFF_ALT", 4.0, MavParamType::MAV_PARAM_TYPE_REAL32);
    assert_eq!(param_reply(&v, "MIS_TAKEOFF_ALT").map(|p| p.0), Some(4.0));
    // A refused value echoes the unchanged one and says why.
    param_set(&mut v, "MIS_TAKEOFF_ALT", -3.0, MavParamType::MAV_PARAM_TYPE_REAL32);
    assert_eq!(param_reply(&v, "MIS_TAKEOFF_ALT").map(|p| p.0), Some(4.0));
    let why = v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::STATUSTEXT(t) => t.text.to_str().ok().map(str::to_owned),
        _ => None,
    });
    assert!(why.is_some_and(|t| t.contains("MIS_TAKEOFF_ALT")));
}

/// Uploads `items` answering each MISSION_REQUEST_INT; the MISSION_ACK result.
fn upload(v: &mut Autopilot, items: &[MavMessage]) -> Option<MavMissionResult> {
    v.send(&MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 1,
        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
        opaque_id: 0,
    }));
    let end = Instant::now() + Duration::from_secs(5);
    while Instant::now() < end {
        enum Next {
            Item(u16),
            Done(MavMissionResult),
        }
        let next = v.wait(Duration::from_secs(1), |_, m| match m {
            MavMessage::MISSION_REQUEST_INT(r) => Some(Next::Item(r.seq)),
            MavMessage::MISSION_ACK(a) => Some(Next::Done(a.mavtype)),
            _ => None,
        })?;
        match next {
            Next::Item(seq) => v.send(&items[usize::from(seq)]),
            Next::Done(result) => return Some(result),
        }
    }
    None
}

fn stored_count(v: &mut Autopilot) -> Option<u16> {
    v.send(&MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
    }));
    v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::MISSION_COUNT(c) => Some(c.count),
        _ => None,
    })
}

#[test]
fn mission_protocol_uploads_atomically() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(heartbeat_mode(&v, Duration::from_secs(3), |_| true).is_some());
    let good = [
        mission_item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, 0, 3.0),
        mission_item(1, MavCmd::MAV_CMD_NAV_WAYPOINT, 450, 3.0),
        mission_item(2, MavCmd::MAV_CMD_NAV_LAND, 450, 0.0),
    ];
    assert_eq!(upload(&mut v, &good), Some(MavMissionResult::MAV_MISSION_ACCEPTED));
    assert_eq!(stored_count(&mut v), Some(3));
    let bad = [
        mission_item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, 0, 3.0),
        mission_item(1, MavCmd::MAV_CMD_DO_SET_SERVO, 0, 0.0),
    ];
    assert_eq!(upload(&mut v, &bad), Some(MavMissionResult::MAV_MISSION_UNSUPPORTED));
    assert_eq!(
        stored_count(&mut v),
        Some(3),
        "a refused upload leaves the stored mission"
    );
}

fn position_setpoint(v: &mut Autopilot, z: f32) {
    v.send(&MavMessage::SET_POSITION_TARGET_LOCAL_NED(
        SET_POSITION_TARGET_LOCAL_NED_DATA {
            z,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            target_system: 1,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..Default::default()
        },
    ));
}

#[test]
fn offboard_needs_a_stream_and_its_loss_holds_position() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(heartbeat_mode(&v, Duration::from_secs(3), |_| true).is_some());
    v.take_off();
    assert_eq!(
        heartbeat_mode(&v, Duration::from_secs(10), |m| m == AUTO_LOITER),
        Some(AUTO_LOITER)
    );
    assert_eq!(
        set_mode(&mut v, 6.0, 0.0),
        Some(MavResult::MAV_RESULT_TEMPORARILY_REJECTED)
    );
    for _ in 0..10 {
        position_setpoint(&mut v, -3.0);
        std::thread::sleep(Duration::from_millis(50));
    }
    position_setpoint(&mut v, -3.0);
    let last_setpoint = Instant::now();
    assert_eq!(set_mode(&mut v, 6.0, 0.0), Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        heartbeat_mode(&v, Duration::from_secs(2), |m| m == OFFBOARD),
        Some(OFFBOARD)
    );
    // The stream has stopped: after COM_OF_LOSS_T (1 s) the vehicle holds position in POSCTL,
    // not before.
    assert_eq!(
        heartbeat_mode(&v, Duration::from_secs(4), |m| m == POSCTL),
        Some(POSCTL)
    );
    assert!(
        last_setpoint.elapsed() >= Duration::from_millis(950),
        "{:?}",
        last_setpoint.elapsed()
    );
}
