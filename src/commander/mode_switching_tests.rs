//! Mode switches on a scripted vehicle: take-off, its speeds, landing, the modes that need
//! something to fly.

use super::super::script::{Script, GROUND_Z_M};
use super::super::{CommanderParams, Event, FlightMode, LandedState, Outcome, Request};
use crate::math::Vec3;

#[test]
fn takeoff_climbs_to_its_height_then_holds_there_in_auto_loiter() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::Takeoff { height_m: Some(5.0) }), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Takeoff);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert!(s.fly_until(10.0, |s| s.c.landed_state() == LandedState::Takeoff));
    assert!(s.fly_until(20.0, |s| s.c.mode() == FlightMode::Loiter));
    assert!((s.x.pos_w - Vec3::new(0.0, 0.0, -5.0)).norm() < 0.2, "{:?}", s.x.pos_w);
    assert_eq!(s.c.landed_state(), LandedState::InAir);
    let airborne = s.events.iter().position(|e| *e == Event::Airborne);
    let loiter = s
        .events
        .iter()
        .position(|e| *e == Event::ModeChanged(FlightMode::Loiter));
    assert!(airborne.is_some() && airborne < loiter, "{:?}", s.events);
    // Then it holds the take-off point.
    assert!(s.fly(5.0).is_empty());
    assert!((s.x.pos_w - Vec3::new(0.0, 0.0, -5.0)).norm() < 1e-9);
}

#[test]
fn takeoff_climbs_at_px4s_takeoff_speed_then_at_the_auto_climb_speed() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::Takeoff { height_m: Some(100.0) }), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    let (mut low_peak, mut high_peak, mut acc_peak, mut t) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0);
    while s.c.mode() == FlightMode::Takeoff && t < 120.0 {
        s.step();
        t += super::super::script::DT_S;
        let Some(sp) = s.last.as_ref().and_then(|tick| tick.setpoint) else {
            continue;
        };
        let (height, up) = (GROUND_Z_M - s.x.pos_w.z, -sp.vel_w.unwrap_or_default().z);
        if height < 9.0 {
            low_peak = low_peak.max(up);
            acc_peak = acc_peak.max(-sp.acc_w.unwrap_or_default().z);
        } else {
            high_peak = high_peak.max(up);
        }
    }
    // MPC_TKO_SPEED 1.5 m/s reached in MPC_TKO_RAMP_T 3 s below MPC_LAND_ALT1 10 m, then
    // MPC_Z_V_AUTO_UP 3 m/s: 10 m in ≈ 8 s, 90 m in ≈ 31 s (PX4 SITL: ≈ 40 s to 100 m).
    assert!((low_peak - 1.5).abs() < 0.01, "{low_peak}");
    assert!(acc_peak < 0.5 + 1e-9, "{acc_peak}");
    assert!((high_peak - 3.0).abs() < 0.01, "{high_peak}");
    assert!((36.0..45.0).contains(&t), "took {t} s");
    assert!((s.x.pos_w.z - (GROUND_Z_M - 100.0)).abs() < 0.2, "{:?}", s.x.pos_w);
}

#[test]
fn the_auto_vertical_speeds_are_kept_within_the_caps() {
    let mut s = Script::new(CommanderParams::default());
    s.c.params.auto_vertical.up_m_s = 5.0;
    s.c.params.auto_vertical.down_m_s = 1.0;
    let limits = s.c.paths().limits(5.0);
    assert_eq!(
        (limits.up_m_s, limits.down_m_s),
        (3.0, 1.0),
        "MPC_Z_VEL_MAX_UP caps MPC_Z_V_AUTO_UP"
    );
    s.c.params.auto_vertical.takeoff_ramp_s = 0.0;
    assert_eq!(
        s.c.paths().takeoff_limits(1.0).acc_up_m_s2,
        4.0,
        "no ramp: MPC_ACC_UP_MAX"
    );
    assert_eq!(s.c.paths().takeoff_limits(1.0).up_m_s, 1.5);
    assert_eq!(s.c.paths().takeoff_limits(10.0).up_m_s, 3.0);
}

