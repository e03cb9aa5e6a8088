//! The RC receiver of an ArduCopter-faced vehicle (docs/ardupilot.md §8) through the shipped link
//! machine with virtual time: RC_CHANNELS shows SITL's resting channels and each override for
//! RC_OVERRIDE_TIME, the stick channels reach the commander as its manual input at 50 Hz, the
//! boot mode STABILIZE is asked for, Copter's throttle rules for arming and mode changes; a
//! PX4-faced vehicle ignores RC_CHANNELS_OVERRIDE.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::link_bench;

use link_bench::*;
use mavlink::dialects::ardupilotmega::*;
use rotorpilot::commander::{FlightMode, LandedState, Request};
use rotorpilot::mav::identity::Personality;
use rotorpilot::mav::link::{ToVehicle, VehicleRequest};
use rotorpilot::mav::translate::Identity;

fn ardupilot() -> Bench {
    Bench::with(|c| c.identity = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot))
}

fn rc_override(first4: [u16; 4]) -> MavMessage {
    MavMessage::RC_CHANNELS_OVERRIDE(RC_CHANNELS_OVERRIDE_DATA {
        chan1_raw: first4[0],
        chan2_raw: first4[1],
        chan3_raw: first4[2],
        chan4_raw: first4[3],
        chan5_raw: u16::MAX,
        chan6_raw: u16::MAX,
        chan7_raw: u16::MAX,
        chan8_raw: u16::MAX,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    })
}

/// The RC_CHANNELS the vehicle answers with now (asked for by MAV_CMD_REQUEST_MESSAGE).
fn rc_channels(b: &mut Bench) -> RC_CHANNELS_DATA {
    b.send(Gcs, QGC, command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 65.0));
    let out = b.out();
    named(&out, "RC_CHANNELS")
        .iter()
        .find_map(|(_, _, m)| match m {
            MavMessage::RC_CHANNELS(rc) => Some(rc.clone()),
            _ => None,
        })
        .expect("RC_CHANNELS")
}

/// The commander requests since the last call.
fn requests(b: &mut Bench) -> Vec<Request> {
    b.asks()
        .into_iter()
        .filter_map(|ToVehicle { request, .. }| match request {
            VehicleRequest::Commander(r) => Some(r),
            _ => None,
        })
        .collect()
}

fn sticks_of(requests: &[Request]) -> Vec<rotorpilot::guidance::Sticks> {
    requests
        .iter()
        .filter_map(|r| match r {
            Request::ManualControl(s) => Some(*s),
            _ => None,
        })
        .collect()
}

#[test]
fn rc_channels_show_sitl_resting_values_then_each_override_for_three_seconds() {
    let mut b = ardupilot();
    let rc = rc_channels(&mut b);
    assert_eq!((rc.chancount, rc.rssi), (16, 255));
    assert_eq!(
        [
            rc.chan1_raw,
            rc.chan2_raw,
            rc.chan3_raw,
            rc.chan4_raw,
            rc.chan5_raw,
            rc.chan9_raw
        ],
        [1500, 1500, 1000, 1500, 1800, 0]
    );
    b.at(1.0, 1.0);
    b.send(Gcs, QGC, rc_override([1600, u16::MAX, 1900, 0]));
    let rc = rc_channels(&mut b);
    assert_eq!(
        [rc.chan1_raw, rc.chan2_raw, rc.chan3_raw, rc.chan4_raw],
        [1600, 1500, 1900, 1500]
    );
    b.at(3.9, 3.9);
    assert_eq!(rc_channels(&mut b).chan3_raw, 1900, "in force for RC_OVERRIDE_TIME");
    b.at(4.0, 4.0);
    assert_eq!(rc_channels(&mut b).chan3_raw, 1000, "back to the receiver after 3 s");
    // Not addressed to us: ignored.
    let MavMessage::RC_CHANNELS_OVERRIDE(mut other) = rc_override([1200, 1200, 1200, 1200]) else {
        unreachable!()
    };
    other.target_system = 7;
    b.send(Gcs, QGC, MavMessage::RC_CHANNELS_OVERRIDE(other));
    assert_eq!(rc_channels(&mut b).chan1_raw, 1500);
}

