//! AUTO.MISSION on a scripted vehicle: items in order, a climb first from the ground, the end of
//! a mission, pauses, DO_JUMP and a current item set from outside.

use super::super::script::{Script, GROUND_Z_M};
use super::super::{CommanderParams, Event, Outcome, Request};
use super::*;
use crate::control::VehicleState;

fn flown(items: Vec<MissionItem>) -> Script {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(
        s.request(Request::SetMission(Mission {
            items,
            ..Default::default()
        })),
        Outcome::Accepted
    );
    assert_eq!(s.request(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    s
}

/// The mission events, in order.
fn mission_events(s: &Script) -> Vec<Event> {
    s.events
        .iter()
        .filter(|e| matches!(e, Event::MissionItemReached(_) | Event::MissionCurrent(_)))
        .cloned()
        .collect()
}

#[test]
fn a_mission_takes_off_flies_its_items_in_order_and_lands_on_the_last() {
    let mut s = flown(vec![
        MissionItem::Takeoff { height_m: 5.0 },
        MissionItem::Waypoint {
            pos_w: Vec3::new(10.0, 0.0, -5.0),
            hold_s: 1.0,
            accept_m: Some(0.5),
            yaw_rad: Some(0.5),
        },
        MissionItem::LoiterTime {
            pos_w: Vec3::new(10.0, 10.0, -5.0),
            seconds: Some(2.0),
        },
        MissionItem::Land {
            pos_w: Some(Vec3::new(0.0, 10.0, 0.0)),
        },
    ]);
    assert!(s.until_disarmed(120.0), "{:?}", s.events);
    use Event::{MissionCurrent as Current, MissionItemReached as Reached};
    assert_eq!(
        mission_events(&s),
        vec![
            Reached(0),
            Current(1),
            Reached(1),
            Current(2),
            Reached(2),
            Current(3),
            Reached(3)
        ]
    );
    assert_eq!(s.c.mission_progress(), (3, 4, MissionState::Complete));
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 10.0, GROUND_Z_M)).norm() < 1e-6,
        "{:?}",
        s.x.pos_w
    );
    assert_eq!(s.events.last(), Some(&Event::Disarmed("landed")));
}

#[test]
fn a_mission_started_on_the_ground_climbs_first_and_loiters_after_the_last_item() {
    let mut s = flown(vec![MissionItem::Waypoint {
        pos_w: Vec3::new(8.0, 0.0, -4.0),
        hold_s: 0.0,
        accept_m: Some(0.5),
        yaw_rad: None,
    }]);
    let mut straight_up = true;
    assert!(s.fly_until(20.0, |s| {
        straight_up &= s.x.pos_w.x.abs() < 1e-9;
        s.x.pos_w.z < -4.0 + 2e-3
    }));
    assert!(straight_up, "climbs to the item's height before it travels");
    assert!(s.fly_until(20.0, |s| s.c.mode() == FlightMode::Loiter));
    assert_eq!(
        mission_events(&s),
        vec![Event::MissionItemReached(0)],
        "no MISSION_CURRENT past the last item"
    );
    assert!(s.events.contains(&Event::ModeChanged(FlightMode::Loiter)));
    assert!((s.x.pos_w - Vec3::new(8.0, 0.0, -4.0)).norm() < 1e-2);
    assert_eq!(s.c.mission_progress(), (0, 1, MissionState::Complete));
}

