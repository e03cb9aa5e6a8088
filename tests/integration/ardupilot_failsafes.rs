//! An ArduCopter-faced vehicle's failsafes and SET_MODE answer (docs/ardupilot.md §2) through the
//! shipped link machine with virtual time: the GCS failsafe in Copter's words with the HEARTBEAT
//! CRITICAL until the ground station is heard again (the commander's PX4 wording not said), and
//! SET_MODE answered with a COMMAND_ACK whose command is the message id 11.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{Event, FailsafeCause, FlightMode, Outcome, Request};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;

fn ardupilot() -> Bench {
    Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot))
}

/// The requests whose answer the link awaits (not the RC receiver's sticks).
fn awaited(b: &mut Bench) -> Vec<rotorpilot::mav::link::ToVehicle> {
    b.asks().into_iter().filter(|a| a.token.is_some()).collect()
}

fn texts(out: &[(LinkKind, u16, MavMessage)]) -> Vec<(MavSeverity, String)> {
    named(out, "STATUSTEXT")
        .iter()
        .filter(|(link, to, _)| (*link, *to) == (Gcs, QGC))
        .filter_map(|(_, _, m)| match m {
            MavMessage::STATUSTEXT(t) => Some((t.severity, t.text.to_str().unwrap().to_string())),
            _ => None,
        })
        .collect()
}

fn status(out: &[(LinkKind, u16, MavMessage)]) -> Option<MavState> {
    named(out, "HEARTBEAT").iter().rev().find_map(|(_, _, m)| match m {
        MavMessage::HEARTBEAT(h) => Some(h.system_status),
        _ => None,
    })
}

#[test]
fn the_gcs_failsafe_is_said_in_copters_words_and_is_critical_until_the_gcs_is_back() {
    let mut b = ardupilot();
    let mut after = table();
    after.set("NAV_DLL_ACT", 2.0, 1e-3).unwrap();
    b.send(Gcs, QGC, param_set("FS_GCS_ENABLE", 1.0)); // RTL: NAV_DLL_ACT 2
    let token = awaited(&mut b)[0].token.unwrap();
    let table = std::sync::Arc::new(after);
    b.m.handle_reply(b.now, token, VehicleReply::Param { result: Ok(0), table });
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(5.0, 5.0);
    assert_eq!(status(&b.out()), Some(MavState::MAV_STATE_STANDBY));
    b.at(10.5, 10.5);
    let asks = b.asks();
    assert!(asks
        .iter()
        .any(|a| a.request == VehicleRequest::Commander(Request::GcsLinkLost)));
    let out = b.out();
    assert!(
        texts(&out).contains(&(MavSeverity::MAV_SEVERITY_WARNING, "GCS Failsafe".into())),
        "{:?}",
        texts(&out)
    );
    // The commander's return, announced in PX4's words, is not said; the mode shows it.
    b.m.handle_event(
        b.now,
        Event::Failsafe(FailsafeCause::GcsLink, "GCS link lost: returning".into()),
    );
    assert!(texts(&b.out()).is_empty());
    b.at(12.0, 12.0);
    assert_eq!(status(&b.out()), Some(MavState::MAV_STATE_CRITICAL));
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(12.2, 12.2);
    let out = b.out();
    assert!(texts(&out).contains(&(MavSeverity::MAV_SEVERITY_WARNING, "GCS Failsafe Cleared".into())));
    b.at(13.5, 13.5);
    assert_eq!(status(&b.out()), Some(MavState::MAV_STATE_STANDBY));
}

/// The COMMAND_ACKs (command id, result) sent to the ground station since the last call, read
/// from the frames (the dialect has no command 11).
fn raw_acks(b: &mut Bench) -> (Vec<(u16, u8)>, Vec<String>) {
    let (mut acks, mut said) = (Vec::new(), Vec::new());
    while let Some(t) = b.m.poll_transmit() {
        let msgid = u32::from_le_bytes([t.bytes[7], t.bytes[8], t.bytes[9], 0]);
        if msgid == 77 {
            let payload = &t.bytes[10..];
            acks.push((u16::from_le_bytes([payload[0], payload[1]]), payload[2]));
        } else if let Some(rotorpilot::mav::codec::Inbound::Message { message, .. }) =
            rotorpilot::mav::codec::decode_datagram(&t.bytes).into_iter().next()
        {
            if let MavMessage::STATUSTEXT(s) = *message {
                said.push(s.text.to_str().unwrap().to_string());
            }
        }
    }
    (acks, said)
}

#[test]
fn set_mode_is_answered_with_an_ack_whose_command_is_11() {
    let mut b = ardupilot();
    let set_mode = |base: u8, custom_mode: u32| {
        MavMessage::SET_MODE(SET_MODE_DATA {
            custom_mode,
            target_system: 1,
            base_mode: MavModeFlag::from_bits_retain(base),
        })
    };
    b.send(Gcs, QGC, set_mode(1, 4));
    let asks = awaited(&mut b);
    assert_eq!(
        asks[0].request,
        VehicleRequest::Commander(Request::SelectMode(FlightMode::Guided))
    );
    b.m.handle_reply(b.now, asks[0].token.unwrap(), VehicleReply::Outcome(Outcome::Accepted));
    assert_eq!(raw_acks(&mut b), (vec![(11, 0)], vec![]), "ACCEPTED");
    b.send(Gcs, QGC, set_mode(1, 5));
    let token = awaited(&mut b)[0].token.unwrap();
    let refused = Outcome::TemporarilyRejected("Mode POSCTL: no valid position estimate".into());
    b.m.handle_reply(b.now, token, VehicleReply::Outcome(refused));
    let (acks, said) = raw_acks(&mut b);
    assert_eq!(acks, vec![(11, 4)], "FAILED");
    assert_eq!(
        said,
        ["Mode change to LOITER failed: no valid position es"],
        "50 characters"
    );
    b.send(Gcs, QGC, set_mode(0, 4));
    assert_eq!(
        raw_acks(&mut b).0,
        vec![(11, 3)],
        "UNSUPPORTED without the custom mode flag"
    );
    b.send(Gcs, QGC, set_mode(1, 14));
    let (acks, said) = raw_acks(&mut b);
    assert_eq!(
        (acks, said),
        (vec![(11, 4)], vec!["Mode change to FLIP failed: not emulated".into()])
    );
}
