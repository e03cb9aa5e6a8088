//! A scenario's ULog read back by `estimate`'s reader gives the samples of its run.csv (to single
//! precision), and the offline estimator recovers homework Ex. 4's wrench and mass from it; the
//! full profile writes at most 300 KB per simulated second.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use rotorpilot::math::{Vec3, GRAVITY_M_S2};
use rotorpilot::runners::scenario_run::simulate_paced;
use rotorpilot::runtime::Pace;
use rotorpilot::scenario::Scenario;
use rotorpilot::wrench_estimator::log_replay::{parse_log, replay};
use rotorpilot::wrench_estimator::ulog_log::parse_ulog;
use rotorpilot::wrench_estimator::{ChebyshevDesign, WrenchObserver};

#[test]
fn the_ulog_holds_the_run_csv_samples_and_the_estimator_recovers_ex4() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenarios/ex4_estimator.toml"))
        .unwrap()
        .replace("duration = 40.0", "duration = 12.0");
    let scn = Scenario::from_toml_str(&text, "ex4.toml", "ex4", &root.join("scenarios")).unwrap();
    let out = std::env::temp_dir().join(format!("rotorpilot-ulog-replay-{}", std::process::id()));
    simulate_paced(&scn, Some(&out), Pace::Max, true).unwrap();
    let from_ulog = parse_ulog(&std::fs::read(out.join("run.ulg")).unwrap(), "run.ulg", 1e-3).unwrap();
    let from_csv = parse_log(&std::fs::read_to_string(out.join("run.csv")).unwrap(), "run.csv", 1e-3).unwrap();
    let bytes_per_s = std::fs::metadata(out.join("run.ulg")).unwrap().len() as f64 / 12.0;
    std::fs::remove_dir_all(&out).ok();
    // The full profile with the estimator on (every topic logged): the budget.
    assert!(bytes_per_s <= 300e3, "{:.0} KB per simulated second", bytes_per_s / 1e3);
    assert_eq!(from_ulog.len(), 12_000);
    assert_eq!(from_ulog.len(), from_csv.len());
    for (u, c) in from_ulog.iter().zip(&from_csv) {
        assert!((u.t_s - c.t_s).abs() < 1e-9);
        assert!((u.thrust_n - c.thrust_n).abs() < 1e-5 * c.thrust_n.max(1.0));
        assert!(
            (u.vel_w - c.vel_w).norm() < 1e-6 && (u.eta - c.eta).norm() < 1e-6,
            "{u:?} {c:?}"
        );
        assert!((u.eta_dot - c.eta_dot).norm() < 1e-6 && (u.torque_b - c.torque_b).norm() < 1e-6);
    }
    let gains = ChebyshevDesign {
        order: 1,
        ripple_db: 3.0,
        passband_rad_s: 2.0,
    }
    .gains(1e-3)
    .unwrap();
    let observer = WrenchObserver::new(1.5, Vec3::new(1.2416, 1.2416, 2.4832), gains, 1e-3).unwrap();
    let last = replay(&from_ulog, observer).last().unwrap().estimate;
    let want = Vec3::new(0.5, 0.5, 0.2 * GRAVITY_M_S2);
    assert!((last.force_w - want).norm() < 0.01 * want.norm(), "{:?}", last.force_w);
    assert!((last.torque_b.z - 0.2).abs() < 0.002, "{:?}", last.torque_b);
    assert!((last.mass_kg - 1.7).abs() < 0.005 * 1.7, "{}", last.mass_kg);
}
