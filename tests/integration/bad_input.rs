//! Setpoints and commands with NaN, Inf, out-of-range or contradictory values are refused
//! (DENIED, or ignored with a STATUSTEXT) and never flown: a hovering vehicle takes a barrage of
//! them over UDP and is still where it was, in the mode it was in.
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![allow(deprecated)] // MAV_FRAME_GLOBAL_RELATIVE_ALT_INT is what MAVSDK sends

use crate::support;

use std::time::Duration;

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMessage, MavParamType, MavResult, PositionTargetTypemask, COMMAND_INT_DATA, PARAM_SET_DATA,
    SET_POSITION_TARGET_GLOBAL_INT_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use support::{attitude_target, Autopilot};

const NAN: f32 = f32::NAN;
const INF: f32 = f32::INFINITY;
const AUTO_LOITER: u32 = (4 << 16) | (3 << 24);

fn local_target(mask: u16, p: [f32; 3], v: [f32; 3]) -> MavMessage {
    MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        x: p[0],
        y: p[1],
        z: p[2],
        vx: v[0],
        vy: v[1],
        vz: v[2],
        type_mask: PositionTargetTypemask::from_bits_truncate(mask),
        target_system: 1,
        target_component: 1,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
        ..Default::default()
    })
}

/// The next STATUSTEXT within 1 s.
fn status_text(v: &Autopilot) -> Option<String> {
    v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::STATUSTEXT(t) => t.text.to_str().ok().map(str::to_owned),
        _ => None,
    })
}

/// Latest LOCAL_POSITION_NED (x, y, z) and heartbeat custom mode.
fn where_and_mode(v: &Autopilot) -> ([f32; 3], u32) {
    let pos = v
        .wait(Duration::from_secs(3), |_, m| match m {
            MavMessage::LOCAL_POSITION_NED(p) => Some([p.x, p.y, p.z]),
            _ => None,
        })
        .unwrap();
    let mode = v
        .wait(Duration::from_secs(3), |h, m| match m {
            MavMessage::HEARTBEAT(hb) if h.component_id == 1 => Some(hb.custom_mode),
            _ => None,
        })
        .unwrap();
    (pos, mode)
}