#[test]
fn land_descends_lands_and_disarms_after_com_disarm_land() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(8.0);
    assert_eq!(
        s.request(Request::Reposition {
            north_m: Some(3.0),
            east_m: Some(-2.0),
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        }),
        Outcome::Accepted
    );
    s.fly(10.0);
    assert_eq!(s.request(Request::Land), Outcome::Accepted);
    assert_eq!(s.c.landed_state(), LandedState::Landing);
    assert!(s.fly_until(60.0, |s| s.c.landed_state() == LandedState::OnGround));
    let landed_s = s.t();
    assert!(s.c.armed() && s.events.contains(&Event::Landed));
    assert!(
        (s.x.pos_w - Vec3::new(3.0, -2.0, GROUND_Z_M)).norm() < 1e-6,
        "lands where it was"
    );
    assert!(s.until_disarmed(5.0));
    let after_s = s.t() - landed_s;
    assert!(
        (after_s - 2.0).abs() < 0.05,
        "COM_DISARM_LAND 2 s, disarmed after {after_s} s"
    );
    assert_eq!(s.events.last(), Some(&Event::Disarmed("landed")));
    assert_eq!(s.c.mode(), FlightMode::Loiter);
}

#[test]
fn mission_and_offboard_need_something_to_fly() {
    let mut s = Script::new(CommanderParams::default());
    let refused = |text: &str| Outcome::TemporarilyRejected(text.into());
    assert_eq!(
        s.request(Request::SetMode(FlightMode::Mission)),
        refused("Mode AUTO.MISSION: no mission")
    );
    assert_eq!(
        s.request(Request::SetMode(FlightMode::Offboard)),
        refused("Mode OFFBOARD: no setpoint stream")
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter);
}

#[test]
fn auto_takeoff_selected_in_the_air_goes_to_mis_takeoff_alt() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(6.0);
    assert_eq!(s.request(Request::SetMode(FlightMode::Takeoff)), Outcome::Accepted);
    assert!(s.fly_until(20.0, |s| s.c.mode() == FlightMode::Loiter));
    assert!((s.x.pos_w.z + 2.5).abs() < 0.2, "MIS_TAKEOFF_ALT: {:?}", s.x.pos_w);
}

#[test]
fn guided_takes_off_in_place_and_stays_in_guided() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::SetMode(FlightMode::Guided)), Outcome::Accepted);
    assert!(
        matches!(s.request(Request::UserTakeoff { height_m: 5.0 }), Outcome::Failed(_)),
        "a GUIDED take-off needs the motors armed"
    );
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert!(
        matches!(s.request(Request::UserTakeoff { height_m: 0.0 }), Outcome::Failed(_)),
        "the target must be above the vehicle"
    );
    assert_eq!(s.request(Request::UserTakeoff { height_m: 5.0 }), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Guided);
    assert!(s.fly_until(20.0, |s| (s.x.pos_w.z + 5.0).abs() < 0.05
        && s.c.landed_state() == LandedState::InAir));
    assert!(s.c.in_air());
    assert!(matches!(
        s.request(Request::UserTakeoff { height_m: 8.0 }),
        Outcome::Failed(_)
    ));
    s.fly(5.0);
    assert_eq!(s.c.mode(), FlightMode::Guided, "{:?}", s.events);
    assert!(
        !s.events.iter().any(|e| matches!(e, Event::ModeChanged(_))),
        "{:?}",
        s.events
    );
    assert!((s.x.pos_w - Vec3::new(0.0, 0.0, -5.0)).norm() < 0.2, "{:?}", s.x.pos_w);
}

#[test]
fn guided_position_targets_persist_and_velocity_targets_stop_when_their_stream_falls_silent() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::SetMode(FlightMode::Guided)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(s.request(Request::UserTakeoff { height_m: 4.0 }), Outcome::Accepted);
    assert!(s.fly_until(20.0, |s| (s.x.pos_w.z + 4.0).abs() < 0.05));
    s.fly(1.0);
    // One position target, never repeated: flown to the end (ArduCopter's never time out).
    let to = Vec3::new(6.0, -3.0, -4.0);
    let goto = crate::control::FlatSetpoint {
        pos_w: Some(to),
        ..Default::default()
    };
    assert_eq!(s.request(Request::offboard(goto)), Outcome::Accepted);
    assert!(s.fly_until(30.0, |s| (s.x.pos_w - to).norm() < 0.05), "{:?}", s.x.pos_w);
    // A velocity target sent once: flown until its stream's loss, then the vehicle stops.
    let east = crate::control::FlatSetpoint {
        vel_w: Some(Vec3::new(0.0, 1.0, 0.0)),
        ..Default::default()
    };
    assert_eq!(s.request(Request::offboard(east)), Outcome::Accepted);
    s.fly(0.5);
    assert!(s.x.vel_w.y > 0.5, "{:?}", s.x.vel_w);
    let loss_s = s.c.params.offboard_loss_s;
    s.fly(loss_s + 0.5);
    let stopped_at = s.x.pos_w;
    s.fly(3.0);
    assert!(
        (s.x.pos_w - stopped_at).norm() < 0.05,
        "holds where it stopped: {:?}",
        s.x.pos_w
    );
    assert!(stopped_at.y > to.y + 0.5, "it moved east first: {stopped_at:?}");
    assert_eq!(s.c.mode(), FlightMode::Guided, "no failsafe in GUIDED: {:?}", s.events);
    assert!(s.c.in_air());
    // CONDITION_YAW turns the hold to its heading and keeps it there.
    assert_eq!(s.request(Request::TurnTo { yaw_rad: 1.5 }), Outcome::Accepted);
    s.fly(5.0);
    let yaw = crate::math::euler_zyx(&s.x.r_wb).z;
    assert!((yaw - 1.5).abs() < 0.01, "{yaw}");
    assert!(
        (s.x.pos_w - stopped_at).norm() < 0.05,
        "turned in place: {:?}",
        s.x.pos_w
    );
    assert!(matches!(
        s.request(Request::SetMode(FlightMode::Loiter)),
        Outcome::Accepted
    ));
    assert!(matches!(
        s.request(Request::TurnTo { yaw_rad: 0.0 }),
        Outcome::Failed(_)
    ));
}