#[test]
fn a_return_item_ends_the_mission_in_auto_rtl_and_another_mode_pauses_it() {
    let mut s = flown(vec![
        MissionItem::Takeoff { height_m: 3.0 },
        MissionItem::ChangeSpeed { speed_m_s: 2.0 },
        MissionItem::Delay { seconds: 1.0 },
        MissionItem::ReturnToLaunch,
    ]);
    assert!(s.fly_until(30.0, |s| s.c.mode() == FlightMode::ReturnToLaunch));
    assert_eq!(s.c.mission_progress(), (3, 4, MissionState::Complete));
    assert!(s.events.contains(&Event::ModeChanged(FlightMode::ReturnToLaunch)));
    let mut s = flown(vec![MissionItem::Waypoint {
        pos_w: Vec3::new(30.0, 0.0, -4.0),
        hold_s: 0.0,
        accept_m: Some(0.5),
        yaw_rad: None,
    }]);
    s.fly(8.0);
    assert_eq!(s.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
    assert_eq!(s.c.mission_progress().2, MissionState::Paused);
}

fn waypoint(north_m: f64, east_m: f64) -> MissionItem {
    MissionItem::Waypoint {
        pos_w: Vec3::new(north_m, east_m, -5.0),
        hold_s: 0.0,
        accept_m: Some(1.0),
        yaw_rad: None,
    }
}

/// PX4's DO_JUMP case: take-off, two waypoints, a jump back to item 1 taken once, a waypoint, a
/// landing.
fn jump_mission() -> Vec<MissionItem> {
    vec![
        MissionItem::Takeoff { height_m: 5.0 },
        waypoint(20.0, 0.0),
        waypoint(20.0, 20.0),
        MissionItem::Jump {
            target: 1,
            repeat: Some(1),
        },
        waypoint(0.0, 20.0),
        MissionItem::Land {
            pos_w: Some(Vec3::zeros()),
        },
    ]
}

/// The items reached, in order.
fn reached(s: &Script) -> Vec<u16> {
    s.events
        .iter()
        .filter_map(|e| match e {
            Event::MissionItemReached(seq) => Some(*seq),
            _ => None,
        })
        .collect()
}

#[test]
fn a_do_jump_is_taken_its_count_of_times_and_never_flown() {
    let mut s = flown(jump_mission());
    assert!(s.until_disarmed(300.0), "{:?}", s.events);
    assert_eq!(reached(&s), vec![0, 1, 2, 1, 2, 4, 5]);
    assert!(
        !s.events.contains(&Event::MissionItemReached(3)),
        "a jump is no place to reach"
    );
    assert_eq!(s.c.mission_progress().2, MissionState::Complete);
}

#[test]
fn a_current_item_set_onto_a_do_jump_resolves_it_and_the_mission_goes_on() {
    let mut s = flown(jump_mission());
    assert!(s.fly_until(60.0, |s| s.c.mission_progress().0 == 2));
    s.events.clear();
    assert_eq!(
        s.request(Request::SetMissionCurrent {
            seq: Some(3),
            reset: false
        }),
        Outcome::Accepted
    );
    assert!(s.until_disarmed(300.0), "{:?}", s.events);
    // Jumped back to 1 (its one repeat), then past the jump the second time.
    assert_eq!(reached(&s), vec![1, 2, 4, 5]);
    assert_eq!(
        s.request(Request::SetMissionCurrent {
            seq: Some(6),
            reset: false
        }),
        Outcome::Denied("Mission: no item 6 (the mission has 6)".into())
    );
}

#[test]
fn a_jump_for_ever_loops_until_the_current_item_is_moved_past_it() {
    let mut items = jump_mission();
    items[3] = MissionItem::Jump {
        target: 1,
        repeat: None,
    };
    let mut s = flown(items);
    assert!(s.fly_until(200.0, |s| reached(s).iter().filter(|&&i| i == 2).count() >= 3));
    assert_eq!(s.c.mode(), FlightMode::Mission);
    assert_eq!(
        s.request(Request::SetMissionCurrent {
            seq: Some(4),
            reset: false
        }),
        Outcome::Accepted
    );
    assert!(s.until_disarmed(300.0), "{:?}", s.events);
}

#[test]
fn heights_above_home_follow_a_home_moved_in_flight_and_the_waypoint_is_flown_where_it_is_now() {
    let mut s = Script::new(CommanderParams::default());
    let items = vec![
        MissionItem::Takeoff { height_m: 10.0 },
        waypoint(40.0, 0.0),
        waypoint(80.0, 0.0),
        MissionItem::Land { pos_w: None },
    ];
    let mission = Mission {
        above_home: vec![true; items.len()],
        items,
        ..Default::default()
    };
    assert_eq!(s.request(Request::SetMission(mission)), Outcome::Accepted);
    assert_eq!(s.request(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert!(s.fly_until(60.0, |s| s.x.pos_w.x > 20.0), "on the way to item 1");
    // Home moves 3 m down (DO_SET_HOME): the waypoints' heights above home come down with it.
    let home = Vec3::new(0.0, 0.0, 3.0);
    assert_eq!(s.request(Request::SetHome(Some(home))), Outcome::Accepted);
    assert!(s.fly_until(60.0, |s| reached(s).contains(&1)), "{:?}", s.events);
    assert!(
        (s.x.pos_w.z - (3.0 - 5.0)).abs() <= 0.8,
        "reached item 1 at its new height: {:?}",
        s.x.pos_w
    );
    assert!(s.fly_until(60.0, |s| reached(s).contains(&2)));
    assert!(
        (s.x.pos_w - Vec3::new(80.0, 0.0, -2.0)).norm() <= 1.5,
        "{:?}",
        s.x.pos_w
    );
}

#[test]
fn the_run_alone_hands_over_to_a_return_item_and_to_a_hold_after_its_last_item() {
    use crate::guidance::Guidance;
    let p = CommanderParams::default();
    let paths = AutoPaths::new(&p, (None, (None, None)), None, 0.0);
    let x = VehicleState {
        t_s: 0.0,
        pos_w: Vec3::new(0.0, 0.0, -5.0),
        vel_w: Vec3::zeros(),
        r_wb: crate::math::Mat3::identity(),
        omega_b: Vec3::zeros(),
    };
    let at = |t_s| Moment {
        x: &x,
        yaw_rad: 0.0,
        dt_s: 0.01,
        t_s,
    };
    let hold = MissionFlight {
        guidance: Guidance::Hold {
            pos_w: x.pos_w,
            yaw_rad: 0.0,
        },
        takeoff_target_w: None,
        climbing_out: false,
    };
    let mut run = MissionRun::default();
    assert_eq!(run.progress(), (0, 0, MissionState::NoMission));
    let items = vec![MissionItem::ChangeSpeed { speed_m_s: 2.0 }, MissionItem::ReturnToLaunch];
    run.replace(Mission {
        items,
        ..Default::default()
    });
    assert_eq!(run.progress(), (0, 2, MissionState::NotStarted));
    run.start();
    let mut events = Vec::new();
    let (flight, then) = run.advance(&paths, true, hold, at(0.0), &mut events);
    assert_eq!((flight, then), (hold, None), "a speed change flies nothing");
    assert_eq!(events, vec![Event::MissionItemReached(0), Event::MissionCurrent(1)]);
    let (_, then) = run.advance(&paths, true, hold, at(0.01), &mut events);
    assert_eq!(then, Some(FlightMode::ReturnToLaunch));
    assert_eq!(events.last(), Some(&Event::MissionItemReached(1)));
    assert_eq!(run.progress(), (1, 2, MissionState::Complete));
    assert!(run.start_at(0) && !run.start_at(2));
    assert_eq!(run.progress(), (0, 2, MissionState::NotStarted));
    run.start();
    run.pause();
    assert_eq!(run.progress(), (0, 2, MissionState::Paused));
    run.replace(Mission {
        items: vec![MissionItem::ChangeSpeed { speed_m_s: 2.0 }],
        ..Default::default()
    });
    run.start();
    let (_, then) = run.advance(&paths, true, hold, at(0.02), &mut events);
    assert_eq!(then, Some(FlightMode::Loiter), "after the last item: a hold");
    assert_eq!(run.progress(), (0, 1, MissionState::Complete));
}
