//! AUTO.RTL on a scripted vehicle and the return alone: the climb, the cone, rally points, a
//! moved home, the way round the fence.

use super::super::script::{Script, GROUND_Z_M};
use super::super::{CommanderParams, Event, FlightMode, GeofenceAction, Outcome, Request};
use crate::guidance::geofence::{Shape, Zone};
use crate::guidance::{Geofence, RallyPoints};
use crate::math::Vec3;

fn params() -> CommanderParams {
    CommanderParams {
        rtl_return_alt_m: 15.0,
        ..Default::default()
    }
}

fn reposition(s: &mut Script, north_m: Option<f64>, east_m: Option<f64>, down_m: Option<f64>) {
    let to = Request::Reposition {
        north_m,
        east_m,
        down_m,
        yaw_rad: None,
        speed_m_s: None,
        change_mode: true,
    };
    assert_eq!(s.request(to), Outcome::Accepted);
    s.fly(20.0);
}

#[test]
fn rtl_climbs_to_rtl_return_alt_returns_home_and_lands() {
    let mut s = Script::new(params());
    s.airborne(3.0);
    reposition(&mut s, Some(20.0), Some(10.0), None);
    s.events.clear();
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    assert_eq!(s.c.mode(), FlightMode::ReturnToLaunch);
    // Straight up first, to the return altitude above home.
    let start_xy = Vec3::new(20.0, 10.0, 0.0).xy();
    let mut climbed_in_place = true;
    assert!(s.fly_until(30.0, |s| {
        climbed_in_place &= (s.x.pos_w.xy() - start_xy).norm() < 1e-9;
        s.x.pos_w.z < -15.0 + 1e-6
    }));
    assert!(climbed_in_place, "climbs before it turns home");
    let mut highest: f64 = 0.0;
    let landed = s.fly_until(200.0, |s| {
        highest = highest.max(-s.x.pos_w.z);
        !s.c.armed()
    });
    assert!(landed, "returned, landed and disarmed: {:?}", s.events);
    assert!((highest - 15.0).abs() < 1e-6, "returned at RTL_RETURN_ALT: {highest} m");
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
        "home is nearer: {:?}",
        s.x.pos_w
    );
    assert_eq!(s.events, vec![Event::Landed, Event::Disarmed("landed")]);
}

#[test]
fn close_to_home_the_cone_lowers_the_return_altitude() {
    // RTL_RETURN_ALT 15, cone 45°, RTL_MIN_DIST 10, NAV_ACC_RAD 2; 3 m up.
    for (north_m, expected_m) in [(0.0, 3.0), (1.5, 3.0), (8.0, 8.0), (30.0, 15.0)] {
        let mut s = Script::new(params());
        s.airborne(3.0);
        if north_m > 0.0 {
            reposition(&mut s, Some(north_m), None, None);
        }
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        let mut highest: f64 = 0.0;
        assert!(s.fly_until(200.0, |s| {
            highest = highest.max(-s.x.pos_w.z);
            !s.c.armed()
        }));
        assert!(
            (highest - expected_m).abs() < 1e-3,
            "{north_m} m out: climbed to {highest} m"
        );
        assert!(s.x.pos_w.xy().norm() < 1e-3, "landed at home: {:?}", s.x.pos_w);
    }
}

#[test]
fn a_return_asked_on_the_ground_does_not_take_off() {
    let mut s = Script::new(params());
    assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    s.fly(5.0);
    assert!(
        (s.x.pos_w.z - GROUND_Z_M).abs() < 1e-9,
        "stayed on the ground: {:?}",
        s.x.pos_w
    );
    assert!(s.until_disarmed(15.0), "auto-disarm without a take-off: {:?}", s.events);
}

#[test]
fn rtl_with_a_rally_point_nearer_than_home_lands_there() {
    let mut s = Script::new(params());
    let rally = RallyPoints {
        points_w: vec![Vec3::new(40.0, 10.0, 0.0), Vec3::new(-60.0, 0.0, 0.0)],
        ..Default::default()
    };
    assert_eq!(s.request(Request::SetRallyPoints(rally)), Outcome::Accepted);
    s.airborne(3.0);
    reposition(&mut s, Some(30.0), Some(0.0), None);
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    assert!(s.until_disarmed(200.0), "{:?}", s.events);
    let landed_at = Vec3::new(40.0, 10.0, GROUND_Z_M);
    assert!((s.x.pos_w - landed_at).norm() < 1e-6, "{:?}", s.x.pos_w);
    // From near home, home is closer: it lands at home.
    s.airborne(3.0);
    reposition(&mut s, Some(-5.0), Some(5.0), None);
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    assert!(s.until_disarmed(200.0));
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
        "home is nearer: {:?}",
        s.x.pos_w
    );
}

