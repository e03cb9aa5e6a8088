//! Liveness judged by the vehicle's MAVLink endpoint with virtual clocks: GCS link loss and the
//! offboard stream and the sticks (MANUAL_CONTROL), each counted in wall and in simulated time;
//! which links the sticks are flown from (`COM_RC_IN_MODE`).
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::FailsafeCause;
use rotorpilot::commander::{Event, InputStream, Request};
use rotorpilot::guidance::Sticks;
use rotorpilot::mav::link::{VehicleReply, VehicleRequest};

#[test]
fn link_loss_needs_silence_in_wall_and_simulated_time_and_fires_once() {
    let mut b = Bench::new();
    let mut after = table();
    after.set("NAV_DLL_ACT", 2.0, 1e-3).unwrap();
    b.send(Gcs, QGC, param_set("NAV_DLL_ACT", 2.0));
    let token = b.asks()[0].token.unwrap();
    b.m.handle_reply(
        b.now,
        token,
        VehicleReply::Param {
            result: Ok(0),
            table: std::sync::Arc::new(after),
        },
    );
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(9.9, 9.9);
    assert!(b.asks().is_empty());
    b.at(12.0, 5.0);
    assert!(b.asks().is_empty(), "simulated time is still within COM_DL_LOSS_T");
    b.at(12.1, 10.1);
    let asks = b.asks();
    assert_eq!(asks.len(), 1);
    assert_eq!(asks[0].request, VehicleRequest::Commander(Request::GcsLinkLost));
    assert_eq!(asks[0].token, None, "no answer is awaited");
    b.at(13.0, 11.0);
    assert!(b.asks().is_empty(), "once per loss");
    // The reaction comes back as a commander event, announced on every link like every event.
    b.m.handle_event(
        b.now,
        Event::Failsafe(FailsafeCause::GcsLink, "GCS link lost: returning".into()),
    );
    let out = b.out();
    let texts = named(&out, "STATUSTEXT");
    let said = |m: &MavMessage| {
        matches!(m, MavMessage::STATUSTEXT(t) if t.severity == MavSeverity::MAV_SEVERITY_CRITICAL
            && t.text.to_str().unwrap() == "GCS link lost: returning")
    };
    assert!(
        texts.iter().any(|(link, to, m)| (*link, *to) == (Gcs, QGC) && said(m)),
        "{texts:?}"
    );
    // A heartbeat ends the loss; the next silence fires again.
    b.send(Gcs, QGC, gcs_heartbeat());
    b.at(13.1, 11.1);
    b.at(23.2, 21.2);
    assert_eq!(b.asks().len(), 1);
}

#[test]
fn the_offboard_stream_is_alive_for_the_commander_until_com_of_loss_t_of_wall_time_silence() {
    let mut b = Bench::new();
    let setpoint = || {
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            target_system: 1,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            z: -3.0,
            ..Default::default()
        })
    };
    let lost = VehicleRequest::Commander(Request::StreamLost(InputStream::Offboard));
    b.send(Api, SDK, setpoint());
    let asks: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert!(matches!(
        asks[..],
        [VehicleRequest::Commander(Request::OffboardSetpoint { .. })]
    ));
    // Simulated time racing ahead does not matter; wall time does.
    b.at(0.9, 40.0);
    b.send(Api, SDK, setpoint());
    assert_eq!(b.asks().len(), 1, "only the setpoint: the stream is still alive");
    b.at(1.85, 80.0);
    assert!(
        b.asks().is_empty(),
        "0.95 s of wall-time silence is within COM_OF_LOSS_T"
    );
    b.at(1.95, 80.0);
    assert_eq!(b.asks().into_iter().map(|a| a.request).collect::<Vec<_>>(), vec![lost]);
    b.at(5.0, 90.0);
    assert!(b.asks().is_empty(), "said once");
}

fn joystick(x: i16, z: i16) -> MavMessage {
    MavMessage::MANUAL_CONTROL(MANUAL_CONTROL_DATA {
        target: 1,
        x,
        y: 0,
        z,
        r: 0,
        ..Default::default()
    })
}

fn sticks_of(asks: Vec<rotorpilot::mav::link::ToVehicle>) -> Vec<VehicleRequest> {
    asks.into_iter().map(|a| a.request).collect()
}

#[test]
fn manual_control_is_flown_from_the_first_link_and_alive_until_com_rc_loss_t_of_wall_time_silence() {
    let mut b = Bench::new();
    let lost = VehicleRequest::Commander(Request::StreamLost(InputStream::ManualControl));
    b.send(Gcs, QGC, joystick(1000, 500));
    let forward = Sticks {
        pitch: 1.0,
        ..Sticks::CENTRED
    };
    assert_eq!(
        sticks_of(b.asks()),
        vec![VehicleRequest::Commander(Request::ManualControl(forward))]
    );
    // COM_RC_IN_MODE 3 keeps the first source: MAVSDK's sticks on the API link are not flown.
    b.send(Api, SDK, joystick(-1000, 500));
    assert!(b.asks().is_empty());
    b.at(0.45, 30.0);
    b.send(Gcs, QGC, joystick(0, 500));
    assert_eq!(sticks_of(b.asks()).len(), 1, "alive: only the sticks");
    b.at(0.9, 60.0);
    assert!(b.asks().is_empty(), "0.45 s of silence is within COM_RC_LOSS_T");
    b.at(0.96, 60.0);
    assert_eq!(sticks_of(b.asks()), vec![lost]);
    // A malformed axis is refused with the field named, never flown.
    b.send(Gcs, QGC, joystick(1001, 500));
    assert!(b.asks().is_empty());
    let out = b.out();
    let texts = named(&out, "STATUSTEXT");
    assert!(
        texts.iter().any(|(_, _, m)| matches!(m, MavMessage::STATUSTEXT(t)
            if t.text.to_str().unwrap() == "MANUAL_CONTROL x = 1001 is outside [-1000, 1000]")),
        "{texts:?}"
    );
}

#[test]
fn com_rc_in_mode_zero_and_four_ignore_manual_control_and_one_takes_any_link() {
    for (mode, flown) in [(0.0, [false, false]), (4.0, [false, false]), (1.0, [true, true])] {
        let mut b = Bench::with(|config| {
            std::sync::Arc::make_mut(&mut config.params)
                .set("COM_RC_IN_MODE", mode, 1e-3)
                .unwrap();
        });
        b.send(Gcs, QGC, joystick(0, 500));
        let from_gcs = !b.asks().is_empty();
        b.send(Api, SDK, joystick(0, 500));
        let from_api = !b.asks().is_empty();
        assert_eq!([from_gcs, from_api], flown, "COM_RC_IN_MODE {mode}");
    }
}
