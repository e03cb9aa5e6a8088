//! The failsafes on a scripted vehicle and the failsafe state alone: geofence and battery,
//! motor failures, GCS link loss, the `COM_FAIL_ACT_T` hold.

use super::super::script::Script;
use super::super::FailsafeCause;
use super::super::{BatteryParams, Event, FailsafeParams, GeofenceAction, LowBatteryAction, Outcome, Request};
use super::*;
use crate::guidance::{Mission, MissionItem};
use crate::math::Vec3;

fn failsafe_starting(s: &Script, prefix: &str) -> bool {
    s.events
        .iter()
        .any(|e| matches!(e, Event::Failsafe(_, t) if t.starts_with(prefix)))
}

/// A vehicle whose geofence (10 m around home) holds on a breach.
fn fenced() -> Script {
    Script::new(CommanderParams {
        failsafe: FailsafeParams {
            geofence_action: GeofenceAction::Hold,
            geofence_max_hor_m: 10.0,
            ..Default::default()
        },
        ..Default::default()
    })
}

/// Flies until the breach, then checks the vehicle holds where it happened.
fn holds_after_breach(s: &mut Script) {
    assert!(s.fly_until(20.0, |s| s.c.geofence_breached()));
    let breached_at = s.x.pos_w;
    assert!(failsafe_starting(s, "Geofence breached"), "{:?}", s.events);
    s.fly(10.0);
    assert!((s.x.pos_w - breached_at).norm() < 1e-9, "holds: {:?}", s.x.pos_w);
    assert!(s.x.pos_w.x < 10.1);
}