#[test]
fn a_hovering_vehicle_refuses_every_bad_value_and_stays_put() {
    let mut v = Autopilot::start(1, "quad_x");
    assert!(v
        .wait(Duration::from_secs(3), |_, m| matches!(m, MavMessage::HEARTBEAT(_))
            .then_some(()))
        .is_some());
    let denied = Some(MavResult::MAV_RESULT_DENIED);
    // On the ground: take-off heights that are not heights.
    for p7 in [INF, -INF, 488.0 + 5000.0, -3.0] {
        let r = v.command_with(MavCmd::MAV_CMD_NAV_TAKEOFF, [NAN, NAN, NAN, NAN, NAN, NAN, p7], (1, 1));
        assert_eq!(r, denied, "take-off p7 {p7}");
    }
    assert_eq!(v.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, INF, (1, 1)), denied);
    v.take_off();
    let hover = v.wait(Duration::from_secs(10), |h, m| match m {
        MavMessage::HEARTBEAT(hb) if h.component_id == 1 && hb.custom_mode == AUTO_LOITER => Some(()),
        _ => None,
    });
    assert!(hover.is_some(), "take-off done");
    std::thread::sleep(Duration::from_millis(500));
    let (before, _) = where_and_mode(&v);

    // Commands with non-finite or impossible values.
    let cases: [(MavCmd, [f32; 7]); 8] = [
        (MavCmd::MAV_CMD_DO_CHANGE_SPEED, [NAN, INF, NAN, NAN, NAN, NAN, NAN]),
        (MavCmd::MAV_CMD_DO_CHANGE_SPEED, [NAN, -2.0, NAN, NAN, NAN, NAN, NAN]),
        (MavCmd::MAV_CMD_DO_REPOSITION, [NAN, NAN, NAN, NAN, 91.0, 8.5, 490.0]),
        (MavCmd::MAV_CMD_DO_REPOSITION, [NAN, NAN, NAN, NAN, 47.4, INF, 490.0]),
        (MavCmd::MAV_CMD_DO_REPOSITION, [NAN, NAN, NAN, NAN, NAN, NAN, -INF]),
        (MavCmd::MAV_CMD_DO_SET_HOME, [0.0, NAN, NAN, NAN, 47.4, 200.0, 488.0]),
        (MavCmd::MAV_CMD_DO_SET_MODE, [1.0, NAN, NAN, NAN, NAN, NAN, NAN]),
        (
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [-1.0, NAN, NAN, NAN, NAN, NAN, NAN],
        ),
    ];
    for (cmd, params) in cases {
        assert_eq!(v.command_with(cmd, params, (1, 1)), denied, "{cmd:?} {params:?}");
        assert!(status_text(&v).is_some(), "{cmd:?}: a STATUSTEXT says why");
    }
    v.send(&MavMessage::COMMAND_INT(COMMAND_INT_DATA {
        param1: NAN,
        param2: NAN,
        param3: NAN,
        param4: NAN,
        x: 2_000_000_000,
        y: 85_455_940,
        z: 3.0,
        command: MavCmd::MAV_CMD_DO_REPOSITION,
        target_system: 1,
        target_component: 1,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        current: 0,
        autocontinue: 0,
    }));
    let ack = v.wait(Duration::from_secs(1), |_, m| match m {
        MavMessage::COMMAND_ACK(a) if a.command == MavCmd::MAV_CMD_DO_REPOSITION => Some(a.result),
        _ => None,
    });
    assert_eq!(ack, denied, "latitude 200°");
    assert_eq!(
        status_text(&v).as_deref(),
        Some("Reposition: 200.00, 8.55 is not a place")
    );

    // Offboard setpoints that cannot be flown: ignored with a STATUSTEXT each.
    let bad_targets = [
        local_target(2552, [NAN, 0.0, -3.0], [0.0; 3]),
        local_target(2552, [0.0, INF, -3.0], [0.0; 3]),
        local_target(2552, [1e9, 0.0, -3.0], [0.0; 3]),
        local_target(2503, [0.0; 3], [500.0, 0.0, 0.0]),
        local_target(2552 & !(1 << 3), [0.0, 0.0, -3.0], [0.0; 3]), // position with half a velocity
        local_target(2552 | (1 << 9), [0.0, 0.0, -3.0], [0.0; 3]),  // force setpoint
        MavMessage::SET_POSITION_TARGET_GLOBAL_INT(SET_POSITION_TARGET_GLOBAL_INT_DATA {
            lat_int: 900_000_000,
            lon_int: 85_455_940,
            alt: 3.0,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            target_system: 1,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
            ..Default::default()
        }),
        attitude_target([NAN, 0.0, 0.0, 0.0], 0.5),
        attitude_target([1.0, 0.0, 0.0, 0.0], 3.0),
    ];
    for target in &bad_targets {
        v.send(target);
        let why = status_text(&v);
        let explained = why
            .as_deref()
            .is_some_and(|t| t.starts_with("Offboard") || t.starts_with("Attitude target"));
        assert!(explained, "{target:?}: {why:?}");
    }
    // Offboard cannot be entered on them either.
    assert_eq!(
        v.command_with(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 6.0, 0.0, NAN, NAN, NAN, NAN], (1, 1)),
        Some(MavResult::MAV_RESULT_TEMPORARILY_REJECTED)
    );
    // Parameters: NaN, Inf and out-of-range values are refused; the echo keeps the old value.
    for value in [NAN, INF, -5.0, 1e9] {
        v.send(&MavMessage::PARAM_SET(PARAM_SET_DATA {
            param_value: value,
            target_system: 1,
            target_component: 1,
            param_id: "MPC_XY_CRUISE".into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        }));
        let echo = v.wait(Duration::from_secs(1), |_, m| match m {
            MavMessage::PARAM_VALUE(p) if p.param_id.to_str().ok() == Some("MPC_XY_CRUISE") => Some(p.param_value),
            _ => None,
        });
        assert_eq!(echo, Some(5.0), "MPC_XY_CRUISE = {value}");
    }

    let (after, mode) = where_and_mode(&v);
    assert_eq!(mode, AUTO_LOITER, "still holding");
    let moved = before
        .iter()
        .zip(&after)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f32>()
        .sqrt();
    assert!(moved < 0.05, "moved {moved} m");
}
