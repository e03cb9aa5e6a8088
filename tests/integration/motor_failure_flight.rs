//! Motor failures injected in flight as PX4's MAVSDK control-allocation and failure-injection
//! cases inject them (MAV_CMD_INJECT_FAILURE through the commander's request), on `hexa_x`
//! through the runtime vehicle (flight controller + plant), without sockets:
//! - `COM_ACT_FAIL_ACT` 0 (PX4's default): the motor and its opposite leave the allocation, the
//!   mission flies on along its legs and lands;
//! - 3: the vehicle returns and lands at home; 4: flight termination, motors off at once;
//! - a restored motor goes back into the allocation;
//! - `SYS_FAIL_MOT_OFF` 1 (a hard failure): only that motor stops, nothing is told.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::runtime_vehicle::{vehicle, DT_S};
use rotorpilot::commander::FailsafeCause;
use rotorpilot::commander::{Event, FlightMode, Outcome, Request};
use rotorpilot::guidance::{Mission, MissionItem};
use rotorpilot::math::Vec3;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;
use rotorpilot::telemetry::Snapshot;

const HEIGHT_M: f64 = 10.0;

fn hexa(params: &[(&str, f64)]) -> Vehicle {
    vehicle("hexa_x", SensorModel::State, 0, params)
}

/// Steps until `done` holds (at most `max_s` [s]); every snapshot goes to `watch`, every event
/// to `events`. Whether `done` held.
fn fly(
    v: &mut Vehicle,
    max_s: f64,
    events: &mut Vec<Event>,
    mut watch: impl FnMut(&Snapshot),
    mut done: impl FnMut(&Snapshot) -> bool,
) -> bool {
    for _ in 0..(max_s / DT_S) as usize {
        let out = v.step();
        events.extend(out.events);
        watch(&out.snapshot);
        if done(&out.snapshot) {
            return true;
        }
    }
    false
}

/// Takes off to 10 m and settles there (as the cases' hover before the injection).
fn hovering(v: &mut Vehicle, events: &mut Vec<Event>) {
    assert_eq!(
        v.apply(Request::Takeoff {
            height_m: Some(HEIGHT_M)
        }),
        Outcome::Accepted
    );
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    let up = fly(v, 30.0, events, |_| {}, |s| s.mode == FlightMode::Loiter);
    assert!(up, "took off: {events:?}");
    fly(v, 3.0, events, |_| {}, |_| false);
}

fn motor(v: &mut Vehicle, rotor: usize, failed: bool) {
    assert_eq!(
        v.apply(Request::InjectRotorFailure { rotor, failed }),
        Outcome::Accepted
    );
}

fn said(events: &[Event], text: &str) -> bool {
    events.iter().any(|e| matches!(e, Event::Failsafe(_, t) if t == text))
}

/// Distance of `p` from the segment `a`–`b` [m].
fn off_leg(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let k = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (p - (a + k * ab)).norm()
}

/// How a square mission was flown: its events, the largest distance from the square's path
/// and from 10 m [m], the motors stopped on the way, the largest tilt [deg] and the heading's
/// range [deg].
struct Square {
    events: Vec<Event>,
    off_track_m: f64,
    off_height_m: f64,
    stopped: u32,
    tilt_deg: f64,
    heading_deg: (f64, f64),
}

