//! Same scenario and seed give a bit-identical run.csv and run.ulg at any speed-up; another seed
//! gives another run.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use rotorpilot::runners::scenario_run::simulate_paced;
use rotorpilot::runtime::Pace;
use rotorpilot::scenario::Scenario;

fn run(seed: u64, pace: Pace, dir: &str) -> (Vec<u8>, PathBuf) {
    let text = format!(
        r#"
duration = 3.0
seed = {seed}
[airframe]
preset = "hexa_x"
[airframe.overrides.plant]
noise = {{ position = 0.01, velocity = 0.02, attitude = 0.002, gyro = 0.01 }}
disturbance = [{{ kind = "sinusoid", frequency = 0.5, force = [0.3, 0.0, 0.0], torque = [0.0, 0.0, 0.05] }}]
[initial]
position = [0.0, 0.0, -1.0]
[controller]
kind = "passivity"
compensation = true
[estimator]
order = 3
wp = 5.0
[trajectory]
kind = "circle"
centre = [0.0, 0.0, -1.0]
radius = 0.5
period = 4.0
"#
    );
    let out = std::env::temp_dir().join(format!("rotorpilot-determinism-{}-{dir}", std::process::id()));
    let scn = Scenario::from_toml_str(&text, "det", "det", Path::new(".")).unwrap();
    simulate_paced(&scn, Some(&out), pace, true).unwrap();
    let mut bytes = std::fs::read(out.join("run.csv")).unwrap();
    bytes.extend(std::fs::read(out.join("run.ulg")).unwrap());
    (bytes, out)
}

#[test]
fn same_seed_same_bytes_other_seed_other_run() {
    let (a, da) = run(7, Pace::Max, "a");
    let (b, db) = run(7, Pace::Max, "b");
    let (c, dc) = run(8, Pace::Max, "c");
    // 3 simulated seconds at 20× take 0.15 s of wall time, paced tick by tick.
    let (d, dd) = run(7, Pace::Speedup(20.0), "d");
    assert!(a.len() > 100_000);
    assert!(a == b, "same scenario and seed must give identical files");
    assert!(a == d, "the speed-up must not change the files");
    assert!(a != c, "the seed must change the noise");
    for d in [da, db, dc, dd] {
        let _ = std::fs::remove_dir_all(d);
    }
}
