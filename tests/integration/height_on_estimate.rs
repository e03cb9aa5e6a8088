//! The height a ground station is shown on the default sensors (issue: LOCAL_POSITION_NED jumped
//! to ±0.6 m at alignment and arming was allowed anyway, so a landed vehicle showed itself under
//! ground): the filter's frame starts where the vehicle stands (z = 0 there, as PX4's local
//! frame), arming waits for the estimator's pre-flight checks, and after a flight the vehicle
//! reports itself back on the ground. Judged on the snapshot the telemetry is built from
//! (LOCAL_POSITION_NED.z is `pos_w.z`; GLOBAL_POSITION_INT.relative_alt is `home_w.z − pos_w.z`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::runtime_vehicle::{self, DT_S};
use rotorpilot::commander::{FlightMode, Outcome, Request};
use rotorpilot::lockstep::ScheduledSensorFailure;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;
use rotorpilot::telemetry::Snapshot;

fn vehicle(seed: u64) -> Vehicle {
    runtime_vehicle::vehicle("quad_x", SensorModel::Suite, seed, &[])
}

fn relative_alt_m(s: &Snapshot) -> f64 {
    s.home_w.z - s.pos_w.z
}

/// Steps `v` for `seconds`, calling `each` with every snapshot.
fn run(v: &mut Vehicle, seconds: f64, mut each: impl FnMut(&Snapshot)) {
    for _ in 0..(seconds / DT_S) as usize {
        each(&v.step().snapshot);
    }
}

#[test]
fn on_the_ground_the_height_reads_zero_from_the_start_and_after_a_flight() {
    for seed in 0..20 {
        let mut v = vehicle(seed);
        // 20 s on the ground: every reading within 0.1 m of zero; arming refused until the
        // estimator says it may.
        let mut worst: f64 = 0.0;
        let mut armable_at = None;
        for k in 0..(20.0 / DT_S) as usize {
            let s = v.step().snapshot;
            worst = worst.max(s.pos_w.z.abs());
            if armable_at.is_none() && s.nav.armable {
                armable_at = Some(k);
            }
            if armable_at.is_none() && k % 250 == 0 {
                let refused = v.apply(Request::Arm { force: false });
                assert!(
                    matches!(&refused, Outcome::TemporarilyRejected(why) if why.starts_with("Arming denied: ")),
                    "seed {seed}: arming before the checks passed: {refused:?}"
                );
            }
        }
        assert!(
            worst <= 0.1,
            "seed {seed}: LOCAL_POSITION_NED.z reached {worst:.3} m on the ground"
        );
        assert!(armable_at.is_some(), "seed {seed}: never armable");
        // A flight to 5 m and a landing: back on the ground, relative_alt within 0.2 m of 0.
        assert_eq!(v.apply(Request::Takeoff { height_m: Some(5.0) }), Outcome::Accepted);
        assert_eq!(v.apply(Request::Arm { force: false }), Outcome::Accepted);
        run(&mut v, 15.0, |_| {});
        assert_eq!(v.apply(Request::Land), Outcome::Accepted);
        let mut disarmed = false;
        run(&mut v, 30.0, |s| disarmed |= !s.armed);
        assert!(disarmed, "seed {seed}: landed and disarmed");
        let mut last = None;
        run(&mut v, 2.0, |s| last = Some(relative_alt_m(s)));
        let rel = last.unwrap();
        assert!(rel.abs() <= 0.2, "seed {seed}: relative_alt {rel:.3} m after landing");
    }
}

#[test]
fn a_height_source_that_disagrees_on_the_ground_holds_arming_back_as_px4s_preflight_check() {
    let mut v = vehicle(3);
    let mut armable = false;
    run(&mut v, 10.0, |s| armable |= s.nav.armable);
    assert!(armable);
    // The barometer now reads 100 m too high: its innovations hold beyond the gate.
    let at = v.time_s();
    v.schedule_sensor_failure(format!("baro:wrong@{at}").parse::<ScheduledSensorFailure>().unwrap());
    run(&mut v, 1.5, |_| {});
    assert_eq!(
        v.apply(Request::Arm { force: false }),
        Outcome::TemporarilyRejected("Arming denied: height estimate not stable".into())
    );
    assert_eq!(v.step().snapshot.mode, FlightMode::Loiter);
}
