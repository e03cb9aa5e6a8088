//! MAV_CMD_DO_ORBIT flown through the autopilot's flight controller: the vehicle approaches the
//! circle, flies it at the commanded speed and height with its nose on the centre, and a new
//! speed takes effect without leaving the circle.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::flight_bench;

use flight_bench::Sim;
use rotorpilot::commander::{FlightMode, OrbitRequest, Outcome, Request};
use rotorpilot::math::{wrap_pi, Vec3};

#[test]
fn do_orbit_flies_the_circle_at_its_speed_and_height_facing_the_centre() {
    let mut sim = Sim::autopilot("quad_x");
    assert_eq!(sim.request(Request::Takeoff { height_m: Some(5.0) }), Outcome::Accepted);
    assert_eq!(sim.request(Request::Arm { force: false }), Outcome::Accepted);
    sim.run(8.0);
    let orbit = OrbitRequest {
        radius_m: Some(10.0),
        speed_m_s: Some(3.0),
        yaw: None,
        centre_ne_m: Some((20.0, 0.0)),
        centre_down_m: Some(-10.0),
    };
    assert_eq!(sim.request(Request::Orbit(orbit)), Outcome::Accepted);
    assert_eq!(sim.commander().mode(), FlightMode::Orbit);
    sim.run(20.0);
    let centre = Vec3::new(20.0, 0.0, -10.0);
    let mut worst = (0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..200 {
        sim.run(0.1);
        let d = sim.position() - centre;
        let yaw = sim.lockstep.plant().truth().q_wb.euler_angles().2;
        worst = (
            worst.0.max((d.xy().norm() - 10.0).abs()),
            worst.1.max((sim.velocity().xy().norm() - 3.0).abs()),
            worst.2.max(wrap_pi(yaw - (-d.y).atan2(-d.x)).abs()),
        );
        assert!(d.z.abs() < 0.3, "at the centre's height: {d:?}");
    }
    assert!(worst.0 < 0.3, "radius error {} m", worst.0);
    assert!(worst.1 < 0.3, "speed error {} m/s", worst.1);
    assert!(worst.2.to_degrees() < 5.0, "heading error {} deg", worst.2.to_degrees());
    let faster = OrbitRequest {
        speed_m_s: Some(5.0),
        ..Default::default()
    };
    assert_eq!(sim.request(Request::Orbit(faster)), Outcome::Accepted);
    sim.run(15.0);
    let d = sim.position() - centre;
    assert!((d.xy().norm() - 10.0).abs() < 0.5, "still on the circle: {d:?}");
    assert!((sim.velocity().xy().norm() - 5.0).abs() < 0.4, "{:?}", sim.velocity());
    let (c, r) = sim.commander().orbit_status().unwrap();
    assert!(
        (c - centre).norm() < 0.3 && r == 10.0,
        "same centre (at the height flown): {c:?}"
    );
}
