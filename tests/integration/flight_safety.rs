//! The flight-safety cases real clients hit, flown in-process through the autopilot's own tick
//! (`runtime::vehicle::Vehicle`: commander, land detector, flight core, plant) as the clients fly
//! them: a MAVSDK mission without a take-off item, offboard descents onto the ground, position
//! steps, yaw rates and half-turns of heading in offboard.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::airframe::AirframeSource;
use rotorpilot::commander::{Event, FlightMode, LandedState, Outcome, Request};
use rotorpilot::control::{ControllerKind, FlatSetpoint};
use rotorpilot::guidance::{Home, Mission, MissionItem};
use rotorpilot::math::{wrap_pi, Vec3};
use rotorpilot::runtime::vehicle::{TickOutput, Vehicle};
use rotorpilot::sitl::SensorModel;

const DT: f64 = 1e-3;

fn vehicle(kind: ControllerKind) -> Vehicle {
    let src = AirframeSource::resolve("quad_x").unwrap();
    Vehicle::new(&src, kind, Home::default(), SensorModel::State, 0, DT).unwrap()
}

/// Steps `v` for `seconds`, handing every tick to `each`; the ticks' events.
fn fly(v: &mut Vehicle, seconds: f64, mut each: impl FnMut(&TickOutput)) -> Vec<Event> {
    let mut events = Vec::new();
    for _ in 0..(seconds / DT).round() as usize {
        let out = v.step();
        each(&out);
        events.extend(out.events);
    }
    events
}

/// An offboard position setpoint (MAVSDK `set_position_ned`), optionally with velocity.
fn position(north: f64, east: f64, down: f64, yaw_deg: f64, vel: Option<Vec3>) -> Request {
    Request::OffboardSetpoint {
        setpoint: FlatSetpoint {
            pos_w: Some(Vec3::new(north, east, down)),
            vel_w: vel,
            yaw_rad: Some(yaw_deg.to_radians()),
            ..Default::default()
        },
        body_frame: false,
    }
}

/// Streams `setpoint` at 20 Hz for `seconds` (as MAVSDK does), handing every tick to `each`.
fn stream(v: &mut Vehicle, setpoint: &Request, seconds: f64, mut each: impl FnMut(&TickOutput)) -> Vec<Event> {
    let mut events = Vec::new();
    for _ in 0..(seconds * 20.0).round() as usize {
        assert_eq!(v.apply(setpoint.clone()), Outcome::Accepted);
        events.extend(fly(v, 0.05, &mut each));
    }
    events
}

