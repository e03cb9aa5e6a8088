//! The stick modes on a scripted vehicle: take-off, flight and landing in POSCTL, the modes'
//! needs, stick loss and its exceptions, a pilot taking over, the attitude modes' targets.

use super::super::script::{Script, DT_S, GROUND_Z_M};
use super::super::FailsafeCause;
use super::super::{CommanderParams, Event, FlightMode, ManualLossAction, Outcome, Request};
use crate::guidance::Sticks;
use crate::math::Vec3;

/// Sends `sticks` every step for `seconds` [s].
fn hold_sticks(s: &mut Script, sticks: Sticks, seconds: f64) {
    for _ in 0..(seconds / DT_S).round() as usize {
        assert_eq!(s.request(Request::ManualControl(sticks)), Outcome::Accepted);
        s.step();
    }
}

fn throttle(t: f64) -> Sticks {
    Sticks {
        throttle: t,
        ..Sticks::CENTRED
    }
}

/// Armed in POSCTL and climbed with the throttle to about `height_m` [m], sticks centred.
fn position_flight(height_m: f64) -> Script {
    let mut s = Script::new(CommanderParams::default());
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    hold_sticks(&mut s, Sticks::CENTRED, 1.0);
    assert!(!s.c.in_air(), "centred throttle on the ground: it waits");
    while -s.x.pos_w.z < height_m {
        hold_sticks(&mut s, throttle(1.0), DT_S);
        assert!(s.t() < 30.0, "climbs");
    }
    hold_sticks(&mut s, Sticks::CENTRED, 3.0);
    assert!(s.c.in_air());
    s
}

#[test]
fn posctl_takes_off_flies_holds_and_lands_on_the_sticks() {
    let mut s = position_flight(5.0);
    let held = s.x.pos_w;
    hold_sticks(&mut s, Sticks::CENTRED, 3.0);
    assert!((s.x.pos_w - held).norm() < 1e-9, "centred sticks hold: {:?}", s.x.pos_w);
    let forward = Sticks {
        pitch: 1.0,
        ..Sticks::CENTRED
    };
    hold_sticks(&mut s, forward, 5.0);
    assert!(
        s.x.vel_w.x > 9.9 && s.x.vel_w.y.abs() < 1e-9,
        "MPC_VEL_MANUAL north: {:?}",
        s.x.vel_w
    );
    hold_sticks(&mut s, Sticks::CENTRED, 6.0);
    let stopped = s.x.pos_w;
    hold_sticks(&mut s, Sticks::CENTRED, 2.0);
    assert!((s.x.pos_w - stopped).norm() < 1e-9 && stopped.x > 40.0, "{stopped:?}");
    assert!((stopped.z - held.z).abs() < 1e-9, "height held while flying");
    s.events.clear();
    assert!(
        {
            let mut landed = false;
            for _ in 0..3000 {
                hold_sticks(&mut s, throttle(0.0), DT_S);
                if !s.c.armed() {
                    landed = true;
                    break;
                }
            }
            landed
        },
        "the throttle down lands and auto-disarms: {:?}",
        s.events
    );
    assert!(s.events.contains(&Event::Landed));
    assert_eq!(s.events.last(), Some(&Event::Disarmed("landed")));
    assert!((s.x.pos_w.z - GROUND_Z_M).abs() < 1e-9);
}

#[test]
fn the_stick_modes_but_posctl_need_sticks_and_manual_thrust_needs_the_throttle_down() {
    let mut s = Script::new(CommanderParams::default());
    let refused = |what: &str| Outcome::TemporarilyRejected(format!("{what}: no manual control input"));
    for mode in [
        FlightMode::Altitude,
        FlightMode::Stabilized,
        FlightMode::Acro,
        FlightMode::Manual,
    ] {
        assert_eq!(
            s.request(Request::SetMode(mode)),
            refused(&format!("Mode {}", mode.name()))
        );
    }
    assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    hold_sticks(&mut s, throttle(0.6), 0.1);
    assert_eq!(s.request(Request::SetMode(FlightMode::Stabilized)), Outcome::Accepted);
    assert_eq!(
        s.request(Request::Arm { force: false }),
        Outcome::TemporarilyRejected("Arming denied: throttle above 20%".into())
    );
    hold_sticks(&mut s, throttle(0.0), 0.1);
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    s.fly(1.0);
    assert_eq!(s.c.mode(), FlightMode::Stabilized, "on the ground: nothing to react to");
}