#[test]
fn the_stick_channels_feed_the_commander_at_50_hz_and_stabilize_is_the_boot_mode() {
    let mut b = ardupilot();
    b.state.nav.validity.attitude = true;
    requests(&mut b);
    let mut asked = Vec::new();
    for k in 1..=200 {
        let t = f64::from(k) * 0.005;
        b.at(t, t);
        asked.extend(requests(&mut b));
    }
    let sticks = sticks_of(&asked);
    assert!((49..=51).contains(&sticks.len()), "{} samples in 1 s", sticks.len());
    assert!(
        sticks.iter().all(|s| s.throttle == 0.0 && s.roll == 0.0),
        "at rest on the ground"
    );
    assert!(
        asked.contains(&Request::SetMode(FlightMode::Stabilized)),
        "boot mode asked for"
    );
    b.send(Gcs, QGC, rc_override([2000, 1000, 1500, 1500]));
    let now = sticks_of(&requests(&mut b));
    assert_eq!(now.len(), 1, "an override reaches the commander at once");
    assert_eq!((now[0].roll, now[0].pitch, now[0].throttle), (1.0, 1.0, 0.5));
    // In the air a throttle without an override rests centred: the vehicle holds its height.
    b.state.landed = LandedState::InAir;
    b.at(5.0, 5.0);
    let later = sticks_of(&requests(&mut b));
    assert_eq!((later[0].roll, later[0].throttle), (0.0, 0.5));
    // MANUAL_CONTROL overrides the stick channels, as Copter reads it.
    b.send(
        Gcs,
        QGC,
        MavMessage::MANUAL_CONTROL(MANUAL_CONTROL_DATA {
            x: 0,
            y: 500,
            z: 900,
            r: 0,
            target: 1,
            ..Default::default()
        }),
    );
    let rc = rc_channels(&mut b);
    assert_eq!([rc.chan1_raw, rc.chan3_raw], [1750, 1900]);
}

#[test]
fn copter_throttle_rules_for_arming_and_manual_throttle_modes() {
    let mut b = ardupilot();
    b.state.mode = FlightMode::Stabilized;
    b.at(0.5, 0.5);
    b.out();
    requests(&mut b);
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0);
    b.send(Gcs, QGC, rc_override([0, 0, 1200, 0]));
    b.send(Gcs, QGC, arm.clone());
    let out = b.out();
    assert_eq!(acks(&out), vec![MavResult::MAV_RESULT_FAILED]);
    assert!(
        named(&out, "STATUSTEXT").iter().any(|(_, _, m)| matches!(m,
            MavMessage::STATUSTEXT(t) if String::from_utf8_lossy(&t.text[..]).starts_with("Arm: Throttle too high"))),
        "{out:?}"
    );
    b.send(Gcs, QGC, rc_override([0, 0, 1000, 0]));
    b.send(Gcs, QGC, arm);
    assert!(
        requests(&mut b).iter().any(|r| matches!(r, Request::Arm { .. })),
        "at its minimum the throttle lets the vehicle arm"
    );
    // Armed on the ground in GUIDED, STABILIZE with the throttle up is "throttle too high".
    b.state.mode = FlightMode::Guided;
    b.state.armed = true;
    b.at(1.0, 1.0);
    b.out();
    b.send(Gcs, QGC, rc_override([0, 0, 1500, 0]));
    let stabilize = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        command: MavCmd::MAV_CMD_DO_SET_MODE,
        param1: 1.0,
        param2: 0.0,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    });
    b.send(Gcs, QGC, stabilize.clone());
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_FAILED]);
    // In the air, a throttle held low would drop the vehicle in STABILIZE: refused.
    b.state.landed = LandedState::InAir;
    b.at(2.0, 2.0);
    b.out();
    b.send(Gcs, QGC, rc_override([0, 0, 1100, 0]));
    let mut refused = stabilize.clone();
    if let MavMessage::COMMAND_LONG(c) = &mut refused {
        c.confirmation = 1;
    }
    b.send(Gcs, QGC, refused);
    assert_eq!(acks(&b.out()), vec![MavResult::MAV_RESULT_FAILED]);
}

#[test]
fn a_px4_vehicle_ignores_rc_overrides() {
    let mut b = Bench::new();
    requests(&mut b);
    b.send(Gcs, QGC, rc_override([1600, 1600, 1600, 1600]));
    b.at(0.1, 0.1);
    assert!(sticks_of(&requests(&mut b)).is_empty());
}
