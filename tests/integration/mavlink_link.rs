//! The autopilot process on ephemeral ports, driven over UDP with the codec: heartbeat,
//! command/ACK rules, garbage on the socket, and two vehicles in one process.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::support;

use std::time::Duration;

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavResult, MavType, HEARTBEAT_DATA};
use rotorpilot::mav::codec::encode_v2;
use rotorpilot::mav::gcs::gcs_header;
use support::Autopilot;

#[test]
fn heartbeat_commands_and_garbage() {
    let mut v = Autopilot::start(1, "quad_x");
    let hb = v.wait(Duration::from_secs(3), |h, m| match m {
        MavMessage::HEARTBEAT(hb) if h.component_id == 1 => Some((h.system_id, hb.mavtype)),
        _ => None,
    });
    assert_eq!(hb, Some((1, MavType::MAV_TYPE_QUADROTOR)));
    v.send(&MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        mavtype: MavType::MAV_TYPE_GCS,
        ..Default::default()
    }));
    assert_eq!(
        v.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 2.0, (1, 1)),
        Some(MavResult::MAV_RESULT_DENIED)
    );
    assert_eq!(
        v.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, (9, 1)),
        None,
        "other system"
    );
    assert_eq!(
        v.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, (1, 50)),
        None,
        "other component"
    );
    assert_eq!(
        v.command(MavCmd::MAV_CMD_DO_SET_SERVO, 1.0, (1, 0)),
        Some(MavResult::MAV_RESULT_UNSUPPORTED)
    );

    // Garbage: random bytes, a truncated frame, a frame with a broken CRC, an oversized datagram.
    let mut good = Vec::new();
    encode_v2(
        gcs_header(0),
        &MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()),
        &mut good,
    );
    let mut bad_crc = good.clone();
    let last = bad_crc.len() - 1;
    bad_crc[last] ^= 0xFF;
    let mut state = 0x1234_5678u32;
    let mut noise = vec![0u8; 60_000];
    for b in noise.iter_mut() {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        *b = state as u8;
    }
    for _ in 0..200 {
        v.gcs.send_bytes(&noise[..(state as usize % 280) + 1], v.autopilot);
        v.gcs.send_bytes(&good[..good.len() / 2], v.autopilot);
        v.gcs.send_bytes(&bad_crc, v.autopilot);
        state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
    }
    v.gcs.send_bytes(&noise, v.autopilot);
    // The kernel may drop datagrams during such a burst when net.core.rmem_max is small: retry as
    // MAVSDK does (4 × 0.5 s). With the 4 MiB receive buffer the first try is answered here.
    let retried = (0..4).find_map(|_| v.command(MavCmd::MAV_CMD_NAV_TAKEOFF, f32::NAN, (1, 1)));
    assert_eq!(retried, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        v.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, (1, 1)),
        Some(MavResult::MAV_RESULT_ACCEPTED),
        "still answering after the garbage"
    );
}

#[test]
fn two_vehicles_in_one_process_are_separate_systems() {
    let mut a = Autopilot::start(1, "quad_x");
    let mut b = Autopilot::start(2, "hexa_x");
    let sysid = |v: &Autopilot| {
        v.wait(Duration::from_secs(3), |h, m| match m {
            MavMessage::HEARTBEAT(hb) => Some((h.system_id, hb.mavtype)),
            _ => None,
        })
    };
    assert_eq!(sysid(&a), Some((1, MavType::MAV_TYPE_QUADROTOR)));
    assert_eq!(sysid(&b), Some((2, MavType::MAV_TYPE_HEXAROTOR)));
    assert_eq!(
        a.command(MavCmd::MAV_CMD_NAV_LAND, 0.0, (2, 1)),
        None,
        "vehicle 1 ignores sysid 2"
    );
    assert_eq!(
        b.command(MavCmd::MAV_CMD_NAV_TAKEOFF, f32::NAN, (2, 1)),
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
}