#[test]
fn rp_arm_checks_0_skips_the_stick_checks_but_not_the_modes_needs() {
    let params = CommanderParams {
        arming_checks: false,
        ..CommanderParams::default()
    };
    let mut s = Script::new(params);
    assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    hold_sticks(&mut s, throttle(0.6), 0.1);
    assert_eq!(s.request(Request::SetMode(FlightMode::Stabilized)), Outcome::Accepted);
    assert_eq!(
        s.request(Request::Arm { force: false }),
        Outcome::Accepted,
        "throttle up: ARMING_CHECK 0"
    );
    assert_eq!(s.request(Request::Disarm { force: true }), Outcome::Accepted);
    assert_eq!(s.request(Request::SetMode(FlightMode::Land)), Outcome::Accepted);
    assert_eq!(
        s.request(Request::Arm { force: false }),
        Outcome::TemporarilyRejected("Arming denied: not in AUTO.LAND".into()),
        "the mode's needs stay (Copter: mode not armable)"
    );
}

#[test]
fn stick_loss_runs_nav_rcl_act_once_and_the_return_of_the_sticks_is_announced() {
    let mut s = position_flight(4.0);
    s.events.clear();
    s.fly(0.4);
    assert_eq!(s.c.mode(), FlightMode::Position, "within COM_RC_LOSS_T");
    s.fly(0.2);
    assert_eq!(
        s.events,
        vec![Event::Failsafe(
            FailsafeCause::Other,
            "Manual control lost: returning".into()
        )],
        "NAV_RCL_ACT 2 by default"
    );
    // COM_FAIL_ACT_T (5 s) in a hold first, then the return.
    assert_eq!(s.c.mode(), FlightMode::Loiter);
    s.fly(1.0);
    assert_eq!(s.events.len(), 1, "once per loss");
    s.fly(4.0);
    assert_eq!(s.c.mode(), FlightMode::ReturnToLaunch);
    assert_eq!(s.events[1], Event::ModeChanged(FlightMode::ReturnToLaunch));
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    assert_eq!(
        s.events[2],
        Event::Failsafe(FailsafeCause::Other, "Manual control regained".into())
    );
    assert_eq!(s.c.mode(), FlightMode::ReturnToLaunch, "the pilot switches back");
}

#[test]
fn sticks_back_within_com_fail_act_t_give_the_pilot_back_the_mode_and_no_return() {
    let mut s = position_flight(4.0);
    s.fly(2.0);
    assert_eq!(s.c.mode(), FlightMode::Loiter, "lost: holding");
    // A stick moved in the hold does not take over (PX4: mode switch only during the delay)...
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    assert!(s
        .events
        .contains(&Event::Failsafe(FailsafeCause::Other, "Manual control regained".into())));
    // ...but the cause is gone: back to POSCTL, and no return comes.
    assert_eq!(s.c.mode(), FlightMode::Position);
    hold_sticks(&mut s, Sticks::CENTRED, 6.0);
    assert_eq!(s.c.mode(), FlightMode::Position, "{:?}", s.events);
}

#[test]
fn com_rcl_except_exempts_hold_and_a_stick_mode_without_an_action_holds() {
    let mut params = CommanderParams::default();
    params.manual.loss_exceptions = 2;
    let mut s = Script::new(params);
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    s.airborne(4.0);
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    s.events.clear();
    s.fly(2.0);
    assert_eq!(
        s.events,
        vec![Event::Failsafe(FailsafeCause::Other, "Manual control lost".into())]
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter, "hold is exempt");

    let mut params = CommanderParams::default();
    params.manual.loss_action = ManualLossAction::Disabled;
    let mut s = Script::new(params);
    s.airborne(4.0);
    hold_sticks(&mut s, Sticks::CENTRED, 0.1);
    assert_eq!(s.request(Request::SetMode(FlightMode::Altitude)), Outcome::Accepted);
    hold_sticks(&mut s, Sticks::CENTRED, 1.0);
    s.events.clear();
    s.fly(1.0);
    assert_eq!(
        s.events[0],
        Event::Failsafe(FailsafeCause::Other, "Manual control lost: holding".into())
    );
    assert_eq!(s.c.mode(), FlightMode::Loiter, "ALTCTL cannot fly without sticks");
}

