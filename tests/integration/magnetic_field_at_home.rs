//! Closed loop: the magnetometer reads the World Magnetic Model's field at the vehicle's home
//! (docs/model.md §10.5) and the navigation filter takes the same model's declination there
//! (docs/navigation_filter.md §10, eq. (10.5)), so the heading estimate is right far from PX4's
//! default home. At ArduPilot SITL's home (CMAC, Canberra: declination +12.6°, the field pointing
//! up) a vehicle on the default sensors aligns, takes off and turns through every heading with
//! its estimated yaw within a few degrees of the truth; with the declination taken from
//! `EKF2_MAG_DECL` (0) instead, the estimate is off by the declination. Its barometer reads the
//! pressure of CMAC's altitude, not of PX4's default home.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::airframe::AirframeSource;
use rotorpilot::commander::{FlightMode, Outcome, Request};
use rotorpilot::control::{ControllerKind, FlatSetpoint};
use rotorpilot::guidance::Home;
use rotorpilot::math::{wrap_pi, Vec3};
use rotorpilot::nav_filter::isa::pressure_altitude_m;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::{magnetic_declination_rad, SensorModel};

const DT_S: f64 = 1e-3;

/// ArduPilot SITL's default home.
const CMAC: Home = Home {
    lat_deg: -35.363261,
    lon_deg: 149.165230,
    alt_amsl_m: 584.0,
};

/// quad_x at CMAC on the default sensors with parameters `params`, ready to arm.
fn at_cmac(params: &[(&str, f64)]) -> Vehicle {
    let src = AirframeSource::resolve("quad_x").unwrap();
    let mut v = Vehicle::new(&src, ControllerKind::Geometric, CMAC, SensorModel::Suite, 5, DT_S).unwrap();
    for (name, value) in params {
        v.set_param(name, *value).unwrap();
    }
    for _ in 0..(30.0 / DT_S) as usize {
        if v.step().snapshot.nav.armable {
            return v;
        }
    }
    panic!("not ready to arm within 30 s");
}

/// Estimated minus true yaw after the next tick [rad].
fn heading_error(v: &mut Vehicle) -> f64 {
    let s = v.step().snapshot;
    let (_, _, true_yaw) = s.truth.unwrap().q_wb.euler_angles();
    wrap_pi(s.eta.z - true_yaw)
}

#[test]
fn the_field_at_cmac_points_up_with_the_models_declination() {
    let decl = magnetic_declination_rad(&CMAC).unwrap().to_degrees();
    assert!((decl - 12.65).abs() < 0.05, "{decl}°");
    let mut v = at_cmac(&[]);
    let mag_b = v.step().snapshot.nav.mag_b.unwrap();
    assert!(mag_b.z < -0.4, "level, the field points up: {mag_b:?}");
}

#[test]
fn the_barometer_at_cmac_reads_the_pressure_of_its_altitude() {
    let mut v = at_cmac(&[]);
    let (pressure_pa, _) = v.step().snapshot.nav.baro.unwrap();
    // On the ground the centre of mass stands at quad_x's gear height, 0.1 m above z = 0; the
    // typical barometer's noise is 0.085 m.
    let alt_m = pressure_altitude_m(pressure_pa).unwrap();
    assert!((alt_m - 584.1).abs() < 0.5, "{alt_m} m: CMAC is at 584 m");
}

#[test]
fn heading_stays_true_through_a_full_turn_at_cmac() {
    let mut v = at_cmac(&[]);
    let mut worst = 0.0_f64;
    for _ in 0..(2.0 / DT_S) as usize {
        worst = worst.max(heading_error(&mut v).abs());
    }
    assert_eq!(v.apply(Request::Takeoff { height_m: None }), Outcome::Accepted);
    assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
    for _ in 0..(12.0 / DT_S) as usize {
        worst = worst.max(heading_error(&mut v).abs());
    }
    // 30°/s for 13 s: more than a full turn.
    let turn = Request::OffboardSetpoint {
        setpoint: FlatSetpoint {
            vel_w: Some(Vec3::zeros()),
            yaw_rate_rad_s: Some(30f64.to_radians()),
            ..Default::default()
        },
        body_frame: true,
    };
    assert_eq!(v.apply(turn.clone()), Outcome::Accepted);
    assert_eq!(v.apply(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
    let (mut turned, mut last_yaw) = (0.0, None);
    for k in 0..(13.0 / DT_S) as usize {
        if k % 50 == 0 {
            assert_eq!(v.apply(turn.clone()), Outcome::Accepted);
        }
        worst = worst.max(heading_error(&mut v).abs());
        let (_, _, yaw) = v.truth().q_wb.euler_angles();
        turned += last_yaw.map_or(0.0, |y| wrap_pi(yaw - y));
        last_yaw = Some(yaw);
    }
    assert!(turned > 2.0 * std::f64::consts::PI, "turned {turned} rad");
    let worst_deg = worst.to_degrees();
    assert!(worst_deg < 3.0, "heading error up to {worst_deg}°");
}

#[test]
fn without_the_models_declination_the_heading_is_off_by_it() {
    let decl = magnetic_declination_rad(&CMAC).unwrap();
    // EKF2_DECL_TYPE 0: EKF2_MAG_DECL (0°) is the declination.
    let mut v = at_cmac(&[("EKF2_DECL_TYPE", 0.0)]);
    let mean = (0..1000).map(|_| heading_error(&mut v)).sum::<f64>() / 1000.0;
    assert!((mean + decl).abs() < 2f64.to_radians(), "off by {}°", mean.to_degrees());
    // The user's declination is used as given.
    let mut v = at_cmac(&[("EKF2_DECL_TYPE", 0.0), ("EKF2_MAG_DECL", decl.to_degrees())]);
    let mean = (0..1000).map(|_| heading_error(&mut v)).sum::<f64>() / 1000.0;
    assert!(mean.abs() < 2f64.to_radians(), "off by {}°", mean.to_degrees());
}
