//! Offboard velocity and yaw-rate streams flown on the default sensors (the navigation filter's
//! estimate), judged on what a ground station is shown: the estimated body rates ATTITUDE
//! carries. MAVSDK's `offboard_velocity_body.py` streams 5 m/s forward or sideways with a yaw rate
//! of 30°/s; the vehicle must turn at that rate through every heading, never stall, never spin.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::runtime_vehicle::{vehicle, DT_S};
use rotorpilot::commander::{FlightMode, Outcome, Request};
use rotorpilot::control::FlatSetpoint;
use rotorpilot::math::Vec3;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;

/// quad_x on the default sensors, seed `seed`, hovering at 2.5 m in AUTO.LOITER.
fn hovering(seed: u64) -> Vehicle {
    let mut v = vehicle("quad_x", SensorModel::Suite, seed, &[]);
    let mut armable = false;
    for _ in 0..(30.0 / DT_S) as usize {
        if v.step().snapshot.nav.armable {
            armable = true;
            break;
        }
    }
    assert!(armable, "ready to arm within 30 s");
    assert_eq!(v.apply(Request::Takeoff { height_m: None }), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    for _ in 0..(12.0 / DT_S) as usize {
        v.step();
    }
    assert_eq!(v.step().snapshot.mode, FlightMode::Loiter);
    v
}

/// Streams the body-frame velocity `vel_b` [m/s] with yaw rate `yaw_rate` [rad/s] at 20 Hz for
/// `seconds` in OFFBOARD; the estimated yaw rate [rad/s] of every tick after the first second.
fn stream(v: &mut Vehicle, vel_b: Vec3, yaw_rate: f64, seconds: f64) -> Vec<f64> {
    let request = Request::OffboardSetpoint {
        setpoint: FlatSetpoint {
            vel_w: Some(vel_b),
            yaw_rate_rad_s: Some(yaw_rate),
            ..Default::default()
        },
        body_frame: true,
    };
    assert_eq!(v.apply(request.clone()), Outcome::Accepted);
    assert_eq!(v.apply(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
    let mut rates = Vec::new();
    for k in 0..(seconds / DT_S) as usize {
        if k % 50 == 0 {
            assert_eq!(v.apply(request.clone()), Outcome::Accepted);
        }
        let s = v.step().snapshot;
        assert_eq!(s.mode, FlightMode::Offboard);
        if k as f64 * DT_S > 1.0 {
            rates.push(s.omega_b.z);
        }
    }
    rates
}

/// The yaw rate [°/s] averaged over each `window_s` of `rates`.
fn windowed_deg_s(rates: &[f64], window_s: f64) -> Vec<f64> {
    let n = (window_s / DT_S) as usize;
    rates
        .chunks(n)
        .filter(|c| c.len() == n)
        .map(|c| c.iter().sum::<f64>() / n as f64 * 180.0 / std::f64::consts::PI)
        .collect()
}

#[test]
fn a_yaw_rate_is_flown_through_every_heading_forward_and_sideways() {
    for (seed, vel_b) in [(0, Vec3::new(5.0, 0.0, 0.0)), (1, Vec3::new(0.0, -5.0, 0.0))] {
        let mut v = hovering(seed);
        // 15 s at 30°/s: 450°, through ±180° more than once.
        let rates = stream(&mut v, vel_b, 30f64.to_radians(), 15.0);
        // After the acceleration to 5 m/s (1.7 s at MPC_ACC_HOR, tilted by the body drag too,
        // when the body rate reads a little less than the heading rate): the steady turn.
        let windows = windowed_deg_s(&rates[1000..], 0.25);
        let slowest = windows.iter().copied().fold(f64::MAX, f64::min);
        let fastest = windows.iter().copied().fold(f64::MIN, f64::max);
        assert!(
            slowest > 24.0 && fastest < 36.0,
            "seed {seed}, {vel_b:?}: yaw rate over 0.25 s windows between {slowest:.1} and {fastest:.1}°/s, not 30"
        );
        let peak = rates.iter().map(|r| r.abs()).fold(0.0, f64::max).to_degrees();
        assert!(peak < 60.0, "seed {seed}: a spike of {peak:.0}°/s");
    }
}

/// MAVSDK's `offboard_position_ned.py` ends on a position at the take-off height: the vehicle
/// touches down there, the land detector sees it land, and it disarms (`COM_DISARM_LAND`), with
/// the ground station shown a height of zero.
#[test]
fn an_offboard_position_back_at_the_take_off_height_touches_down_lands_and_disarms() {
    let mut v = vehicle("quad_x", SensorModel::Suite, 4, &[]);
    for _ in 0..(10.0 / DT_S) as usize {
        v.step();
    }
    let at = |p: Vec3| Request::OffboardSetpoint {
        setpoint: FlatSetpoint::hold(p, 0.0),
        body_frame: false,
    };
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    assert_eq!(v.apply(at(Vec3::zeros())), Outcome::Accepted);
    assert_eq!(v.apply(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
    let mut disarmed_at = None;
    let mut max_height: f64 = 0.0;
    for (target, seconds) in [(Vec3::new(0.0, 0.0, -5.0), 10.0), (Vec3::new(5.0, 0.0, 0.0), 15.0)] {
        for k in 0..(seconds / DT_S) as usize {
            if k % 50 == 0 {
                v.apply(at(target));
            }
            let s = v.step().snapshot;
            max_height = max_height.max(-s.pos_w.z);
            if !s.armed && disarmed_at.is_none() {
                disarmed_at = Some((s.t_s, s.pos_w));
            }
        }
    }
    assert!(max_height > 4.5, "flew up to 5 m: {max_height}");
    let (t, p) = disarmed_at.expect("landed and disarmed");
    assert!(
        p.z.abs() < 0.1 && (p.xy() - Vec3::new(5.0, 0.0, 0.0).xy()).norm() < 0.5,
        "at {p:?}, {t} s"
    );
}
