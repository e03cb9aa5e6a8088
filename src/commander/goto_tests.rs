use super::super::script::Script;
use super::super::{CommanderParams, Event, FlightMode, Outcome, Request};
use super::RepositionAction;
use crate::math::{euler_zyx, Vec3};

/// DO_REPOSITION to north/east [m], `down_m` and `yaw_rad` when given; `change_mode` the flag.
fn to(north_m: f64, east_m: f64, down_m: Option<f64>, yaw_rad: Option<f64>, change_mode: bool) -> Request {
    at_speed(north_m, east_m, down_m, yaw_rad, None, change_mode)
}

/// [`to`] at `speed_m_s` [m/s].
fn at_speed(
    north_m: f64,
    east_m: f64,
    down_m: Option<f64>,
    yaw_rad: Option<f64>,
    speed_m_s: Option<f64>,
    change_mode: bool,
) -> Request {
    Request::Reposition {
        north_m: Some(north_m),
        east_m: Some(east_m),
        down_m,
        yaw_rad,
        speed_m_s,
        change_mode,
    }
}

/// DO_REPOSITION without a position: `down_m` and `yaw_rad` when given.
fn only(down_m: Option<f64>, yaw_rad: Option<f64>, change_mode: bool) -> Request {
    Request::Reposition {
        north_m: None,
        east_m: None,
        down_m,
        yaw_rad,
        speed_m_s: None,
        change_mode,
    }
}

fn horizontal_speed(s: &Script) -> f64 {
    s.x.vel_w.xy().norm()
}

#[test]
fn the_mode_change_flag_decides_between_goto_hold_and_a_refusal_as_px4s_commander() {
    use FlightMode::*;
    use RepositionAction as A;
    let cases = [
        // (mode, flag, horizontal target, height or heading) → action
        (Loiter, true, true, false, A::Goto),
        (Mission, true, true, true, A::Goto),
        (Goto, true, false, true, A::Goto),
        (Goto, true, false, false, A::Hold),
        (Loiter, true, false, true, A::Hold),
        (Mission, true, false, false, A::Hold),
        (Loiter, false, true, false, A::InHold),
        (Loiter, false, false, false, A::InHold),
        (Goto, false, true, false, A::Goto),
        (Mission, false, true, false, A::Refused),
        (Position, false, false, true, A::Refused),
    ];
    for (mode, flag, horizontal, other, action) in cases {
        assert_eq!(
            RepositionAction::decide(mode, flag, horizontal, other),
            action,
            "{mode:?} flag {flag} horizontal {horizontal} height/heading {other}"
        );
    }
}