/// Arms in OFFBOARD with `initial` streaming, as MAVSDK's offboard examples start.
fn start_offboard(v: &mut Vehicle, initial: &Request) {
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    stream(v, initial, 0.2, |_| {});
    assert_eq!(v.apply(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
}

#[test]
fn a_mission_without_takeoff_climbs_first_and_stays_armed_in_the_air() {
    // MAVSDK's mission.py: first item a waypoint 25 m up, 30 m away; started on the ground.
    let mut v = vehicle(ControllerKind::Geometric);
    let mission = Mission {
        items: vec![
            MissionItem::Waypoint {
                pos_w: Vec3::new(30.0, 0.0, -25.0),
                hold_s: 0.0,
                accept_m: Some(1.0),
                yaw_rad: None,
            },
            MissionItem::Land {
                pos_w: Some(Vec3::new(30.0, 0.0, 0.0)),
            },
        ],
        ..Default::default()
    };
    assert_eq!(v.apply(Request::SetMission(mission)), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(v.apply(Request::StartMission { first: 0 }), Outcome::Accepted);
    let (mut max_xy_below_item, mut reached_item) = (0.0_f64, false);
    let mut states = Vec::new();
    let events = fly(&mut v, 90.0, |o| {
        let s = &o.snapshot;
        let height = -s.pos_w.z - 0.1;
        if height > 0.5 {
            assert!(s.armed, "disarmed at {height:.1} m, t = {:.1} s", s.t_s);
            assert_ne!(s.landed, LandedState::OnGround, "on ground at {height:.1} m");
        }
        if height < 24.0 && !reached_item {
            max_xy_below_item = max_xy_below_item.max(s.pos_w.xy().norm());
        }
        reached_item |= (s.pos_w - Vec3::new(30.0, 0.0, -25.0)).norm() < 1.0;
        if states.last() != Some(&s.landed) {
            states.push(s.landed);
        }
    });
    assert!(reached_item, "{events:?}");
    assert!(
        max_xy_below_item < 0.3,
        "did not climb vertically first: {max_xy_below_item} m"
    );
    assert_eq!(
        states,
        [
            LandedState::OnGround,
            LandedState::Takeoff,
            LandedState::InAir,
            LandedState::Landing,
            LandedState::OnGround
        ]
    );
    assert!(events.contains(&Event::Disarmed("landed")), "{events:?}");
    assert!(!events.contains(&Event::Disarmed("no takeoff")));
}

#[test]
fn an_offboard_descent_onto_the_ground_lands_and_disarms() {
    // MAVSDK's offboard_position_ned.py: up to 5 m, over, then a setpoint on the ground.
    let mut v = vehicle(ControllerKind::Geometric);
    start_offboard(&mut v, &position(0.0, 0.0, 0.0, 0.0, None));
    let mut states = Vec::new();
    let mut record = |o: &TickOutput| {
        if states.last() != Some(&o.snapshot.landed) {
            states.push(o.snapshot.landed);
        }
    };
    stream(&mut v, &position(0.0, 0.0, -5.0, 0.0, None), 10.0, &mut record);
    stream(&mut v, &position(5.0, 0.0, -5.0, 90.0, None), 10.0, &mut record);
    let (mut impact, mut disarmed_at, mut landed_at) = (0.0_f64, None, None);
    let events = stream(&mut v, &position(0.0, 10.0, 0.0, 180.0, None), 12.0, |o| {
        let s = &o.snapshot;
        if -s.pos_w.z < 0.15 && landed_at.is_none() {
            impact = impact.max(s.vel_w.z);
        }
        if s.landed == LandedState::OnGround && landed_at.is_none() {
            landed_at = Some(s.t_s);
        }
        if !s.armed && disarmed_at.is_none() {
            disarmed_at = Some(s.t_s);
            assert!(-s.pos_w.z < 0.15, "disarmed in the air");
        }
        record(o);
    });
    assert_eq!(
        states,
        [LandedState::OnGround, LandedState::InAir, LandedState::OnGround]
    );
    assert!(impact < 1.6, "touched down at {impact} m/s");
    let (landed, disarmed) = (landed_at.unwrap(), disarmed_at.unwrap());
    assert!(
        (disarmed - landed - 2.0).abs() < 0.01,
        "COM_DISARM_LAND: {landed} → {disarmed}"
    );
    assert!(events.contains(&Event::Landed) && events.contains(&Event::Disarmed("landed")));
}

#[test]
fn a_fifty_metre_offboard_step_keeps_the_limits_and_does_not_overshoot() {
    // MAVSDK's offboard_position_velocity_ned.py: 10 m up, then 50 m north with 1 m/s ahead.
    for kind in ControllerKind::ALL {
        let mut v = vehicle(kind);
        start_offboard(&mut v, &position(0.0, 0.0, 0.0, 0.0, None));
        let up = position(0.0, 0.0, -10.0, 0.0, Some(Vec3::new(0.0, 0.0, -1.0)));
        stream(&mut v, &up, 10.0, |_| {});
        let (mut peak_speed, mut peak_tilt, mut max_north) = (0.0_f64, 0.0_f64, 0.0_f64);
        let step = position(50.0, 0.0, -10.0, 0.0, Some(Vec3::new(1.0, 0.0, 0.0)));
        stream(&mut v, &step, 25.0, |o| {
            let s = &o.snapshot;
            peak_speed = peak_speed.max(s.vel_w.xy().norm());
            peak_tilt = peak_tilt.max((s.eta.x.cos() * s.eta.y.cos()).acos().to_degrees());
            max_north = max_north.max(s.pos_w.x);
        });
        let name = kind.name();
        // The reference keeps MPC_XY_VEL_MAX exactly; the vehicle tracks it within 7 % (the
        // stiff geometric law catches up its drag lag at 12.5 m/s, the RPY laws at 12.3 m/s).
        assert!(peak_speed <= 12.0 * 1.07, "{name}: MPC_XY_VEL_MAX: {peak_speed} m/s");
        assert!(peak_tilt <= 45.0, "{name}: MPC_TILTMAX_AIR: {peak_tilt}°");
        assert!(max_north < 50.5, "{name}: overshoot to {max_north} m");
        let p = v.step().snapshot.pos_w;
        assert!((p - Vec3::new(50.0, 0.0, -10.0)).norm() < 0.1, "{name}: settled at {p}");
    }
}

/// The heading [rad] of a snapshot.
fn heading(o: &TickOutput) -> f64 {
    o.snapshot.eta.z
}

#[test]
fn yaw_rate_turns_body_velocity_into_circles() {
    // MAVSDK's offboard_velocity_body.py: 5 m/s forward at 30 °/s.
    let mut v = vehicle(ControllerKind::Geometric);
    let body = |forward: f64, down: f64, yaw_rate_deg_s: f64| Request::OffboardSetpoint {
        setpoint: FlatSetpoint {
            vel_w: Some(Vec3::new(forward, 0.0, down)),
            yaw_rate_rad_s: Some(yaw_rate_deg_s.to_radians()),
            ..Default::default()
        },
        body_frame: true,
    };
    start_offboard(&mut v, &body(0.0, 0.0, 0.0));
    stream(&mut v, &body(0.0, -1.0, 60.0), 5.0, |_| {});
    let turned = heading(&{ v.step() });
    // 60 °/s for 5 s: 300°, i.e. −60° wrapped.
    assert!(
        wrap_pi(turned - 300f64.to_radians()).abs() < 0.15,
        "{}",
        turned.to_degrees()
    );
    stream(&mut v, &body(0.0, 0.0, 0.0), 2.0, |_| {});
    let start = v.step().snapshot.pos_w;
    let (mut farthest, mut turned, mut last) = (0.0_f64, 0.0_f64, heading(&v.step()));
    stream(&mut v, &body(5.0, 0.0, 30.0), 12.0, |o| {
        farthest = farthest.max((o.snapshot.pos_w - start).xy().norm());
        turned += wrap_pi(heading(o) - last);
        last = heading(o);
    });
    // A full circle of radius v/ω = 9.5 m in 12 s: never farther than its diameter, and back
    // (within the ≈ 4 m the 1.7 s acceleration to 5 m/s takes off the first quarter).
    let back = (v.step().snapshot.pos_w - start).xy().norm();
    assert!(
        (turned.to_degrees() - 360.0).abs() < 5.0,
        "turned {}°",
        turned.to_degrees()
    );
    assert!(farthest < 19.5 && farthest > 15.0, "farthest {farthest} m");
    assert!(back < 5.0, "{back} m from the start after a full circle");
}

#[test]
fn a_half_turn_of_heading_keeps_the_velocity_and_turns_the_short_way() {
    // MAVSDK's offboard_velocity_ned.py: north facing east, then south facing west.
    for kind in ControllerKind::ALL {
        let mut v = vehicle(kind);
        let ned = |n: f64, e: f64, d: f64, yaw_deg: f64| Request::OffboardSetpoint {
            setpoint: FlatSetpoint {
                vel_w: Some(Vec3::new(n, e, d)),
                yaw_rad: Some(yaw_deg.to_radians()),
                ..Default::default()
            },
            body_frame: false,
        };
        start_offboard(&mut v, &ned(0.0, 0.0, 0.0, 0.0));
        stream(&mut v, &ned(0.0, 0.0, -2.0, 0.0), 4.0, |_| {});
        stream(&mut v, &ned(2.0, 0.0, 0.0, 90.0), 4.0, |_| {});
        let (mut turned, mut last, mut worst_north) = (0.0_f64, heading(&v.step()), f64::MIN);
        let mut north_after_1s = f64::MIN;
        let t0 = v.time_s();
        // 180° at 45 °/s with 0.75 s ramps at 60 °/s² (MPC_YAWRAUTO_ACC): 4.75 s.
        stream(&mut v, &ned(-2.0, 0.0, 0.0, 270.0), 5.0, |o| {
            turned += wrap_pi(heading(o) - last).abs();
            last = heading(o);
            worst_north = worst_north.max(o.snapshot.vel_w.x);
            if o.snapshot.t_s - t0 > 1.5 {
                north_after_1s = north_after_1s.max(o.snapshot.vel_w.x);
            }
        });
        let name = kind.name();
        assert!(turned < 190f64.to_radians(), "{name}: turned {}°", turned.to_degrees());
        assert!(
            wrap_pi(last - 270f64.to_radians()).abs() < 0.05,
            "{name}: heading {}",
            last.to_degrees()
        );
        // 90 % of the way by 1.5 s (the body drag slows the RPY laws' last centimetres a second).
        assert!(
            north_after_1s < -1.75,
            "{name}: still {north_after_1s} m/s north after 1.5 s"
        );
        assert!(worst_north < 2.1, "{name}: {worst_north}");
    }
}

#[test]
fn a_landing_from_high_up_descends_fast_and_touches_down_slowly() {
    // PX4's landing: MPC_Z_VEL_MAX_DN above MPC_LAND_ALT1 (10 m), MPC_LAND_SPEED below
    // MPC_LAND_ALT2 (5 m).
    let mut v = vehicle(ControllerKind::Geometric);
    assert_eq!(v.apply(Request::Takeoff { height_m: Some(20.0) }), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    fly(&mut v, 15.0, |_| {});
    assert_eq!(v.apply(Request::Land), Outcome::Accepted);
    let (mut fast, mut touch_down, mut landed_after) = (0.0_f64, 0.0_f64, None);
    let t0 = v.time_s();
    fly(&mut v, 30.0, |o| {
        let (height, down) = (-o.snapshot.pos_w.z - 0.1, o.snapshot.vel_w.z);
        if height > 10.5 {
            fast = fast.max(down);
        }
        if height < 0.3 && landed_after.is_none() {
            touch_down = touch_down.max(down);
        }
        if o.snapshot.landed == LandedState::OnGround && landed_after.is_none() {
            landed_after = Some(o.snapshot.t_s - t0);
        }
    });
    assert!((fast - 1.5).abs() < 0.1, "high up: {fast} m/s");
    assert!(touch_down < 0.8, "touch-down at {touch_down} m/s");
    // 10 m at 1.5 m/s, the 5 m band, 5 m at 0.7 m/s, touch-down detection: ≈ 19 s (29 s at 0.7).
    let landed_after = landed_after.expect("landed");
    assert!(landed_after < 21.0, "landed after {landed_after} s");
}
