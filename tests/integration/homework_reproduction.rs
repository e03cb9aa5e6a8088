//! The shipped homework scenarios reproduce the homework's results (docs/homework.md §2, §5).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use rotorpilot::runners::scenario_run::{simulate, SimSummary};
use rotorpilot::scenario::Scenario;

fn run(file: &str) -> SimSummary {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios").join(file);
    simulate(&Scenario::load(&path).unwrap(), None).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn ex5_geometric_reaches_the_goal_within_a_centimetre_with_hover_thrust_mg() {
    let s = run("ex5_geometric.toml");
    assert_eq!(
        (s.controller, s.airframe.as_str(), s.exit),
        ("geometric", "fsr_quad", "complete")
    );
    assert_eq!(s.tracking.final_reference_m, [1.0, 1.0, -1.0]);
    assert!(
        s.tracking.final_position_error_norm_m < 0.01,
        "{:?}",
        s.tracking.final_position_error_m
    );
    assert!(
        rel(s.tracking.final_thrust_n, 1.5 * 9.81) < 1e-3,
        "{}",
        s.tracking.final_thrust_n
    );
    // docs/homework.md §2.5: the Ex. 5 move stays inside the rotor limits.
    assert_eq!(s.tracking.saturated_time_s, 0.0);
}

#[test]
fn ex4_estimator_recovers_the_wrench_within_one_percent_and_the_mass_within_half_a_percent() {
    let s = run("ex4_estimator.toml");
    let est = s.estimate.as_ref().expect("estimator on");
    assert_eq!(est.order, 1);
    // Truth: scripted f_e = (0.5, 0.5, 0) N and τ_e = (0, 0, 0.2) N·m, plus the unmodelled
    // weight (m_r − m_e) g = 1.962 N along +z (docs/estimator.md §5, eq. (5.2)).
    assert_eq!(s.true_force_n, [0.5, 0.5, 0.0]);
    let unmodelled = (s.true_mass_kg - s.believed_mass_kg) * 9.81;
    let expected = [s.true_force_n[0], s.true_force_n[1], s.true_force_n[2] + unmodelled];
    for (e, t) in est.force_n.iter().zip(expected) {
        assert!(rel(*e, t) < 0.01, "force {:?} vs {expected:?}", est.force_n);
    }
    assert!(
        rel(est.torque_n_m[2], s.true_torque_n_m[2]) < 0.01,
        "{:?}",
        est.torque_n_m
    );
    assert!(est.torque_n_m[0].abs() < 0.002 && est.torque_n_m[1].abs() < 0.002);
    assert!(rel(est.mass_kg, 1.7) < 0.005, "{}", est.mass_kg);
    // With compensation the hierarchical law holds the point despite 1.7 kg vs 1.5 kg.
    assert!(s.tracking.final_position_error_norm_m < 0.01);
}

#[test]
fn every_controller_compensates_the_same_disturbance_on_the_same_move() {
    for kind in ["geometric", "hierarchical", "passivity"] {
        let s = run(&format!("{kind}_quintic.toml"));
        assert_eq!(s.controller, kind);
        assert!(
            s.tracking.final_position_error_norm_m < 0.01,
            "{kind}: {:?}",
            s.tracking.final_position_error_m
        );
        let est = s.estimate.as_ref().unwrap();
        assert!(rel(est.mass_kg, 1.7) < 0.005, "{kind}: {}", est.mass_kg);
    }
}

#[test]
fn ground_and_ceiling_show_as_an_upward_force_that_the_controller_flies_through() {
    let s = run("ground_ceiling.toml");
    assert_eq!(s.exit, "complete");
    // Back in ground effect at 0.3 m: less thrust than the weight holds the vehicle, and the
    // estimator reports the aerodynamic lift as an upward (negative z, NED) external force.
    assert!(
        s.tracking.final_thrust_n < 0.99 * s.true_weight_n,
        "{}",
        s.tracking.final_thrust_n
    );
    assert!(s.estimate.as_ref().unwrap().force_n[2] < -0.1);
    assert!(s.tracking.final_position_error_norm_m < 0.05);
}

#[test]
fn the_estimator_tracks_a_turbulent_wind_force_and_the_vehicle_holds_its_point() {
    let s = run("wind_turbulence.toml");
    assert_eq!(s.exit, "complete");
    let tracking = s
        .estimate
        .as_ref()
        .and_then(|e| e.tracking.clone())
        .expect("estimator on");
    // 5 m/s toward east through c_1 = 0.05 N·s/m and c_2 = 0.02 N·s²/m²: ≈ 0.75 N east on
    // average, and the Dryden turbulence makes it vary by a few tenths of a newton.
    assert!(tracking.true_force_sd_n[1] > 0.1, "{tracking:?}");
    assert!(tracking.true_force_sd_n[0] > 0.05, "{tracking:?}");
    // The estimate follows the horizontal wind force with errors a quarter of its spread.
    for axis in 0..2 {
        assert!(
            tracking.rms_force_error_n[axis] < 0.25 * tracking.true_force_sd_n[axis],
            "axis {axis}: {tracking:?}"
        );
    }
    // z carries the motor lag the estimator does not model (it uses the commanded speeds).
    assert!(tracking.rms_force_error_n[2] < 0.25, "{tracking:?}");
    assert!(
        s.tracking.rms_position_error_m.iter().all(|e| *e < 0.02),
        "{:?}",
        s.tracking
    );
    assert_eq!(
        run("wind_turbulence.toml").tracking,
        s.tracking,
        "same seed, same gusts"
    );
}
