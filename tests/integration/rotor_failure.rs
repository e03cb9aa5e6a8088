//! Rotors that stop in the plant (`--fail-rotor`, a scenario's `[[rotor_failure]]`): the flight
//! controller's ESC check (`FD_ACT_EN`) reports the stopped rotor after `FD_ACT_MOT_TOUT`, the
//! allocation leaves it (and on a hexa- or octocopter its opposite) out, and `COM_ACT_FAIL_ACT`
//! decides: PX4's default 0 flies on (a hexa- or octocopter hovers where it was, a quadrotor
//! gives up yaw and spins), 2 lands where it was. Through the runtime vehicle (commander + flight
//! core + plant), without sockets.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::runtime_vehicle::vehicle;
use rotorpilot::commander::{Event, FlightMode, Outcome, Request};
use rotorpilot::lockstep::ScheduledFailure;
use rotorpilot::sitl::SensorModel;

struct Flight {
    events: Vec<Event>,
    /// When the first failure was announced [s].
    announced_s: Option<f64>,
    max_tilt_deg: f64,
    max_drift_m: f64,
    armed_at_end: bool,
    final_z_m: f64,
    finite: bool,
}

/// Takes off to 3 m, loses `rotor` at 6 s, runs until `seconds`, with the parameters `params`.
/// When the rotor fails [s]: after the take-off to 3 m (≈ 5.5 s at PX4's take-off speed).
const FAILURE_AT_S: f64 = 9.0;

fn fly(preset: &str, rotor: usize, seconds: f64, params: &[(&str, f64)]) -> Flight {
    let mut v = vehicle(preset, SensorModel::State, 0, params);
    v.schedule_rotor_failure(ScheduledFailure {
        rotor,
        at_s: FAILURE_AT_S,
    })
    .unwrap();
    assert_eq!(v.apply(Request::Takeoff { height_m: Some(3.0) }), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    let mut flight = Flight {
        events: Vec::new(),
        announced_s: None,
        max_tilt_deg: 0.0,
        max_drift_m: 0.0,
        armed_at_end: true,
        final_z_m: 0.0,
        finite: true,
    };
    for _ in 0..(seconds * 1000.0) as usize {
        let out = v.step();
        let s = out.snapshot;
        if flight.announced_s.is_none() && out.events.iter().any(|e| matches!(e, Event::Failsafe(..))) {
            flight.announced_s = Some(s.t_s);
        }
        flight.events.extend(out.events);
        flight.finite &= s.pos_w.iter().chain(s.eta.iter()).all(|x| x.is_finite());
        if s.t_s > FAILURE_AT_S {
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
    events.iter().any(|e| matches!(e, Event::Failsafe(_, t) if t == text))
}

#[test]
fn hexa_and_octo_report_the_stopped_rotor_and_hover_on_by_default() {
    // The PNPNPN hexacopter idles the opposite rotor too and gives up yaw: it hovers without
    // spinning; the octocopter keeps full control with seven rotors.
    for (preset, rotor, text) in [
        ("hexa_x", 1, "Motor 1 failed, motor 4 off, yaw lost"),
        ("octo", 3, "Motor 3 failed"),
    ] {
        let f = fly(preset, rotor, 23.0, &[]);
        assert!(announced(&f.events, text), "{preset}: {:?}", f.events);
        let after = f.announced_s.unwrap() - FAILURE_AT_S;
        assert!(
            (0.099..0.11).contains(&after),
            "{preset}: FD_ACT_MOT_TOUT, then reported: {after} s"
        );
        assert!(
            !f.events
                .iter()
                .any(|e| matches!(e, Event::ModeChanged(m) if *m != FlightMode::Loiter)),
            "{preset}: COM_ACT_FAIL_ACT 0 flies on: {:?}",
            f.events
        );
        assert!(f.finite && f.armed_at_end, "{preset}: still flying");
        assert!((f.final_z_m + 3.0).abs() < 0.3, "{preset}: at 3 m: {}", f.final_z_m);
        assert!(f.max_tilt_deg < 15.0, "{preset}: tilt {}", f.max_tilt_deg);
        assert!(f.max_drift_m < 0.5, "{preset}: drift {}", f.max_drift_m);
        eprintln!(
            "{preset}: reported {after:.3} s after the stop, hovers on: drift {:.2} m, tilt {:.1}°, z {:.2} m",
            f.max_drift_m, f.max_tilt_deg, f.final_z_m
        );
    }
}

#[test]
fn with_com_act_fail_act_2_hexa_and_octo_land_where_they_were() {
    for (preset, rotor, text) in [
        ("hexa_x", 1, "Motor 1 failed, motor 4 off, yaw lost: landing"),
        ("octo", 3, "Motor 3 failed: landing"),
    ] {
        let f = fly(preset, rotor, 28.0, &[("COM_ACT_FAIL_ACT", 2.0)]);
        assert!(announced(&f.events, text), "{preset}: {:?}", f.events);
        let modes: Vec<&Event> = f.events.iter().filter(|e| matches!(e, Event::ModeChanged(_))).collect();
        assert_eq!(
            &modes[1..],
            [
                &Event::ModeChanged(FlightMode::Loiter),
                &Event::ModeChanged(FlightMode::Land)
            ],
            "{preset}: the COM_FAIL_ACT_T hold, then the landing"
        );
        assert!(
            f.events.contains(&Event::Disarmed("landed")),
            "{preset}: {:?}",
            f.events
        );
        assert!(f.finite && !f.armed_at_end);
        assert!(f.max_tilt_deg < 15.0, "{preset}: tilt {}", f.max_tilt_deg);
        assert!(f.max_drift_m < 0.5, "{preset}: drift {}", f.max_drift_m);
        eprintln!(
            "{preset}: lands {:.2} m from the failure, tilt {:.1}°",
            f.max_drift_m, f.max_tilt_deg
        );
    }
}

#[test]
fn a_quadrotor_gives_up_yaw_and_comes_down_whatever_com_act_fail_act_says() {
    // The rotor across the failed one must idle for roll and pitch: the two left give 2 × 7.1 N
    // for 14.7 N of weight.
    for (params, text) in [
        (vec![], "Motor 2 failed, yaw lost"),
        (vec![("COM_ACT_FAIL_ACT", 2.0)], "Motor 2 failed, yaw lost: landing"),
    ] {
        let f = fly("quad_x", 2, 23.0, &params);
        assert!(announced(&f.events, text), "{:?}", f.events);
        assert!(f.finite, "no NaN");
        assert!(
            f.final_z_m > -0.5,
            "on or near the ground at the end: z = {}",
            f.final_z_m
        );
    }
}

#[test]
fn without_the_esc_check_nothing_is_reported() {
    let f = fly("octo", 3, 15.0, &[("FD_ACT_EN", 0.0)]);
    assert!(
        !f.events.iter().any(|e| matches!(e, Event::Failsafe(..))),
        "{:?}",
        f.events
    );
    assert!(f.finite && f.armed_at_end);
    assert!(
        f.max_drift_m < 1.0,
        "the octocopter flies on its full allocation: drift {}",
        f.max_drift_m
    );
}

#[test]
fn injection_needs_sys_failure_en() {
    let mut v = vehicle("hexa_x", SensorModel::State, 0, &[]);
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
        announced(&events, "Motor 1 failed, motor 4 off, yaw lost"),
        "on the ground: announced, nothing else: {events:?}"
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