#[test]
fn a_geofence_breach_holds_where_it_happened() {
    let mut s = fenced();
    // A mission leg out through the fence.
    let leg = MissionItem::Waypoint {
        pos_w: Vec3::new(30.0, 0.0, -3.0),
        hold_s: 0.0,
        accept_m: Some(0.5),
        yaw_rad: None,
    };
    let mission = Mission {
        items: vec![leg],
        ..Default::default()
    };
    assert_eq!(s.request(Request::SetMission(mission)), Outcome::Accepted);
    assert_eq!(s.request(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    s.events.clear();
    holds_after_breach(&mut s);
    assert!(
        s.events.contains(&Event::ModeChanged(FlightMode::Loiter)),
        "{:?}",
        s.events
    );
}

#[test]
fn a_geofence_hold_stops_a_reposition_already_holding_mode() {
    let mut s = fenced();
    s.airborne(3.0);
    let out = Request::Reposition {
        north_m: Some(30.0),
        east_m: None,
        down_m: None,
        yaw_rad: None,
        speed_m_s: None,
        change_mode: false,
    };
    assert_eq!(s.request(out), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    holds_after_breach(&mut s);
}

#[test]
fn a_geofence_hold_leaves_goto_for_the_hold() {
    let mut s = fenced();
    s.airborne(3.0);
    let out = Request::Reposition {
        north_m: Some(30.0),
        east_m: Some(0.0),
        down_m: None,
        yaw_rad: None,
        speed_m_s: None,
        change_mode: true,
    };
    assert_eq!(s.request(out), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::Goto);
    holds_after_breach(&mut s);
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    assert!(s.events.contains(&Event::ModeChanged(FlightMode::Loiter)));
}

#[test]
fn a_critical_battery_lands_with_com_low_bat_act_land() {
    let mut s = Script::new(CommanderParams {
        failsafe: FailsafeParams {
            low_battery_action: LowBatteryAction::Land,
            ..Default::default()
        },
        battery: BatteryParams {
            capacity_mah: 100.0,
            cells: 3,
        },
        ..Default::default()
    });
    // 3996 J at 200 W: low after 17 s, critical after 18.6 s.
    s.power_w = 200.0;
    s.airborne(3.0);
    assert!(s.fly_until(30.0, |s| s.c.mode() == FlightMode::Land), "{:?}", s.events);
    assert!(failsafe_starting(&s, "Low battery"));
    assert!(failsafe_starting(&s, "Critical battery"));
    assert_eq!(s.events.last(), Some(&Event::ModeChanged(FlightMode::Land)));
    assert!(s.until_disarmed(30.0), "landed and disarmed");
}

fn loss(rotor: usize, also_off: Option<usize>, allocation: LossAllocation) -> RotorLoss {
    RotorLoss {
        rotor,
        also_off,
        allocation,
    }
}

#[test]
fn a_motor_failure_is_announced_and_flown_on_by_default() {
    let mut s = Script::new(CommanderParams::default());
    let on_ground = s.c.rotor_failed(loss(3, None, LossAllocation::Impossible), &s.x, 0.0);
    assert_eq!(
        on_ground,
        vec![Event::Failsafe(
            FailsafeCause::Other,
            "Motor 3 failed, no allocation left".into()
        )]
    );
    s.airborne(4.0);
    let (t, mode) = (s.t(), s.c.mode());
    let yaw_lost = LossAllocation::Around(FailedRotors::YawUncontrolled);
    let events = s.c.rotor_failed(loss(1, Some(4), yaw_lost), &s.x, t);
    assert_eq!(
        events,
        vec![Event::Failsafe(
            FailsafeCause::Other,
            "Motor 1 failed, motor 4 off, yaw lost".into()
        )],
        "COM_ACT_FAIL_ACT 0: a warning only"
    );
    assert_eq!(s.c.mode(), mode, "flies on");
    assert!(s.c.armed());
}

#[test]
fn com_act_fail_act_holds_lands_returns_or_terminates_in_flight() {
    let full = LossAllocation::Around(FailedRotors::FullControl);
    for (action, text, expect) in [
        (
            ActuatorFailureAction::Hold,
            "Motor 2 failed: holding",
            Some(FlightMode::Loiter),
        ),
        (
            ActuatorFailureAction::Land,
            "Motor 2 failed: landing",
            Some(FlightMode::Land),
        ),
        (
            ActuatorFailureAction::Return,
            "Motor 2 failed: returning",
            Some(FlightMode::ReturnToLaunch),
        ),
        (ActuatorFailureAction::Terminate, "Motor 2 failed: terminating", None),
    ] {
        let mut s = Script::new(CommanderParams {
            actuator_failure_action: action,
            fail_action_delay_s: 0.0,
            ..Default::default()
        });
        s.airborne(4.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
        let t = s.t();
        let events = s.c.rotor_failed(loss(2, None, full), &s.x, t);
        assert_eq!(
            events.first(),
            Some(&Event::Failsafe(FailsafeCause::Other, text.into())),
            "{action:?}"
        );
        match expect {
            Some(mode) => assert_eq!(s.c.mode(), mode, "{action:?}"),
            None => {
                assert!(!s.c.armed(), "terminated");
                assert_eq!(events.last(), Some(&Event::Disarmed("flight termination")));
            }
        }
    }
    // A landing is never turned into a return; the return waits out COM_FAIL_ACT_T in a hold.
    let mut s = Script::new(CommanderParams {
        actuator_failure_action: ActuatorFailureAction::Return,
        ..Default::default()
    });
    s.airborne(4.0);
    let t = s.t();
    s.c.rotor_failed(loss(2, None, full), &s.x, t);
    assert_eq!(s.c.mode(), FlightMode::Loiter, "COM_FAIL_ACT_T hold first");
    assert!(s.fly_until(6.0, |s| s.c.mode() == FlightMode::ReturnToLaunch));
    assert_eq!(s.request(Request::SetMode(FlightMode::Land)), Outcome::Accepted);
    let t = s.t();
    let again = s.c.rotor_failed(loss(3, None, LossAllocation::Unchanged), &s.x, t);
    assert_eq!(
        again,
        vec![Event::Failsafe(
            FailsafeCause::Other,
            "Motor 3 failed: returning".into()
        )]
    );
    assert_eq!(s.c.mode(), FlightMode::Land, "still landing");
    assert!(s.until_disarmed(30.0));
}

#[test]
fn gcs_link_loss_runs_nav_dll_act_in_flight_and_announces_it_on_the_next_tick() {
    for (action, expect) in [
        (LinkLossAction::Disabled, Some(FlightMode::Position)),
        (LinkLossAction::Hold, Some(FlightMode::Loiter)),
        (LinkLossAction::Return, Some(FlightMode::ReturnToLaunch)),
        (LinkLossAction::Land, Some(FlightMode::Land)),
        (LinkLossAction::Terminate, None),
        (LinkLossAction::Disarm, None),
    ] {
        let mut s = Script::new(CommanderParams {
            link_loss_action: action,
            fail_action_delay_s: 0.0,
            ..Default::default()
        });
        assert_eq!(s.request(Request::GcsLinkLost), Outcome::Accepted);
        assert!(s.step().is_empty(), "on the ground: nothing ({action:?})");
        s.airborne(3.0);
        assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
        assert_eq!(s.request(Request::GcsLinkLost), Outcome::Accepted, "{action:?}");
        match expect {
            Some(mode) => assert_eq!(s.c.mode(), mode, "{action:?}"),
            None => assert!(!s.c.armed(), "{action:?}"),
        }
        let announced = s.step();
        if action == LinkLossAction::Disabled {
            assert!(announced.is_empty());
        } else {
            assert_eq!(
                announced.first(),
                Some(&Event::Failsafe(FailsafeCause::GcsLink, loss_text("GCS link", action)))
            );
        }
        assert!(s.step().iter().all(|e| !matches!(e, Event::Failsafe(..))), "once");
    }
}

#[test]
fn a_failsafe_waits_com_fail_act_t_in_a_hold_unless_landing_or_on_the_ground() {
    let mut f = FailsafeState::default();
    let rtl = FlightMode::ReturnToLaunch;
    assert_eq!(
        f.fail_to(rtl, FlightMode::Mission, false, 0.0, 5.0),
        FailTo::Now,
        "on the ground"
    );
    assert_eq!(f.fail_to(rtl, FlightMode::Land, true, 0.0, 5.0), FailTo::Now, "landing");
    assert_eq!(
        f.fail_to(rtl, FlightMode::Mission, true, 0.0, 0.05),
        FailTo::Now,
        "no delay"
    );
    assert!(!f.delayed());
    assert_eq!(
        f.fail_to(rtl, FlightMode::Takeoff, true, 10.0, 5.0),
        FailTo::Delayed { hold: false },
        "a take-off climbs on"
    );
    assert!(f.delayed());
    assert_eq!(
        f.fail_to(FlightMode::Land, FlightMode::Loiter, true, 11.0, 5.0),
        FailTo::Retargeted
    );
    assert_eq!(f.due(14.99), None);
    assert_eq!(
        f.due(15.0),
        Some(FlightMode::Land),
        "the later failsafe's mode, the first one's time"
    );
    assert!(!f.delayed() && f.due(20.0).is_none());
}

#[test]
fn a_cancelled_failsafe_gives_back_the_pilots_mode_from_the_hold() {
    let mut f = FailsafeState::default();
    let rtl = FlightMode::ReturnToLaunch;
    assert_eq!(f.cancel(FlightMode::Loiter), None, "nothing waiting");
    assert_eq!(
        f.fail_to(rtl, FlightMode::Position, true, 0.0, 5.0),
        FailTo::Delayed { hold: true }
    );
    assert_eq!(f.cancel(FlightMode::Loiter), Some(FlightMode::Position));
    assert!(!f.delayed());
    f.fail_to(rtl, FlightMode::Loiter, true, 0.0, 5.0);
    assert_eq!(f.cancel(FlightMode::Loiter), None, "it held already");
    f.fail_to(rtl, FlightMode::Position, true, 0.0, 5.0);
    f.give_way();
    assert_eq!(f.cancel(FlightMode::Loiter), None, "a mode chosen meanwhile");
}

#[test]
fn com_act_fail_act_never_turns_a_landing_into_a_hold_or_a_return() {
    use ActuatorFailureAction as A;
    let land = FlightMode::Land;
    assert_eq!(A::Hold.reaction(FlightMode::Position), Reaction::Hold);
    assert_eq!(A::Hold.reaction(FlightMode::Loiter), Reaction::Nothing);
    assert_eq!(A::Hold.reaction(land), Reaction::Nothing);
    assert_eq!(A::Return.reaction(land), Reaction::Nothing);
    assert_eq!(A::Return.reaction(FlightMode::ReturnToLaunch), Reaction::Nothing);
    assert_eq!(A::Land.reaction(FlightMode::Mission), Reaction::FailTo(land));
    assert_eq!(A::Terminate.reaction(land), Reaction::Terminate);
    let yaw_lost = loss(1, Some(4), LossAllocation::Around(FailedRotors::YawUncontrolled));
    assert_eq!(
        yaw_lost.announcement(A::Return, true),
        "Motor 1 failed, motor 4 off, yaw lost: returning"
    );
    assert_eq!(
        yaw_lost.announcement(A::Return, false),
        "Motor 1 failed, motor 4 off, yaw lost"
    );
}
