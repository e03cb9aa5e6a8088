//! Liveness judged by the vehicle's MAVLink endpoint with virtual clocks: GCS link loss and the
//! offboard stream, each counted in wall and in simulated time.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

mod link_bench;

use link_bench::*;
use mavlink::dialects::common::*;
use rotorpilot::commander::{Event, Request, Stream};
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
            table: Box::new(after),
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
    b.m.handle_event(b.now, Event::Failsafe("GCS link lost: returning".into()));
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
    let wall = |alive| {
        VehicleRequest::Commander(Request::StreamInWallTime {
            stream: Stream::Offboard,
            alive,
        })
    };
    b.send(Api, SDK, setpoint());
    let asks: Vec<_> = b.asks().into_iter().map(|a| a.request).collect();
    assert!(matches!(
        asks[0],
        VehicleRequest::Commander(Request::OffboardSetpoint { .. })
    ));
    assert_eq!(asks[1], wall(true), "the stream started");
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
    assert_eq!(
        b.asks().into_iter().map(|a| a.request).collect::<Vec<_>>(),
        vec![wall(false)]
    );
    b.at(5.0, 90.0);
    assert!(b.asks().is_empty(), "said once");
}
