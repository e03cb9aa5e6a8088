//! Scenarios with `[autopilot]`: the flight controller of `rotorpilot run` flies the trajectory in
//! OFFBOARD, so its battery, failsafes and rotor-failure reactions act in `rotorpilot sim` too.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use rotorpilot::runners::scenario_run::{simulate, SimSummary};
use rotorpilot::scenario::Scenario;

/// `quad_x` from the ground to a hover at `position`, with the `extra` tables.
fn scenario(duration_s: f64, position: [f64; 3], extra: &str) -> Result<Scenario, String> {
    let text = format!(
        r#"
duration = {duration_s}
[airframe]
preset = "quad_x"
[controller]
kind = "geometric"
[trajectory]
kind = "hover"
position = {position:?}
{extra}
"#
    );
    Scenario::from_toml_str(&text, "ap.toml", "ap", Path::new(".")).map_err(|e| e.to_string())
}

/// The summary's events without their times.
fn events(s: &SimSummary) -> Vec<&str> {
    s.events.iter().map(|e| e.split_once(" s: ").unwrap().1).collect()
}

#[test]
fn a_small_battery_returns_then_lands_and_disarms() {
    let extra = "[autopilot]\nparams = { BAT1_CAPACITY = 300, COM_LOW_BAT_ACT = 3 }";
    let s = simulate(&scenario(40.0, [3.0, 0.0, -2.0], extra).unwrap(), None).unwrap();
    let said = events(&s);
    let at = |text: &str| {
        said.iter()
            .position(|e| e.starts_with(text))
            .unwrap_or_else(|| panic!("{said:?}"))
    };
    assert!(at("Takeoff detected") < at("Low battery: 15%"));
    assert!(at("Low battery") < at("Critical battery (7%): returning"));
    // COM_FAIL_ACT_T: the return waits 5 s in a hold; the emergency level, reached within it,
    // makes the waiting action a landing, which starts when the hold ends.
    assert_eq!(said[at("Critical battery") + 1], "Mode AUTO.LOITER");
    assert!(at("Critical battery") < at("Emergency battery (5%): landing"));
    assert_eq!(said[at("Emergency battery") + 1], "Mode AUTO.LAND");
    assert!(at("Emergency battery (5%): landing") < at("Landing detected"));
    assert!(at("Landing detected") < at("Disarmed: landed"));
    assert!(
        s.tracking.final_position_m[2] > -0.2,
        "on the ground: {:?}",
        s.tracking.final_position_m
    );
}

#[test]
fn a_rotor_failure_is_reported_and_com_act_fail_act_2_lands() {
    // PX4's default (COM_ACT_FAIL_ACT 0): a warning, and the quadrotor flies on without yaw.
    let extra = "[[rotor_failure]]\nrotor = 1\nat = 6.0\n[autopilot]";
    let s = simulate(&scenario(12.0, [0.0, 0.0, -3.0], extra).unwrap(), None).unwrap();
    assert_eq!(events(&s), ["Takeoff detected", "Motor 1 failed, yaw lost"]);
    let extra =
        "[[rotor_failure]]\nrotor = 1\nat = 6.0\n[autopilot]\nparams = { COM_ACT_FAIL_ACT = 2, COM_FAIL_ACT_T = 0 }";
    let s = simulate(&scenario(25.0, [0.0, 0.0, -3.0], extra).unwrap(), None).unwrap();
    assert_eq!(
        events(&s),
        [
            "Takeoff detected",
            "Motor 1 failed, yaw lost: landing",
            "Mode AUTO.LAND",
            "Landing detected",
            "Disarmed: landed"
        ]
    );
    // FD_ACT_MOT_TOUT (0.1 s) passes before the allocation leaves the rotor out: the quadrotor
    // tilts and drifts meanwhile.
    let p = s.tracking.final_position_m;
    assert!(p[0].hypot(p[1]) < 3.0, "landed near the failure: {p:?}");
}

#[test]
fn without_autopilot_the_same_scenario_has_no_commander() {
    let s = simulate(&scenario(3.0, [0.0, 0.0, -1.0], "").unwrap(), None).unwrap();
    assert!(s.events.is_empty());
    assert!(!serde_json::to_string(&s).unwrap().contains("\"events\""));
}

#[test]
fn autopilot_settings_are_parameters_and_bad_ones_are_named() {
    let bad = |extra: &str| scenario(5.0, [0.0, 0.0, -1.0], extra).unwrap_err();
    assert_eq!(
        bad("[autopilot]\nparams = { NO_SUCH = 1 }"),
        "ap.toml: autopilot.params.NO_SUCH: NO_SUCH: no such parameter"
    );
    assert!(bad("[autopilot]\nparams = { BAT1_CAPACITY = \"big\" }")
        .starts_with("ap.toml: autopilot.params.BAT1_CAPACITY: must be a number"));
    assert_eq!(
        bad("[estimator]\norder = 1\nwp = 2.0\n[autopilot]"),
        "ap.toml: estimator: with [autopilot] set it by its parameter (RP_*) in autopilot.params"
    );
    assert_eq!(
        bad("[initial]\nposition = [0.0, 0.0, -1.0]\n[autopilot]"),
        "ap.toml: initial: with [autopilot] the vehicle starts resting on the ground, as a flight controller boots"
    );
}