/// PX4's case on hexa_x: hover at 10 m, motor `failed` off (none: no failure), then the 20 m
/// square mission at 10 m and a landing at its last corner.
fn square_mission(failed: Option<usize>) -> Square {
    let mut v = hexa(&[]);
    let mut events = Vec::new();
    hovering(&mut v, &mut events);
    if let Some(rotor) = failed {
        motor(&mut v, rotor, true);
    }
    fly(&mut v, 1.0, &mut events, |_| {}, |_| false);
    let corners = [(0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0)].map(|(n, e)| Vec3::new(n, e, -HEIGHT_M));
    let items = corners[1..]
        .iter()
        .map(|c| MissionItem::Waypoint {
            pos_w: *c,
            hold_s: 0.0,
            accept_m: None,
            yaw_rad: None,
        })
        .chain([MissionItem::Land { pos_w: None }])
        .collect();
    assert_eq!(
        v.apply(Request::SetMission(Mission {
            items,
            ..Default::default()
        })),
        Outcome::Accepted
    );
    assert_eq!(v.apply(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    let mut m = Square {
        events: Vec::new(),
        off_track_m: 0.0,
        off_height_m: 0.0,
        stopped: 0,
        tilt_deg: 0.0,
        heading_deg: (f64::MAX, f64::MIN),
    };
    let landed = fly(
        &mut v,
        120.0,
        &mut events,
        |s| {
            // Items 0 to 2 fly the legs from corner to corner (turning through each within
            // NAV_ACC_RAD), item 3 lands: the distance from the square's path.
            if s.mission_seq < 3 && s.armed {
                let path = (0..3).map(|k| off_leg(s.pos_w, corners[k], corners[k + 1]));
                m.off_track_m = m.off_track_m.max(path.fold(f64::MAX, f64::min));
                m.off_height_m = m.off_height_m.max((s.pos_w.z + HEIGHT_M).abs());
                m.stopped |= s.rotors_stopped;
                m.tilt_deg = m.tilt_deg.max((s.eta.x.cos() * s.eta.y.cos()).acos().to_degrees());
                let yaw = s.eta.z.to_degrees();
                m.heading_deg = (m.heading_deg.0.min(yaw), m.heading_deg.1.max(yaw));
            }
        },
        |s| !s.armed,
    );
    assert!(landed, "the mission ended on the ground: {events:?}");
    m.events = events;
    m
}

#[test]
fn a_hexa_that_loses_a_motor_flies_its_mission_on_with_com_act_fail_act_0() {
    let nominal = square_mission(None);
    let m = square_mission(Some(1));
    assert!(
        said(&m.events, "Motor 1 failed, motor 4 off, yaw lost"),
        "{:?}",
        m.events
    );
    assert!(m.events.contains(&Event::Disarmed("landed")));
    let returned = m.events.contains(&Event::ModeChanged(FlightMode::ReturnToLaunch));
    assert!(!returned, "no failsafe mode: {:?}", m.events);
    assert_eq!(
        (nominal.stopped, m.stopped),
        (0, 0b1001),
        "motor 1 and its opposite, motor 4"
    );
    // The corners are turned through beyond the square as without the failure.
    assert!(
        m.off_track_m < nominal.off_track_m + 0.3 && m.off_track_m < 5.0,
        "off the square: {:.2} m, {:.2} m without the failure (PX4's case: 5 m)",
        m.off_track_m,
        nominal.off_track_m
    );
    assert!(
        m.off_height_m < 1.0,
        "within 1 m of 10 m (PX4's case: 4 m): {:.2} m",
        m.off_height_m
    );
    assert!(m.tilt_deg < 45.0, "within the tilt limit: {:.1}°", m.tilt_deg);
    let (lo, hi) = m.heading_deg;
    assert!(hi - lo < 90.0, "the heading drifts, never spins: {lo:.1}° to {hi:.1}°");
    eprintln!(
        "square after the failure: {:.2} m off the square ({:.2} m without), {:.2} m off 10 m ({:.2} m \
         without), tilt {:.1}° ({:.1}°), heading {lo:.1}° to {hi:.1}°",
        m.off_track_m, nominal.off_track_m, m.off_height_m, nominal.off_height_m, m.tilt_deg, nominal.tilt_deg
    );
}

#[test]
fn com_act_fail_act_3_returns_home_and_4_terminates() {
    // Return: from a hold 20 m north, after COM_FAIL_ACT_T in a hold.
    let mut v = hexa(&[("COM_ACT_FAIL_ACT", 3.0), ("RTL_RETURN_ALT", HEIGHT_M)]);
    let mut events = Vec::new();
    hovering(&mut v, &mut events);
    let wp = MissionItem::LoiterTime {
        pos_w: Vec3::new(20.0, 0.0, -HEIGHT_M),
        seconds: Some(600.0),
    };
    assert_eq!(
        v.apply(Request::SetMission(Mission {
            items: vec![wp],
            ..Default::default()
        })),
        Outcome::Accepted
    );
    assert_eq!(v.apply(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    let there = fly(
        &mut v,
        30.0,
        &mut events,
        |_| {},
        |s| (s.pos_w - Vec3::new(20.0, 0.0, -HEIGHT_M)).norm() < 0.3,
    );
    assert!(there);
    motor(&mut v, 1, true);
    let t0 = v.time_s();
    let mut returning_at = None;
    let home = fly(
        &mut v,
        120.0,
        &mut events,
        |s| {
            if s.mode == FlightMode::ReturnToLaunch && returning_at.is_none() {
                returning_at = Some(s.t_s - t0);
            }
        },
        |s| !s.armed,
    );
    assert!(home, "{events:?}");
    assert!(
        said(&events, "Motor 1 failed, motor 4 off, yaw lost: returning"),
        "{events:?}"
    );
    let hold_s = returning_at.unwrap();
    assert!((hold_s - 5.0).abs() < 0.01, "COM_FAIL_ACT_T hold first: {hold_s} s");
    let p = v.truth().pos_w;
    assert!(p.xy().norm() < 0.5, "landed at home: {p:?}");
    eprintln!("returned {:.2} m from home in {:.1} s", p.xy().norm(), v.time_s() - t0);

    // Termination: motors off at once, the vehicle falls.
    let mut v = hexa(&[("COM_ACT_FAIL_ACT", 4.0)]);
    let mut events = Vec::new();
    hovering(&mut v, &mut events);
    motor(&mut v, 1, true);
    let t0 = v.time_s();
    let out = v.step();
    assert!(!out.snapshot.armed, "{:?}", out.events);
    assert!(out.events.contains(&Event::Failsafe(
        FailsafeCause::Other,
        "Motor 1 failed, motor 4 off, yaw lost: terminating".into()
    )));
    assert!(out.events.contains(&Event::Disarmed("flight termination")));
    assert_eq!(out.snapshot.rotors_stopped, u32::MAX, "every motor off");
    let down = fly(
        &mut v,
        5.0,
        &mut events,
        |_| {},
        |s| s.truth.is_some_and(|t| t.pos_w.z > -0.15),
    );
    let fall_s = v.time_s() - t0;
    assert!(down, "on the ground");
    // Free fall from 10 m: 1.43 s; the drag only slows it.
    assert!((1.4..2.5).contains(&fall_s), "fell in {fall_s:.2} s");
    eprintln!("terminated at 10 m: on the ground {fall_s:.2} s later");
}

#[test]
fn a_restored_motor_goes_back_into_the_allocation() {
    let mut v = hexa(&[]);
    let mut events = Vec::new();
    hovering(&mut v, &mut events);
    let mut worst: f64 = 0.0;
    let mut watch = |s: &Snapshot| worst = worst.max((s.pos_w.z + HEIGHT_M).abs());
    for rotor in 1..=6 {
        motor(&mut v, rotor, true);
        fly(&mut v, 1.0, &mut events, &mut watch, |_| false);
        motor(&mut v, rotor, false);
        fly(&mut v, 1.0, &mut events, &mut watch, |_| false);
        let opposite = (rotor + 2) % 6 + 1;
        let text = format!("Motor {rotor} failed, motor {opposite} off, yaw lost");
        assert!(said(&events, &text), "{text}: {events:?}");
        assert!(said(&events, &format!("Motor {rotor} working again")));
    }
    let s = v.step().snapshot;
    assert_eq!(s.rotors_stopped, 0, "every motor back in");
    assert!(
        s.rotor_commands[..6].iter().all(|w| *w > 300.0),
        "{:?}",
        &s.rotor_commands[..6]
    );
    assert!(
        worst < 1.0,
        "every motor out and back in turn: within {worst:.2} m of 10 m"
    );
    assert!(s.pos_w.xy().norm() < 1.0, "held its place: {:?}", s.pos_w);
    eprintln!("each motor out for 1 s and back: within {worst:.2} m of 10 m");
}

#[test]
fn a_hard_failure_only_stops_the_motor_and_a_soft_one_its_opposite_too() {
    for (hard, stopped) in [(1.0, 0b1), (0.0, 0b1001)] {
        let mut v = hexa(&[("SYS_FAIL_MOT_OFF", hard), ("MC_AIRMODE_LIM", 1.0)]);
        let mut events = Vec::new();
        hovering(&mut v, &mut events);
        let before = events.len();
        motor(&mut v, 1, true);
        let mut worst: f64 = 0.0;
        let mut mask = 0;
        fly(
            &mut v,
            5.0,
            &mut events,
            |s| {
                worst = worst.max((s.pos_w.z + HEIGHT_M).abs());
                mask = s.rotors_stopped;
            },
            |_| false,
        );
        assert_eq!(mask, stopped, "SYS_FAIL_MOT_OFF {hard}");
        let announced = events[before..].iter().any(|e| matches!(e, Event::Failsafe(..)));
        assert_eq!(
            announced,
            hard == 0.0,
            "a hard failure is not told: {:?}",
            &events[before..]
        );
        assert!(
            worst < 1.0,
            "SYS_FAIL_MOT_OFF {hard}: within {worst:.2} m of 10 m (PX4's case: 1 m)"
        );
        motor(&mut v, 1, false);
        fly(
            &mut v,
            5.0,
            &mut events,
            |s| worst = worst.max((s.pos_w.z + HEIGHT_M).abs()),
            |_| false,
        );
        assert_eq!(v.step().snapshot.rotors_stopped, 0);
        assert!(worst < 1.0);
        eprintln!("SYS_FAIL_MOT_OFF {hard}: within {worst:.2} m of 10 m, out and back in");
    }
}
