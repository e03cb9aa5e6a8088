//! The stick modes fly the plant through the autopilot's flight controller, with MANUAL_CONTROL
//! at 50 Hz as QGroundControl's virtual joystick sends it: POSCTL takes off on the throttle,
//! flies and holds; ALTCTL holds the height while the sticks tilt it; STABILIZED hovers with the
//! throttle centred (MPC_THR_HOVER from the airframe) and tilts as far as MPC_MAN_TILT_MAX;
//! ACRO turns at the stick's rate; the throttle down lands and disarms.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::flight_bench;

use flight_bench::Sim;
use rotorpilot::commander::{Event, FlightMode, Outcome, Request};
use rotorpilot::guidance::Sticks;

/// Joystick period [s] (50 Hz).
const STICK_PERIOD_S: f64 = 0.02;

/// Flies `seconds` [s] with `sticks` sent at 50 Hz.
fn fly(sim: &mut Sim, sticks: Sticks, seconds: f64) {
    for _ in 0..(seconds / STICK_PERIOD_S).round() as usize {
        assert_eq!(sim.request(Request::ManualControl(sticks)), Outcome::Accepted);
        sim.run(STICK_PERIOD_S);
    }
}

fn sticks(roll: f64, pitch: f64, throttle: f64, yaw: f64) -> Sticks {
    Sticks {
        roll,
        pitch,
        yaw,
        throttle,
    }
}

/// quad_x armed in POSCTL and climbed on the throttle to about 5 m, then 3 s centred.
fn airborne_in_position() -> Sim {
    let mut sim = Sim::autopilot("quad_x");
    fly(&mut sim, Sticks::CENTRED, 0.2);
    assert_eq!(sim.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
    assert_eq!(sim.request(Request::Arm { force: false }), Outcome::Accepted);
    fly(&mut sim, Sticks::CENTRED, 1.0);
    assert!(sim.on_ground(), "centred throttle on the ground: it waits");
    for _ in 0..1000 {
        if sim.position().z < -5.0 {
            break;
        }
        fly(&mut sim, sticks(0.0, 0.0, 1.0, 0.0), STICK_PERIOD_S);
    }
    assert!(sim.position().z < -5.0, "climbs on the throttle: {:?}", sim.position());
    fly(&mut sim, Sticks::CENTRED, 3.0);
    assert!(sim.events.contains(&Event::Airborne));
    sim
}

#[test]
fn posctl_flies_the_sticks_holds_when_centred_and_lands_on_the_throttle() {
    let mut sim = airborne_in_position();
    let held = sim.position();
    fly(&mut sim, Sticks::CENTRED, 5.0);
    let drift = (sim.position() - held).norm();
    assert!(drift < 0.3, "centred sticks hold the point: drifted {drift} m");
    fly(&mut sim, sticks(0.0, 1.0, 0.5, 0.0), 5.0);
    let v = sim.velocity();
    assert!(
        v.x > 8.0 && v.y.abs() < 0.5,
        "full pitch flies north near MPC_VEL_MANUAL: {v:?}"
    );
    fly(&mut sim, Sticks::CENTRED, 8.0);
    let stopped = sim.position();
    assert!(sim.velocity().norm() < 0.2, "braked: {:?}", sim.velocity());
    assert!(
        (stopped.z - held.z).abs() < 0.5,
        "height held while flying: {stopped:?}"
    );
    fly(&mut sim, Sticks::CENTRED, 3.0);
    assert!((sim.position() - stopped).norm() < 0.3, "and holds there");
    fly(&mut sim, sticks(0.0, 0.0, 0.5, 1.0), 1.0);
    let yaw = sim.lockstep.plant().truth().q_wb.euler_angles().2;
    assert!(yaw > 1.5, "the yaw stick turns at MPC_MAN_Y_MAX (150 °/s): {yaw}");
    for _ in 0..1000 {
        fly(&mut sim, sticks(0.0, 0.0, 0.0, 0.0), 0.1);
        if !sim.commander().armed() {
            break;
        }
    }
    assert!(!sim.commander().armed() && sim.on_ground(), "{:?}", sim.events);
    assert!(sim.events.contains(&Event::Landed));
    assert_eq!(sim.events.last(), Some(&Event::Disarmed("landed")));
}

#[test]
fn altctl_holds_the_height_while_the_sticks_tilt_the_vehicle() {
    let mut sim = airborne_in_position();
    let z = sim.position().z;
    assert_eq!(sim.request(Request::SetMode(FlightMode::Altitude)), Outcome::Accepted);
    fly(&mut sim, sticks(0.0, 0.5, 0.5, 0.0), 2.0);
    assert!(
        sim.velocity().x > 3.0,
        "forward tilt accelerates north: {:?}",
        sim.velocity()
    );
    assert!((sim.position().z - z).abs() < 0.5, "height held: {:?}", sim.position());
    fly(&mut sim, sticks(0.0, 0.0, 1.0, 0.0), 1.5);
    assert!(sim.position().z < z - 1.5, "the throttle climbs: {:?}", sim.position());
}

#[test]
fn stabilized_hovers_at_the_centred_throttle_and_tilts_to_the_limit() {
    let mut sim = airborne_in_position();
    assert_eq!(sim.request(Request::SetMode(FlightMode::Stabilized)), Outcome::Accepted);
    fly(&mut sim, Sticks::CENTRED, 3.0);
    let vz = sim.velocity().z;
    assert!(
        vz.abs() < 0.5,
        "MPC_THR_HOVER is the airframe's hover thrust: v_z {vz} m/s"
    );
    fly(&mut sim, sticks(1.0, 0.0, 0.5, 0.0), 1.0);
    let roll = sim.lockstep.plant().truth().q_wb.euler_angles().0;
    assert!(
        (roll.to_degrees() - 35.0).abs() < 3.0,
        "MPC_MAN_TILT_MAX: {} deg",
        roll.to_degrees()
    );
    assert!(
        sim.velocity().y > 1.0,
        "rolled right, it goes east: {:?}",
        sim.velocity()
    );
}

#[test]
fn acro_turns_at_the_stick_rate() {
    let mut sim = airborne_in_position();
    assert_eq!(sim.request(Request::SetMode(FlightMode::Acro)), Outcome::Accepted);
    fly(&mut sim, sticks(0.0, 0.0, 0.5, 0.5), 1.0);
    let r = sim.lockstep.plant().truth().omega_b.z;
    assert!(
        (r.to_degrees() - 50.0).abs() < 5.0,
        "half of MC_ACRO_Y_MAX: {} deg/s",
        r.to_degrees()
    );
}