#[test]
fn a_user_takeoff_in_position_mode_climbs_then_holds_on_the_sticks_reference() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(s.request(Request::UserTakeoff { height_m: 6.0 }), Outcome::Accepted);
    assert!(s.fly_until(20.0, |s| (s.x.pos_w.z + 6.0).abs() < 0.05));
    s.fly(5.0);
    assert_eq!(s.c.mode(), FlightMode::Position, "{:?}", s.events);
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 0.0, -6.0)).norm() < 0.2,
        "held the top: {:?}",
        s.x.pos_w
    );
    assert_eq!(s.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
    s.fly(1.0);
    assert!(
        matches!(s.request(Request::UserTakeoff { height_m: 9.0 }), Outcome::Failed(_)),
        "not in BRAKE"
    );
}

#[test]
fn a_guided_target_ends_a_guided_takeoff_at_once() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::SetMode(FlightMode::Guided)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(s.request(Request::UserTakeoff { height_m: 10.0 }), Outcome::Accepted);
    assert!(s.fly_until(20.0, |s| s.x.pos_w.z < -8.0));
    let to = Vec3::new(20.0, 0.0, -9.0);
    let goto = crate::control::FlatSetpoint {
        pos_w: Some(to),
        ..Default::default()
    };
    assert_eq!(s.request(Request::offboard(goto)), Outcome::Accepted);
    s.fly(0.5);
    assert!(s.x.pos_w.x > 0.05, "on its way at once: {:?}", s.x.pos_w);
    assert!(s.fly_until(30.0, |s| (s.x.pos_w - to).norm() < 0.05));
    assert_eq!(s.c.landed_state(), LandedState::InAir, "the take-off is over");
}

#[test]
fn a_guided_lean_climbs_at_its_share_of_the_climb_speed_and_holds_the_height_at_half_thrust() {
    let mut s = Script::new(CommanderParams::default());
    assert_eq!(s.request(Request::SetMode(FlightMode::Guided)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    let lean = |climb| {
        Request::GuidedLean(super::super::Lean {
            roll_rad: 0.0,
            pitch_rad: 0.0,
            yaw_rad: 0.0,
            climb,
        })
    };
    let stream = |s: &mut Script, climb: f64, seconds: f64| {
        for _ in 0..(seconds / super::super::script::DT_S).round() as usize {
            assert_eq!(s.request(lean(climb)), Outcome::Accepted);
            s.step();
        }
    };
    stream(&mut s, 0.4, 3.0);
    let up = s.c.params.auto_vertical.up_m_s;
    assert!((s.x.vel_w.z + 0.4 * up).abs() < 1e-6, "{} at 40 % of {up}", s.x.vel_w.z);
    assert!(s.c.in_air());
    let z = s.x.pos_w.z;
    stream(&mut s, 0.0, 2.0);
    assert!(
        (s.x.pos_w.z - z).abs() < 0.05 * up,
        "half thrust holds the height: {} vs {z}",
        s.x.pos_w.z
    );
    // Silence: the vehicle stops where it is, still in GUIDED.
    s.fly(s.c.params.offboard_loss_s + 1.0);
    let here = s.x.pos_w;
    s.fly(2.0);
    assert!((s.x.pos_w - here).norm() < 0.01 && s.c.mode() == FlightMode::Guided);
}
