//! The commander flies the plant through the flight core: take-off (requested while disarmed, as
//! QGC does), hold, land with touch-down detection and auto-disarm, and return to launch.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::commander::{
    BatteryParams, CommanderParams, Event, FailsafeParams, FlightMode, GeofenceAction, LandedState, LinkLossAction,
    LowBatteryAction, OffboardLossAction, Outcome, Request,
};
use rotorpilot::math::Vec3;

use crate::flight_bench;

use flight_bench::Sim;

#[test]
fn takeoff_hold_land_and_auto_disarm() {
    let mut sim = Sim::new("quad_x", CommanderParams::default());
    assert_eq!(sim.request(Request::Takeoff { height_m: None }), Outcome::Accepted);
    assert_eq!(sim.commander().mode(), FlightMode::Takeoff);
    assert!(!sim.commander().armed());
    assert_eq!(sim.request(Request::Arm { force: false }), Outcome::Accepted);
    // PX4's take-off: 2.5 m at MPC_TKO_SPEED, reached in MPC_TKO_RAMP_T, ≈ 4.6 s.
    sim.run(7.0);
    assert_eq!(sim.commander().mode(), FlightMode::Loiter, "take-off complete → hold");
    assert_eq!(sim.commander().landed_state(), LandedState::InAir);
    assert!(sim.events.contains(&Event::ModeChanged(FlightMode::Loiter)));
    let z = sim.position().z;
    assert!((z + 2.5).abs() < 0.05, "MIS_TAKEOFF_ALT above home: {z}");
    // In the air: plain disarm and a second take-off are refused.
    assert!(matches!(
        sim.request(Request::Disarm { force: false }),
        Outcome::TemporarilyRejected(_)
    ));
    assert!(matches!(
        sim.request(Request::Takeoff { height_m: None }),
        Outcome::TemporarilyRejected(_)
    ));
    assert_eq!(sim.request(Request::Land), Outcome::Accepted);
    assert_eq!(sim.commander().landed_state(), LandedState::Landing);
    sim.run(8.0);
    assert!(sim.events.contains(&Event::Landed));
    assert!(sim.events.contains(&Event::Disarmed("landed")), "{:?}", sim.events);
    assert!(!sim.commander().armed());
    assert!(sim.on_ground());
}

#[test]
fn return_to_launch_climbs_returns_and_lands() {
    // No cone (RTL_CONE_ANG 0): right above home the return still climbs to RTL_RETURN_ALT.
    let params = CommanderParams {
        rtl_return_alt_m: 6.0,
        rtl_cone_rad: 0.0,
        ..Default::default()
    };
    let mut sim = Sim::new("hexa_x", params);
    sim.request(Request::Takeoff { height_m: Some(4.0) });
    sim.request(Request::Arm { force: false });
    sim.run(6.0);
    assert_eq!(sim.request(Request::ReturnToLaunch), Outcome::Accepted);
    let mut top: f64 = 0.0;
    for _ in 0..200 {
        sim.run(0.1);
        top = top.min(sim.position().z);
    }
    assert!((top + 6.0).abs() < 0.1, "climbed to RTL_RETURN_ALT: {top}");
    assert!(!sim.commander().armed(), "landed and disarmed: {:?}", sim.events);
    let p = sim.position();
    assert!(p.x.abs() < 0.05 && p.y.abs() < 0.05);
}