#[test]
fn rtl_above_the_return_altitude_keeps_its_height_and_lands_at_a_moved_home() {
    let mut s = Script::new(params());
    s.airborne(3.0);
    reposition(&mut s, Some(5.0), Some(5.0), Some(-20.0));
    assert_eq!(
        s.request(Request::SetHome(Some(Vec3::new(-4.0, 2.0, 0.0)))),
        Outcome::Accepted
    );
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    let home_xy = Vec3::new(-4.0, 2.0, 0.0).xy();
    let mut heights = (f64::MAX, 0.0_f64);
    let over_home = s.fly_until(60.0, |s| {
        heights = (heights.0.min(-s.x.pos_w.z), heights.1.max(-s.x.pos_w.z));
        (s.x.pos_w.xy() - home_xy).norm() < 1e-6
    });
    assert!(over_home);
    assert!(
        (heights.0 - 20.0).abs() < 1e-6 && (heights.1 - 20.0).abs() < 1e-6,
        "{heights:?}"
    );
    assert!(s.until_disarmed(120.0));
    assert!(
        (s.x.pos_w - Vec3::new(-4.0, 2.0, GROUND_Z_M)).norm() < 1e-6,
        "{:?}",
        s.x.pos_w
    );
}

/// An exclusion square and circle between the vehicle and home, inside an inclusion square.
fn fence_in_the_way() -> Geofence {
    let square = |inclusion, c: [f64; 2], h: f64| Zone {
        inclusion,
        shape: Shape::Polygon(vec![
            [c[0] - h, c[1] - h],
            [c[0] + h, c[1] - h],
            [c[0] + h, c[1] + h],
            [c[0] - h, c[1] + h],
        ]),
    };
    Geofence {
        zones: vec![
            square(true, [40.0, 0.0], 70.0),
            square(false, [55.0, 5.0], 10.0),
            Zone {
                inclusion: false,
                shape: Shape::Circle {
                    center: [25.0, -8.0],
                    radius_m: 8.0,
                },
            },
        ],
    }
}

#[test]
fn rtl_flies_round_exclusion_zones_in_the_way_and_lands_home() {
    let fence = fence_in_the_way();
    let mut s = Script::new(params());
    assert_eq!(s.request(Request::SetGeofence(fence.clone())), Outcome::Accepted);
    s.airborne(3.0);
    // Out past the zones, east of them.
    for (north_m, east_m) in [(0.0, 30.0), (90.0, 30.0), (90.0, 0.0)] {
        reposition(&mut s, Some(north_m), Some(east_m), None);
    }
    assert!((s.x.pos_w.xy() - Vec3::new(90.0, 0.0, 0.0).xy()).norm() < 1e-6);
    assert!(
        !s.events.iter().any(|e| matches!(e, Event::Failsafe(..))),
        "{:?}",
        s.events
    );
    s.events.clear();
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    let (mut closest, mut farthest_off_line) = (f64::INFINITY, 0.0_f64);
    let landed = s.fly_until(300.0, |s| {
        let p = [s.x.pos_w.x, s.x.pos_w.y];
        for zone in &fence.zones {
            assert!(zone.allows(p), "{p:?} breaches the fence");
        }
        let off_zone = match &fence.zones[1].shape {
            Shape::Polygon(v) => {
                let dn = (v[0][0] - p[0]).max(p[0] - v[2][0]).max(0.0);
                let de = (v[0][1] - p[1]).max(p[1] - v[2][1]).max(0.0);
                dn.hypot(de)
            }
            Shape::Circle { .. } => f64::INFINITY,
        };
        closest = closest.min(off_zone);
        farthest_off_line = farthest_off_line.max(p[1].abs());
        !s.c.armed()
    });
    assert!(landed, "{:?}", s.events);
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-3,
        "landed home: {:?}",
        s.x.pos_w
    );
    // NAV_ACC_RAD 2: a 4 m margin, cut by less than its half at the corners flown through.
    assert!(closest > 2.0, "kept {closest} m off the square");
    // Round the square's west side (5 m off the line, a 4 m margin), then east of the circle.
    assert!(
        farthest_off_line > 8.9,
        "went round: {farthest_off_line} m off the straight line"
    );
    assert_eq!(
        s.events.first(),
        Some(&Event::Notice {
            text: super::AVOIDING_FENCE.into(),
            critical: false
        })
    );
    // Without the fence the same return flies straight.
    let mut s = Script::new(params());
    s.airborne(3.0);
    reposition(&mut s, Some(90.0), Some(0.0), None);
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    let mut off_line = 0.0_f64;
    assert!(s.fly_until(300.0, |s| {
        off_line = off_line.max(s.x.pos_w.y.abs());
        !s.c.armed()
    }));
    assert!(off_line < 1e-6, "{off_line}");
}

