//! The MAVLink shell against the vehicle's MAVLink endpoint, as QGroundControl's MAVLink console
//! and MAVSDK's shell plugin use it: bytes in SERIAL_CONTROL with RESPOND, echoed as they arrive;
//! a line's answer in REPLY frames of at most 70 bytes to the client, then PX4 SITL's prompt
//! `pxh> `; `param set` goes through the vehicle like a PARAM_SET.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};

/// `text` typed into the shell from QGC (RESPOND | EXCLUSIVE, as QGC and MAVSDK send it).
fn type_in(b: &mut Bench, text: &str, respond: bool) {
    for chunk in text.as_bytes().chunks(70) {
        let mut data = [0u8; 70];
        data[..chunk.len()].copy_from_slice(chunk);
        let mut flags = SerialControlFlag::SERIAL_CONTROL_FLAG_EXCLUSIVE;
        if respond {
            flags |= SerialControlFlag::SERIAL_CONTROL_FLAG_RESPOND;
        }
        b.send(
            Gcs,
            QGC,
            MavMessage::SERIAL_CONTROL(SERIAL_CONTROL_DATA {
                baudrate: 0,
                timeout: 0,
                device: SerialControlDev::SERIAL_CONTROL_DEV_SHELL,
                flags,
                count: chunk.len() as u8,
                data,
                target_system: 1,
                target_component: 1,
            }),
        );
    }
}

/// The shell's output since the last call, frames checked and joined.
fn shell_out(b: &mut Bench) -> String {
    let mut text = Vec::new();
    for (_, to, m) in b.out() {
        if let MavMessage::SERIAL_CONTROL(r) = m {
            assert_eq!(to, QGC);
            assert_eq!((r.target_system, r.target_component), (255, 190));
            assert_eq!(r.flags, SerialControlFlag::SERIAL_CONTROL_FLAG_REPLY);
            assert_eq!(r.device, SerialControlDev::SERIAL_CONTROL_DEV_SHELL);
            assert!(r.count as usize <= 70);
            text.extend_from_slice(&r.data[..r.count as usize]);
        }
    }
    String::from_utf8(text).unwrap()
}

#[test]
fn a_console_session_answers_each_line_then_prompts() {
    let mut b = Bench::new();
    // Nothing before the first line (PX4's remote pxh prints its prompt after each line only).
    type_in(&mut b, "\n", true);
    assert_eq!(shell_out(&mut b), "\npxh> ");
    type_in(&mut b, "ver all\n", true);
    let ver = shell_out(&mut b);
    assert!(
        ver.starts_with("ver all\n") && ver.contains("FW version") && ver.ends_with("\npxh> "),
        "{ver}"
    );
    type_in(&mut b, "param sh", true);
    assert_eq!(shell_out(&mut b), "param sh", "echoed as typed, run when the line ends");
    type_in(&mut b, "ow RP_GEO_K*\n", true);
    let show = shell_out(&mut b);
    assert!(show.starts_with("ow RP_GEO_K*\n"), "{show}");
    assert!(show.contains("RP_GEO_KP_X") && show.contains("RP_GEO_KW_Z"), "{show}");
    assert!(show.len() > 70, "several frames");
    type_in(&mut b, "top\n", true);
    assert_eq!(
        shell_out(&mut b),
        "top\nInvalid command: top\ntype 'help' for a list of commands\npxh> "
    );
    type_in(&mut b, "help\n", true);
    assert_eq!(
        shell_out(&mut b),
        "help\nBuiltin Commands:\n  commander\n  listener\n  param\n  ver\npxh> "
    );
    type_in(&mut b, "commander status\n", true);
    assert!(shell_out(&mut b).contains("arming state: STANDBY"));
    type_in(&mut b, "listener vehicle_local_position\n", true);
    assert!(shell_out(&mut b).contains("TOPIC: vehicle_local_position"));
    // Without RESPOND the client is done: nothing is answered.
    type_in(&mut b, "help\n", false);
    assert_eq!(shell_out(&mut b), "");
}

#[test]
fn param_set_waits_for_the_vehicle_and_says_what_changed() {
    let mut b = Bench::new();
    type_in(&mut b, "param set MIS_TAKEOFF_ALT 4.5\n", true);
    assert_eq!(shell_out(&mut b), "param set MIS_TAKEOFF_ALT 4.5\n");
    let asks = b.asks();
    let [ask] = &asks[..] else { panic!("{asks:?}") };
    assert_eq!(
        ask.request,
        VehicleRequest::SetParam {
            name: "MIS_TAKEOFF_ALT".into(),
            value: 4.5
        }
    );
    let mut after = table();
    let result = after.set("MIS_TAKEOFF_ALT", 4.5, 1e-3);
    let now = b.now;
    b.m.handle_reply(
        now,
        ask.token.unwrap(),
        VehicleReply::Param {
            result,
            table: std::sync::Arc::new(after),
        },
    );
    let out = b.out();
    assert!(
        !named(&out, "PARAM_VALUE").is_empty(),
        "the change is announced to the link"
    );
    let text: String = out
        .iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::SERIAL_CONTROL(r) => Some(String::from_utf8_lossy(&r.data[..r.count as usize]).into_owned()),
            _ => None,
        })
        .collect();
    assert_eq!(text, "MIS_TAKEOFF_ALT: curr: 2.5000 -> new: 4.5000\npxh> ");
    type_in(&mut b, "param show MIS_TAKEOFF_ALT\n", true);
    assert!(shell_out(&mut b).contains(": 4.5000"));

    // A refusal says why; an unknown name is refused before the vehicle is asked.
    type_in(&mut b, "param set RP_CTRL 1.5\n", true);
    shell_out(&mut b);
    let asks = b.asks();
    let mut after = table();
    let result = after.set("RP_CTRL", 1.5, 1e-3);
    let now = b.now;
    b.m.handle_reply(
        now,
        asks[0].token.unwrap(),
        VehicleReply::Param {
            result,
            table: std::sync::Arc::new(after),
        },
    );
    let refused = shell_out(&mut b);
    assert!(
        refused.starts_with("ERROR: param set RP_CTRL refused: RP_CTRL: 1.5 is not an integer"),
        "{refused}"
    );
    type_in(&mut b, "param set NOPE 1\n", true);
    assert!(shell_out(&mut b).contains("ERROR: Parameter NOPE not found."));
    assert!(b.asks().is_empty());
}