#[test]
fn wrong_state_requests_are_refused_and_idle_arming_times_out() {
    let mut sim = Sim::new("quad_x", CommanderParams::default());
    assert!(matches!(
        sim.request(Request::SetMode(FlightMode::Mission)),
        Outcome::TemporarilyRejected(_)
    ));
    assert!(matches!(
        sim.request(Request::SetMode(FlightMode::Offboard)),
        Outcome::TemporarilyRejected(_)
    ));
    assert!(matches!(
        sim.request(Request::Takeoff { height_m: Some(-1.0) }),
        Outcome::Denied(_)
    ));
    assert_eq!(
        sim.request(Request::Disarm { force: false }),
        Outcome::Accepted,
        "idempotent"
    );
    assert_eq!(sim.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
    assert_eq!(sim.request(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(
        sim.request(Request::Arm { force: false }),
        Outcome::Accepted,
        "idempotent"
    );
    sim.run(10.5);
    assert!(sim.events.contains(&Event::Disarmed("no takeoff")));
    assert!(sim.on_ground());
}

#[test]
fn mission_takeoff_waypoints_and_land() {
    use rotorpilot::commander::MissionState;
    use rotorpilot::guidance::{Mission, MissionItem};

    let mut sim = Sim::new("quad_x", CommanderParams::default());
    assert!(matches!(
        sim.request(Request::SetMode(FlightMode::Mission)),
        Outcome::TemporarilyRejected(_)
    ));
    let wp = |x, y, z, hold_s| MissionItem::Waypoint {
        pos_w: Vec3::new(x, y, z),
        hold_s,
        accept_m: Some(0.3),
        yaw_rad: None,
    };
    let mission = Mission {
        items: vec![
            MissionItem::Takeoff { height_m: 3.0 },
            wp(5.0, 0.0, -3.0, 1.0),
            MissionItem::ChangeSpeed { speed_m_s: 2.0 },
            wp(5.0, 5.0, -4.0, 0.0),
            MissionItem::Land { pos_w: None },
        ],
        ..Default::default()
    };
    assert_eq!(sim.request(Request::SetMission(mission)), Outcome::Accepted);
    assert_eq!(sim.commander().mission_progress(), (0, 5, MissionState::NotStarted));
    assert_eq!(sim.request(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
    assert_eq!(sim.request(Request::Arm { force: false }), Outcome::Accepted);
    let mut top: f64 = 0.0;
    for _ in 0..400 {
        sim.run(0.1);
        top = top.min(sim.position().z);
        if !sim.commander().armed() {
            break;
        }
    }
    let reached = picked(&sim.events, |e| match e {
        Event::MissionItemReached(s) => Some(*s),
        _ => None,
    });
    assert_eq!(reached, vec![0, 1, 2, 3, 4], "{:?}", sim.events);
    assert_eq!(sim.commander().mission_progress().2, MissionState::Complete);
    assert!(!sim.commander().armed(), "landed and disarmed");
    let p = sim.position();
    assert!((p.x - 5.0).abs() < 0.1 && (p.y - 5.0).abs() < 0.1, "{p}");
    assert!((top + 4.0).abs() < 0.1, "{top}");
}

#[test]
fn mission_ending_in_return_to_launch() {
    use rotorpilot::guidance::{Mission, MissionItem};
    let params = CommanderParams {
        rtl_return_alt_m: 5.0,
        ..Default::default()
    };
    let mut sim = Sim::new("quad_x", params);
    let mission = Mission {
        items: vec![
            MissionItem::Takeoff { height_m: 3.0 },
            MissionItem::Waypoint {
                pos_w: Vec3::new(5.0, 0.0, -3.0),
                hold_s: 0.0,
                accept_m: Some(0.5),
                yaw_rad: None,
            },
            MissionItem::ReturnToLaunch,
        ],
        ..Default::default()
    };
    sim.request(Request::SetMission(mission));
    sim.request(Request::SetMode(FlightMode::Mission));
    sim.request(Request::Arm { force: false });
    for _ in 0..600 {
        sim.run(0.1);
        if !sim.commander().armed() {
            break;
        }
    }
    assert!(
        sim.events.contains(&Event::MissionItemReached(2)),
        "{:?}",
        &sim.events[..sim.events.len().min(12)]
    );
    assert!(!sim.commander().armed());
    let p = sim.position();
    assert!(p.x.abs() < 0.1 && p.y.abs() < 0.1, "{p}");
}

#[test]
fn auto_paths_keep_mpc_xy_vel_max_and_mpc_z_vel_max_dn() {
    let mut params = CommanderParams::default();
    params.motion.horizontal_m_s = 2.0;
    params.motion.down_m_s = 0.8;
    let mut sim = Sim::new("quad_x", params);
    sim.request(Request::Takeoff { height_m: Some(6.0) });
    sim.request(Request::Arm { force: false });
    sim.run(11.0);
    // A 10 m/s request is capped at MPC_XY_VEL_MAX; a straight descent keeps MPC_Z_VEL_MAX_DN
    // (flown in AUTO.LOITER: no mode change asked).
    let moves = [(Some(12.0), -6.0, 2.0, 0.0), (None, -2.0, 0.0, 0.8)];
    for (north_m, down_m, horizontal_limit, down_limit) in moves {
        let reposition = Request::Reposition {
            north_m,
            east_m: None,
            down_m: Some(down_m),
            yaw_rad: None,
            speed_m_s: Some(10.0),
            change_mode: false,
        };
        assert_eq!(sim.request(reposition), Outcome::Accepted);
        let (mut horizontal, mut down): (f64, f64) = (0.0, 0.0);
        for _ in 0..150 {
            sim.run(0.1);
            let v = sim.lockstep.plant().truth().vel_w;
            horizontal = horizontal.max(v.xy().norm());
            down = down.max(v.z);
        }
        for (peak, limit, name) in [
            (horizontal, horizontal_limit, "MPC_XY_VEL_MAX"),
            (down, down_limit, "MPC_Z_VEL_MAX_DN"),
        ] {
            if limit > 0.0 {
                assert!(peak < limit * 1.05 && peak > limit * 0.9, "{name}: {peak}");
            }
        }
    }
    let p = sim.position();
    assert!((p.x - 12.0).abs() < 0.05 && (p.z + 2.0).abs() < 0.05, "{p:?}");
}

/// What `pick` takes from each event that it takes anything from, in order.
fn picked<T>(events: &[Event], pick: impl Fn(&Event) -> Option<T>) -> Vec<T> {
    events.iter().filter_map(pick).collect()
}

fn failsafe_texts(events: &[Event]) -> Vec<String> {
    picked(events, |e| match e {
        Event::Failsafe(_, text) => Some(text.clone()),
        _ => None,
    })
}

#[test]
fn geofence_breach_returns_and_lands_at_home() {
    let params = CommanderParams {
        failsafe: FailsafeParams {
            geofence_action: GeofenceAction::Return,
            geofence_max_hor_m: 5.0,
            ..Default::default()
        },
        rtl_return_alt_m: 3.0,
        ..Default::default()
    };
    let mut sim = Sim::new("quad_x", params);
    sim.request(Request::Takeoff { height_m: Some(2.5) });
    sim.request(Request::Arm { force: false });
    sim.run(5.0);
    let reposition = Request::Reposition {
        north_m: Some(9.0),
        east_m: None,
        down_m: None,
        yaw_rad: None,
        speed_m_s: Some(2.0),
        change_mode: true,
    };
    assert_eq!(sim.request(reposition), Outcome::Accepted);
    let mut farthest: f64 = 0.0;
    for _ in 0..300 {
        sim.run(0.1);
        farthest = farthest.max(sim.position().x);
    }
    let texts = failsafe_texts(&sim.events);
    assert_eq!(texts.len(), 1, "{texts:?}");
    assert!(
        texts[0].starts_with("Geofence breached (5.0 m from home"),
        "{}",
        texts[0]
    );
    assert!(sim.events.contains(&Event::ModeChanged(FlightMode::ReturnToLaunch)));
    assert!(farthest < 6.5, "turned back soon after the fence: {farthest}");
    let p = sim.position();
    assert!(p.x.abs() < 0.1 && p.y.abs() < 0.1 && !sim.commander().armed(), "{p:?}");
}

#[test]
fn battery_failsafes_warn_return_then_land() {
    let mut params = CommanderParams::default();
    params.failsafe.low_battery_action = LowBatteryAction::Return;
    // About 12 s of hover for quad_x (≈ 1 kW electrical).
    params.battery = BatteryParams {
        capacity_mah: 300.0,
        cells: 3,
    };
    let mut sim = Sim::new("quad_x", params);
    sim.request(Request::Takeoff { height_m: Some(2.5) });
    sim.request(Request::Arm { force: false });
    sim.run(30.0);
    let texts = failsafe_texts(&sim.events);
    assert_eq!(texts.len(), 3, "{texts:?}");
    assert!(texts[0].starts_with("Low battery: 15%"), "{texts:?}");
    assert!(texts[1].starts_with("Critical battery (7%): returning"), "{texts:?}");
    assert!(texts[2].starts_with("Emergency battery (5%): landing"), "{texts:?}");
    let modes = picked(&sim.events, |e| match e {
        Event::ModeChanged(m) => Some(*m),
        _ => None,
    });
    // COM_FAIL_ACT_T: the return waits 5 s in a hold; the emergency's landing comes first here
    // (a landing is never delayed once the hold is over or the vehicle lands).
    assert!(
        modes.contains(&FlightMode::Loiter) && modes.last() == Some(&FlightMode::Land),
        "{modes:?}"
    );
    assert!(!sim.commander().armed() && sim.on_ground());
    let (gauge, pack) = sim.commander().battery();
    assert!(gauge.fraction(&pack) < 0.05);
}

/// A `quad_x` taken off to 2 m and holding there (AUTO.LOITER).
fn hovering_at_2_m(params: CommanderParams) -> Sim {
    let mut sim = Sim::new("quad_x", params);
    sim.request(Request::Takeoff { height_m: Some(2.0) });
    sim.request(Request::Arm { force: false });
    sim.run(7.0);
    assert_eq!(sim.commander().mode(), FlightMode::Loiter);
    sim
}

#[test]
fn offboard_loss_runs_com_obl_rc_act() {
    use rotorpilot::control::FlatSetpoint;
    // Every action is checked against a scripted vehicle beside the commander; here two of them
    // on the real plant.
    for (action, expect) in [
        (OffboardLossAction::Land, Some(FlightMode::Land)),
        (OffboardLossAction::Disarm, None),
    ] {
        let mut sim = hovering_at_2_m(CommanderParams {
            offboard_loss_action: action,
            ..Default::default()
        });
        let hold = FlatSetpoint {
            pos_w: Some(sim.position()),
            ..Default::default()
        };
        assert_eq!(sim.request(Request::offboard(hold)), Outcome::Accepted);
        assert_eq!(sim.request(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
        sim.run(1.5);
        assert!(sim.events.contains(&Event::OffboardLost), "COM_OBL_RC_ACT {action:?}");
        match expect {
            Some(mode) => assert_eq!(sim.commander().mode(), mode, "COM_OBL_RC_ACT {action:?}"),
            None => assert!(!sim.commander().armed(), "COM_OBL_RC_ACT {action:?} disarms"),
        }
    }
}

#[test]
fn gcs_link_loss_runs_nav_dll_act_in_flight_only() {
    // Every action is checked against a scripted vehicle beside the commander; here the return
    // is flown to the end on the real plant.
    for (action, expect) in [
        (LinkLossAction::Disabled, Some(FlightMode::Position)),
        (LinkLossAction::Return, Some(FlightMode::ReturnToLaunch)),
        (LinkLossAction::Disarm, None),
    ] {
        let params = CommanderParams {
            link_loss_action: action,
            fail_action_delay_s: 0.0,
            ..Default::default()
        };
        let mut sim = Sim::new("quad_x", params);
        assert_eq!(
            sim.request(Request::GcsLinkLost),
            Outcome::Accepted,
            "on the ground: nothing"
        );
        sim.request(Request::Takeoff { height_m: Some(2.0) });
        sim.request(Request::Arm { force: false });
        sim.run(5.0);
        assert_eq!(sim.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
        let outcome = sim.request(Request::GcsLinkLost);
        match expect {
            Some(mode) => assert_eq!(sim.commander().mode(), mode, "NAV_DLL_ACT {action:?}"),
            None => assert!(!sim.commander().armed(), "NAV_DLL_ACT {action:?} disarms"),
        }
        assert_eq!(outcome, Outcome::Accepted);
        // The reaction is announced as an event of the next tick.
        sim.events.clear();
        sim.run(0.001);
        let announced = sim
            .events
            .iter()
            .any(|e| matches!(e, Event::Failsafe(_, t) if t.starts_with("GCS link lost")));
        assert_eq!(announced, action != LinkLossAction::Disabled, "NAV_DLL_ACT {action:?}");
        if action == LinkLossAction::Return {
            // Up to RTL_RETURN_ALT (60 m), back over home, down at MPC_LAND_SPEED, auto-disarm.
            sim.run(200.0);
            assert!(!sim.commander().armed(), "returned, landed and disarmed");
        }
    }
}

#[test]
fn a_landing_that_interrupts_a_return_climb_descends_within_the_speed_limit() {
    // RTL climbing at MPC_Z_V_AUTO_UP towards RTL_RETURN_ALT, then NAV_LAND: the climb is
    // stopped and the descent never exceeds MPC_Z_VEL_MAX_DN (1.5 m/s), as every automatic path.
    let params = CommanderParams {
        rtl_return_alt_m: 40.0,
        rtl_cone_rad: 0.0,
        ..Default::default()
    };
    let max_down = params.motion.down_m_s;
    let mut sim = Sim::new("quad_x", params);
    sim.request(Request::Takeoff { height_m: Some(5.0) });
    sim.request(Request::Arm { force: false });
    sim.run(8.0);
    assert_eq!(sim.request(Request::ReturnToLaunch), Outcome::Accepted);
    while sim.velocity().z > -2.5 {
        sim.run(0.01);
    }
    assert_eq!(sim.request(Request::Land), Outcome::Accepted);
    let (mut fastest_down, mut top) = (0.0_f64, 0.0_f64);
    for _ in 0..6_000 {
        sim.run(0.01);
        fastest_down = fastest_down.max(sim.velocity().z);
        top = top.min(sim.position().z);
        if !sim.commander().armed() {
            break;
        }
    }
    assert!(!sim.commander().armed(), "landed: {:?}", sim.events);
    assert!(
        fastest_down <= max_down * 1.05,
        "descended at {fastest_down:.2} m/s (top {top:.1} m)"
    );
}