#[test]
fn rtl_without_a_way_inside_the_fence_flies_straight_and_says_so() {
    // A wall across the whole inclusion zone between the vehicle and home.
    let mut fence = fence_in_the_way();
    fence.zones.truncate(1);
    fence.zones.push(Zone {
        inclusion: false,
        shape: Shape::Polygon(vec![[45.0, -80.0], [55.0, -80.0], [55.0, 80.0], [45.0, 80.0]]),
    });
    let mut p = params();
    p.failsafe.geofence_action = GeofenceAction::Warn;
    let mut s = Script::new(p);
    s.airborne(3.0);
    reposition(&mut s, Some(90.0), Some(0.0), None);
    // Uploaded in flight with GF_ACTION 1 (warn): both zones count.
    assert_eq!(s.request(Request::SetGeofence(fence)), Outcome::Accepted);
    s.events.clear();
    assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
    assert!(s.until_disarmed(300.0), "{:?}", s.events);
    assert!(
        (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-3,
        "{:?}",
        s.x.pos_w
    );
    assert!(
        s.events.contains(&Event::Notice {
            text: super::NO_FENCE_PATH.into(),
            critical: true
        }),
        "{:?}",
        s.events
    );
}

/// A vehicle at `pos_w` [m], at rest, level.
fn at(pos_w: Vec3) -> crate::control::VehicleState {
    crate::control::VehicleState {
        t_s: 0.0,
        pos_w,
        vel_w: Vec3::zeros(),
        r_wb: crate::math::Mat3::identity(),
        omega_b: Vec3::zeros(),
    }
}

#[test]
fn the_return_climbs_returns_then_descends_each_when_the_last_is_flown() {
    use super::{AutoPaths, Plans, Rtl, RtlPhase};
    use crate::guidance::Guidance;
    let p = params();
    let paths = AutoPaths::new(&p, (None, (None, None)), None, 0.0);
    let plans = Plans::default();
    let mut rtl = Rtl::default();
    rtl.start();
    let x = at(Vec3::new(30.0, 0.0, -15.0));
    assert_eq!(
        rtl.advance(&paths, &plans, Guidance::Idle, &x, 0.0, 0.0),
        Default::default()
    );
    assert_eq!(rtl.phase(), RtlPhase::Climb, "on the ground: nothing to return from");
    let climbing = paths.path_to(&x, Vec3::new(30.0, 0.0, -15.0), 0.0, 5.0, 0.0);
    let step = rtl.advance(&paths, &plans, climbing, &x, 0.0, 100.0);
    assert_eq!(rtl.phase(), RtlPhase::Return);
    assert_eq!(step.notice, None, "no fence: straight");
    let returning = step.guidance.expect("the flight home");
    assert!(!returning.finished(100.0));
    assert_eq!(
        rtl.advance(&paths, &plans, returning, &x, 0.0, 100.0),
        Default::default()
    );
    let over_home = at(Vec3::new(0.0, 0.0, -15.0));
    let step = rtl.advance(&paths, &plans, returning, &over_home, 0.0, 1000.0);
    assert_eq!(rtl.phase(), RtlPhase::Descend);
    assert!(matches!(step.guidance, Some(Guidance::Descend { .. })), "{step:?}");
}

#[test]
fn the_return_height_follows_the_cone() {
    use super::Rtl;
    let p = params();
    // RTL_RETURN_ALT 15, cone 45°, RTL_MIN_DIST 10, NAV_ACC_RAD 2; 3 m up.
    for (north_m, expected_m) in [(0.0, 3.0), (1.5, 3.0), (8.0, 8.0), (30.0, 15.0)] {
        let h = Rtl::return_height(&p, Vec3::zeros(), &at(Vec3::new(north_m, 0.0, -3.0)));
        assert!((h - expected_m).abs() < 1e-9, "{north_m} m out: {h} m");
    }
    assert_eq!(
        Rtl::return_height(&p, Vec3::zeros(), &at(Vec3::new(30.0, 0.0, -40.0))),
        40.0
    );
}
