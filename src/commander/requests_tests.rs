//! Requests on a scripted vehicle: change speed, take-off and set-home values, the mission
//! stored, started and replaced.

use super::super::script::Script;
use super::super::{CommanderParams, FlightMode, MissionState, Outcome, Request};
use crate::guidance::{Mission, MissionItem};
use crate::math::Vec3;

#[test]
fn change_speed_refuses_bad_speeds_and_sets_the_cruise_speed() {
    let mut s = Script::new(CommanderParams::default());
    for v in [0.0, -1.0, f64::NAN, f64::INFINITY, 31.0] {
        assert!(matches!(s.request(Request::ChangeSpeed(v)), Outcome::Denied(_)), "{v}");
    }
    assert_eq!(s.request(Request::ChangeSpeed(2.0)), Outcome::Accepted);
    s.airborne(3.0);
    // Flown in AUTO.LOITER (no mode change asked), at DO_CHANGE_SPEED's speed.
    let in_hold = Request::Reposition {
        north_m: Some(30.0),
        east_m: Some(0.0),
        down_m: None,
        yaw_rad: None,
        speed_m_s: None,
        change_mode: false,
    };
    assert_eq!(s.request(in_hold), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    let mut fastest: f64 = 0.0;
    assert!(s.fly_until(60.0, |s| {
        fastest = fastest.max(s.x.vel_w.xy().norm());
        (s.x.pos_w.x - 30.0).abs() < 1e-6
    }));
    assert!(
        fastest <= 2.0 + 1e-9 && fastest > 1.9,
        "DO_CHANGE_SPEED 2 m/s: {fastest} m/s"
    );
}

#[test]
fn takeoff_set_home_and_failure_injection_check_their_values() {
    let mut s = Script::new(CommanderParams::default());
    for h in [0.0, -2.0, 1001.0] {
        let takeoff = Request::Takeoff { height_m: Some(h) };
        assert!(matches!(s.request(takeoff), Outcome::Denied(_)), "{h}");
    }
    let bad_home = Request::SetHome(Some(Vec3::new(f64::NAN, 0.0, 0.0)));
    assert!(matches!(s.request(bad_home), Outcome::Denied(_)));
    assert_eq!(s.c.home_w(), Vec3::zeros());
    let inject = Request::InjectRotorFailure { rotor: 1, failed: true };
    assert!(matches!(s.request(inject), Outcome::Denied(_)));
    s.airborne(3.0);
    assert_eq!(
        s.request(Request::Takeoff { height_m: None }),
        Outcome::TemporarilyRejected("Takeoff refused: already flying".into())
    );
    assert_eq!(s.request(Request::SetHome(None)), Outcome::Accepted);
    assert_eq!(s.c.home_w(), s.x.pos_w, "home here");
}

#[test]
fn a_mission_is_stored_started_from_an_item_and_replacing_it_leaves_auto_mission() {
    let mut s = Script::new(CommanderParams::default());
    assert!(matches!(
        s.request(Request::StartMission { first: 0 }),
        Outcome::Denied(_)
    ));
    let wp = |north_m| MissionItem::Waypoint {
        pos_w: Vec3::new(north_m, 0.0, -4.0),
        hold_s: 0.0,
        accept_m: Some(0.5),
        yaw_rad: None,
    };
    let mission = Mission {
        items: vec![wp(5.0), wp(10.0)],
        ..Default::default()
    };
    assert_eq!(s.request(Request::SetMission(mission)), Outcome::Accepted);
    assert_eq!(s.c.mission_progress(), (0, 2, MissionState::NotStarted));
    assert!(matches!(
        s.request(Request::StartMission { first: 2 }),
        Outcome::Denied(_)
    ));
    assert_eq!(s.request(Request::StartMission { first: 1 }), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Mission);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    s.fly(3.0);
    assert_eq!(s.c.mission_progress(), (1, 2, MissionState::Active));
    assert_eq!(s.request(Request::SetMission(Mission::default())), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    assert_eq!(s.c.mission_progress(), (0, 0, MissionState::NoMission));
}
