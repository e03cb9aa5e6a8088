//! Rotor failures: a hexa- or octocopter that loses a rotor keeps control and lands where it
//! was; a quadrotor gives up yaw and comes down as well as it can. Through the runtime vehicle
//! (commander + flight core + plant), without sockets.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::airframe::AirframeSource;
use rotorpilot::commander::{Event, FlightMode, Outcome, Request};
use rotorpilot::control::ControllerKind;
use rotorpilot::lockstep::ScheduledFailure;
use rotorpilot::navigation::Home;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;

struct Flight {
    events: Vec<Event>,
    max_tilt_deg: f64,
    max_drift_m: f64,
    armed_at_end: bool,
    final_z_m: f64,
    finite: bool,
}

/// Takes off to 3 m, loses `rotor` at 6 s, runs until `seconds`.
fn fly(preset: &str, rotor: usize, seconds: f64) -> Flight {
    let src = AirframeSource::resolve(preset).unwrap();
    let mut v = Vehicle::new(
        &src,
        ControllerKind::Geometric,
        Home::default(),
        SensorModel::State,
        0,
        1e-3,
    )
    .unwrap();
    v.schedule_rotor_failure(ScheduledFailure { rotor, at_s: 6.0 }).unwrap();
    assert_eq!(v.apply(Request::Takeoff { height_m: Some(3.0) }), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    let mut flight = Flight {
        events: Vec::new(),
        max_tilt_deg: 0.0,
        max_drift_m: 0.0,
        armed_at_end: true,
        final_z_m: 0.0,
        finite: true,
    };
    for _ in 0..(seconds * 1000.0) as usize {
        let out = v.step();
        let s = out.snapshot;
        flight.events.extend(out.events);
        flight.finite &= s.pos_w.iter().chain(s.eta.iter()).all(|x| x.is_finite());
        if s.t_s > 6.0 {
            let tilt = (s.eta.x.cos() * s.eta.y.cos()).clamp(-1.0, 1.0).acos().to_degrees();
            flight.max_tilt_deg = flight.max_tilt_deg.max(tilt);
            flight.max_drift_m = flight.max_drift_m.max(s.pos_w.xy().norm());
        }
        flight.armed_at_end = s.armed;
        flight.final_z_m = s.pos_w.z;
    }
    flight
}

fn announced(events: &[Event], text: &str) -> bool {
    events.iter().any(|e| matches!(e, Event::Failsafe(t) if t == text))
}

#[test]
fn hexa_and_octo_keep_flying_and_land() {
    // The octocopter keeps full control; the PNPNPN hexacopter gives up yaw (it spins) but
    // stays level.
    for (preset, rotor, text) in [
        ("hexa_x", 1, "Motor 1 failed, yaw lost: landing"),
        ("octo", 3, "Motor 3 failed: landing"),
    ] {
        let f = fly(preset, rotor, 20.0);
        assert!(announced(&f.events, text), "{preset}: {:?}", f.events);
        assert!(f.events.contains(&Event::ModeChanged(FlightMode::Land)));
        assert!(
            f.events.contains(&Event::Disarmed("landed")),
            "{preset}: {:?}",
            f.events
        );
        assert!(f.finite && !f.armed_at_end);
        assert!(f.max_tilt_deg < 15.0, "{preset}: tilt {}", f.max_tilt_deg);
        assert!(f.max_drift_m < 0.5, "{preset}: drift {}", f.max_drift_m);
    }
}

#[test]
fn a_quadrotor_reports_gives_up_yaw_and_comes_down() {
    let f = fly("quad_x", 2, 20.0);
    assert!(
        announced(&f.events, "Motor 2 failed, yaw lost: landing"),
        "{:?}",
        f.events
    );
    assert!(f.events.contains(&Event::ModeChanged(FlightMode::Land)));
    assert!(f.finite, "no NaN");
    assert!(
        f.final_z_m > -0.5,
        "on or near the ground at the end: z = {}",
        f.final_z_m
    );
}

#[test]
fn injection_needs_sys_failure_en() {
    let src = AirframeSource::resolve("hexa_x").unwrap();
    let mut v = Vehicle::new(
        &src,
        ControllerKind::Geometric,
        Home::default(),
        SensorModel::State,
        0,
        1e-3,
    )
    .unwrap();
    let inject = Request::InjectRotorFailure { rotor: 1, failed: true };
    v.set_param("SYS_FAILURE_EN", 0.0).unwrap();
    assert!(matches!(v.apply(inject.clone()), Outcome::Denied(why) if why.contains("SYS_FAILURE_EN")));
    v.set_param("SYS_FAILURE_EN", 1.0).unwrap();
    assert_eq!(v.apply(inject), Outcome::Accepted);
    assert!(matches!(
        v.apply(Request::InjectRotorFailure { rotor: 7, failed: true }),
        Outcome::Denied(why) if why == "Failure injection: no motor 7 (1 to 6)"
    ));
    let events = v.step().events;
    assert!(
        announced(&events, "Motor 1 failed, yaw lost"),
        "on the ground: announced, no landing: {events:?}"
    );
    assert_eq!(
        v.apply(Request::InjectRotorFailure {
            rotor: 1,
            failed: false
        }),
        Outcome::Accepted
    );
    assert!(announced(&v.step().events, "Motor 1 working again"));
}