#[test]
fn a_reposition_with_the_flag_flies_to_the_target_in_goto_and_holds_there_staying_in_goto() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(
        s.request(to(5.0, 0.0, None, None, true)),
        Outcome::TemporarilyRejected("Reposition refused: not flying".into())
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    s.airborne(3.0);
    assert_eq!(s.request(to(30.0, 40.0, Some(-6.0), None, true)), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    let mut fastest: f64 = 0.0;
    assert!(s.fly_until(40.0, |s| {
        fastest = fastest.max(horizontal_speed(s));
        (s.x.pos_w - Vec3::new(30.0, 40.0, -6.0)).norm() < 1e-6
    }));
    assert!((fastest - 5.0).abs() < 1e-6, "MPC_XY_CRUISE: {fastest} m/s");
    // The heading turned towards the target (MPC_YAW_MODE 0), none given.
    let bearing = 40f64.atan2(30.0);
    assert!((euler_zyx(&s.x.r_wb).z - bearing).abs() < 1e-3);
    // Then it holds there, in GOTO, without announcing a mode change.
    let events = s.fly(10.0);
    assert!(events.is_empty(), "{events:?}");
    assert_eq!(s.c.mode(), FlightMode::Goto);
    assert!((s.x.pos_w - Vec3::new(30.0, 40.0, -6.0)).norm() < 1e-6);
    // A heading given is flown; a short hop keeps the heading it has.
    assert_eq!(s.request(to(30.0, 41.0, None, Some(-1.0), true)), Outcome::Accepted);
    s.fly(10.0);
    assert!((euler_zyx(&s.x.r_wb).z + 1.0).abs() < 1e-6);
    assert_eq!(s.request(to(31.0, 41.0, None, None, true)), Outcome::Accepted);
    s.fly(10.0);
    assert!((s.x.pos_w - Vec3::new(31.0, 41.0, -6.0)).norm() < 1e-6);
    assert!((euler_zyx(&s.x.r_wb).z + 1.0).abs() < 1e-6, "within NAV_ACC_RAD");
}

#[test]
fn without_the_flag_hold_flies_there_in_hold_goto_retargets_and_other_modes_refuse() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(3.0);
    assert_eq!(
        s.request(to(10.0, -5.0, Some(-6.0), Some(1.0), false)),
        Outcome::Accepted
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    s.fly(20.0);
    assert!(
        (s.x.pos_w - Vec3::new(10.0, -5.0, -6.0)).norm() < 1e-6,
        "{:?}",
        s.x.pos_w
    );
    assert!((euler_zyx(&s.x.r_wb).z - 1.0).abs() < 1e-6);
    // Unset coordinates keep the current ones.
    let north_only = Request::Reposition {
        north_m: Some(0.0),
        east_m: None,
        down_m: None,
        yaw_rad: None,
        speed_m_s: None,
        change_mode: false,
    };
    assert_eq!(s.request(north_only), Outcome::Accepted);
    s.fly(20.0);
    assert!(
        (s.x.pos_w - Vec3::new(0.0, -5.0, -6.0)).norm() < 1e-6,
        "{:?}",
        s.x.pos_w
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    // In GOTO a target without the flag is GOTO's new target, flown on without a stop.
    assert_eq!(s.request(to(60.0, -5.0, None, None, true)), Outcome::Accepted);
    s.fly(6.0);
    let before = horizontal_speed(&s);
    assert_eq!(s.request(to(80.0, -5.0, None, None, false)), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    let mut slowest = before;
    assert!(s.fly_until(60.0, |s| {
        if s.x.pos_w.x < 70.0 {
            slowest = slowest.min(horizontal_speed(s));
        }
        (s.x.pos_w.x - 80.0).abs() < 1e-6
    }));
    assert!(
        before > 4.9 && slowest > 4.9,
        "flown on: {before} m/s, then at least {slowest} m/s"
    );
    // Any other mode refuses it.
    assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    assert_eq!(
        s.request(to(0.0, 0.0, None, None, false)),
        Outcome::Denied("Reposition refused: no mode change asked in POSCTL".into())
    );
    assert_eq!(s.c.mode(), FlightMode::Position);
}

#[test]
fn hold_here_pauses_a_goto_where_it_is_and_a_height_alone_keeps_gotos_target() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(5.0);
    assert_eq!(s.request(to(100.0, 0.0, None, None, true)), Outcome::Accepted);
    s.fly(10.0);
    // A height alone (with the flag) in GOTO: GOTO climbs and keeps its target's north and east.
    assert_eq!(s.request(only(Some(-8.0), None, true)), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    s.fly(5.0);
    let paused_at = s.x.pos_w;
    assert!(paused_at.x > 40.0 && paused_at.x < 90.0, "{paused_at:?}");
    // Every coordinate unset with the flag: a pause, held in AUTO.LOITER where the vehicle is.
    assert_eq!(s.request(only(None, None, true)), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    s.fly(10.0);
    assert!((s.x.pos_w - paused_at).norm() < 1e-6, "held at {:?}", s.x.pos_w);
    // GOTO again: to the old target's north and east at the height asked.
    assert_eq!(s.request(to(100.0, 0.0, Some(-8.0), None, true)), Outcome::Accepted);
    assert!(s.fly_until(60.0, |s| (s.x.pos_w - Vec3::new(100.0, 0.0, -8.0)).norm() < 1e-6));
    // A height alone in AUTO.LOITER holds there, in AUTO.LOITER.
    assert_eq!(s.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
    assert_eq!(s.request(only(Some(-4.0), None, true)), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    s.fly(10.0);
    assert!(
        (s.x.pos_w - Vec3::new(100.0, 0.0, -4.0)).norm() < 1e-6,
        "{:?}",
        s.x.pos_w
    );
}

#[test]
fn do_change_speed_in_goto_applies_at_once_within_mpc_xy_cruise_and_a_new_target_forgets_it() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(3.0);
    assert_eq!(s.request(to(300.0, 0.0, None, None, true)), Outcome::Accepted);
    s.fly(5.0);
    assert!((horizontal_speed(&s) - 5.0).abs() < 1e-6);
    assert_eq!(s.request(Request::ChangeSpeed(2.0)), Outcome::Accepted);
    // Slowed within a second (MPC_ACC_HOR 3 m/s² from 5 m/s), then 2 m/s on; still GOTO.
    s.fly(1.1);
    assert!(
        (horizontal_speed(&s) - 2.0).abs() < 1e-6,
        "{} m/s",
        horizontal_speed(&s)
    );
    s.fly(5.0);
    assert!((horizontal_speed(&s) - 2.0).abs() < 1e-6);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    // Faster than MPC_XY_CRUISE is not flown in GOTO.
    assert_eq!(s.request(Request::ChangeSpeed(10.0)), Outcome::Accepted);
    s.fly(5.0);
    assert!(
        (horizontal_speed(&s) - 5.0).abs() < 1e-6,
        "{} m/s",
        horizontal_speed(&s)
    );
    assert_eq!(s.request(Request::ChangeSpeed(2.0)), Outcome::Accepted);
    s.fly(5.0);
    // A new target without a speed flies at MPC_XY_CRUISE again; one with a speed at that.
    assert_eq!(s.request(to(400.0, 0.0, None, None, false)), Outcome::Accepted);
    s.fly(5.0);
    assert!(
        (horizontal_speed(&s) - 5.0).abs() < 1e-6,
        "{} m/s",
        horizontal_speed(&s)
    );
    let slow = at_speed(500.0, 0.0, None, None, Some(1.5), true);
    assert_eq!(s.request(slow), Outcome::Accepted);
    s.fly(5.0);
    assert!(
        (horizontal_speed(&s) - 1.5).abs() < 1e-6,
        "{} m/s",
        horizontal_speed(&s)
    );
}

#[test]
fn a_slow_goto_accelerates_at_mpc_acc_hor_scaled_by_its_speed() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(3.0);
    let slow = at_speed(50.0, 0.0, None, None, Some(2.0), true);
    assert_eq!(s.request(slow), Outcome::Accepted);
    // 3 m/s² · 2 / 5 = 1.2 m/s²: 2 m/s after 1.67 s.
    s.fly(1.0);
    assert!(
        (horizontal_speed(&s) - 1.2).abs() < 0.02,
        "{} m/s",
        horizontal_speed(&s)
    );
    s.fly(1.0);
    assert!((horizontal_speed(&s) - 2.0).abs() < 1e-6);
}

#[test]
fn goto_chosen_without_a_target_holds_and_a_disarm_leaves_it() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(
        s.request(Request::SetMode(FlightMode::Goto)),
        Outcome::TemporarilyRejected("Mode GOTO: not in the air".into())
    );
    s.airborne(3.0);
    assert_eq!(s.request(to(0.0, 30.0, None, None, true)), Outcome::Accepted);
    s.fly(3.0);
    assert_eq!(s.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
    s.fly(5.0);
    let here = s.x.pos_w;
    // PX4's Goto entered without a fresh target holds (it never flies back to an old one).
    assert_eq!(s.request(Request::SetMode(FlightMode::Goto)), Outcome::Accepted);
    s.fly(5.0);
    assert!((s.x.pos_w - here).norm() < 1e-6, "{:?}", s.x.pos_w);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    // Landing from GOTO; the disarm leaves GOTO for AUTO.LOITER.
    assert_eq!(s.request(Request::Land), Outcome::Accepted);
    assert!(s.until_disarmed(60.0));
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    assert!(s.events.contains(&Event::Disarmed("landed")));
}

#[test]
fn goto_keeps_mpc_xy_vel_max_which_caps_mpc_xy_cruise() {
    let mut params = CommanderParams::default();
    params.motion.horizontal_m_s = 2.0;
    let mut s = Script::new(params);
    s.airborne(3.0);
    assert_eq!(
        s.request(at_speed(20.0, 0.0, None, None, Some(10.0), true)),
        Outcome::Accepted
    );
    // At MPC_XY_CRUISE capped to 2 m/s the acceleration is MPC_ACC_HOR's whole 3 m/s².
    s.fly(0.5);
    assert!(
        (horizontal_speed(&s) - 1.5).abs() < 0.05,
        "{} m/s",
        horizontal_speed(&s)
    );
    let mut fastest: f64 = 0.0;
    assert!(s.fly_until(30.0, |s| {
        fastest = fastest.max(horizontal_speed(s));
        (s.x.pos_w.x - 20.0).abs() < 1e-6
    }));
    assert!((fastest - 2.0).abs() < 1e-9, "{fastest} m/s");
}

#[test]
fn a_target_fills_its_unset_coordinates_from_a_base_and_heads_for_itself_while_far() {
    use super::RepositionTarget;
    let x = crate::control::VehicleState {
        t_s: 0.0,
        pos_w: Vec3::new(0.0, 0.0, -5.0),
        vel_w: Vec3::zeros(),
        r_wb: crate::math::Mat3::identity(),
        omega_b: Vec3::zeros(),
    };
    let east = RepositionTarget {
        ned_m: [None, Some(10.0), None],
        yaw_rad: None,
        speed_m_s: None,
    };
    assert!(east.horizontal() && !east.height_or_heading());
    let to = east.point_from(x.pos_w).expect("finite");
    assert_eq!(to, Vec3::new(0.0, 10.0, -5.0));
    assert!((east.goto_heading(to, None, &x, 2.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert_eq!(
        east.goto_heading(x.pos_w, None, &x, 2.0),
        0.0,
        "there: the vehicle's heading"
    );
    let bad = RepositionTarget {
        ned_m: [Some(f64::INFINITY), None, None],
        ..east
    };
    assert_eq!(
        bad.point_from(x.pos_w),
        Err(Outcome::Denied("Reposition refused: bad target".into()))
    );
}