#[test]
fn a_roll_pitch_or_yaw_stick_takes_over_an_auto_mode_in_posctl() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(4.0);
    hold_sticks(&mut s, throttle(0.9), 1.0);
    assert_eq!(s.c.mode(), FlightMode::Loiter, "the throttle alone does not take over");
    s.events.clear();
    let roll = Sticks {
        roll: 0.5,
        ..Sticks::CENTRED
    };
    hold_sticks(&mut s, roll, 0.05);
    assert_eq!(s.c.mode(), FlightMode::Position);
    assert_eq!(
        s.events,
        vec![
            Event::Failsafe(FailsafeCause::Other, "Pilot took over using sticks".into()),
            Event::ModeChanged(FlightMode::Position)
        ]
    );
    let y = s.x.pos_w.y;
    hold_sticks(&mut s, roll, 1.0);
    assert!(s.x.pos_w.y > y, "and flies east on the roll stick");
}

#[test]
fn stabilized_and_acro_fly_attitude_and_rate_targets_from_the_sticks() {
    let mut s = Script::new(CommanderParams::default());
    s.airborne(4.0);
    let sticks = Sticks {
        roll: 1.0,
        pitch: 0.0,
        yaw: 0.0,
        throttle: 0.5,
    };
    hold_sticks(&mut s, sticks, 0.1);
    assert_eq!(s.request(Request::SetMode(FlightMode::Stabilized)), Outcome::Accepted);
    hold_sticks(&mut s, sticks, 0.1);
    let target = s.last.as_ref().and_then(|t| t.attitude).expect("an attitude target");
    let roll = target.q_wb.map(|q| q.euler_angles().0).unwrap_or_default();
    assert!((roll - 35f64.to_radians()).abs() < 1e-9, "MPC_MAN_TILT_MAX: {roll}");
    assert!((target.thrust_fraction - 0.5).abs() < 1e-12, "MPC_THR_HOVER at centre");
    assert_eq!(s.request(Request::SetMode(FlightMode::Acro)), Outcome::Accepted);
    hold_sticks(&mut s, sticks, 0.1);
    let target = s.last.as_ref().and_then(|t| t.attitude).expect("a rate target");
    assert_eq!(target.q_wb, None);
    assert_eq!(target.omega_b, Some(Vec3::new(100f64.to_radians(), 0.0, 0.0)));
}

#[test]
fn a_loss_is_reported_once_then_the_return_and_exempt_modes_or_the_ground_run_nothing() {
    use super::{ManualInput, StickWatch};
    use crate::commander::LinkLossAction;
    let p = CommanderParams::default().manual;
    let mut m = ManualInput::default();
    assert_eq!(
        m.watch(FlightMode::Loiter, true, &p),
        StickWatch::Quiet,
        "never any sticks"
    );
    m.receive(Sticks::CENTRED, 0.0);
    m.armed_at();
    assert_eq!(
        m.watch(FlightMode::Loiter, true, &p),
        StickWatch::Alive { regained: false }
    );
    // The link's word after COM_RC_LOSS_T of silence (Request::StreamLost).
    m.set_silent();
    assert_eq!(
        m.watch(FlightMode::Loiter, true, &p),
        StickWatch::Lost(LinkLossAction::from(p.loss_action))
    );
    assert_eq!(m.watch(FlightMode::Loiter, true, &p), StickWatch::Quiet, "once");
    m.receive(Sticks::CENTRED, 1.0);
    assert_eq!(
        m.watch(FlightMode::Loiter, true, &p),
        StickWatch::Alive { regained: true }
    );
    m.set_silent();
    assert_eq!(
        m.watch(FlightMode::Stabilized, false, &p),
        StickWatch::Lost(LinkLossAction::Disabled),
        "on the ground: announced only"
    );
}

#[test]
fn arming_in_a_manual_thrust_mode_needs_the_throttle_down() {
    use super::ManualInput;
    let mut m = ManualInput::default();
    assert!(m.mode_refusal(FlightMode::Stabilized, true).is_some(), "no sticks");
    assert_eq!(
        m.mode_refusal(FlightMode::Position, false),
        None,
        "POSCTL holds without"
    );
    m.receive(throttle(0.5), 0.0);
    assert_eq!(
        m.mode_refusal(FlightMode::Stabilized, true),
        Some(Outcome::TemporarilyRejected("Arming denied: throttle above 20%".into()))
    );
    assert_eq!(m.mode_refusal(FlightMode::Stabilized, false), None, "modes");
    m.receive(throttle(0.0), 0.01);
    assert_eq!(m.mode_refusal(FlightMode::Stabilized, true), None);
}
