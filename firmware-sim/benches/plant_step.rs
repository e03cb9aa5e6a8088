//! One plant step of the octocopter with every effect on: RK4, motor lag, multirotor ground
//! effect and ceiling effect (inside both zones, so the factors are really computed), three
//! disturbance profiles and linear drag. Target: under 1 µs per step on one core.
#![allow(clippy::expect_used)] // a broken bench set-up should stop the bench

use criterion::{criterion_group, criterion_main, Criterion};
use firmware_sim::rigid_body::RigidBodyState;
use firmware_sim::{Plant, PlantParams, DEFAULT_DT_S};
use nalgebra::{UnitQuaternion, Vector3};
use std::hint::black_box;

const ALL_EFFECTS: &str = r#"
[plant.ceiling]
height = -1.2          # [m]

[plant.drag]
linear = [0.1, 0.1, 0.2]   # [N·s/m]

[[plant.disturbance]]
kind = "constant"      # [-]
force = [0.5, 0.5, 0.0]    # [N]
torque = [0.0, 0.0, 0.2]   # [N·m]

[[plant.disturbance]]
kind = "step"          # [-]
start = 0.0            # [s]
force = [0.0, 0.1, 0.0]    # [N]

[[plant.disturbance]]
kind = "sinusoid"      # [-]
frequency = 0.5        # [Hz]
force = [0.2, 0.0, 0.0]    # [N]
torque = [0.01, 0.0, 0.0]  # [N·m]
"#;

fn plant_step(c: &mut Criterion) {
    let text = include_str!("../../airframes/octo.toml").replace("model = \"off\"", "model = \"multirotor\"");
    let params = PlantParams::from_toml_str(&format!("{text}{ALL_EFFECTS}"), "bench").expect("bench airframe");
    let hover = params.hover_speed_rad_s();
    let cmd: Vec<f64> = (0..8).map(|i| hover * (1.0 + 0.01 * i as f64)).collect();
    let start = RigidBodyState {
        pos_w: Vector3::new(0.0, 0.0, -0.6),
        vel_w: Vector3::new(0.1, 0.0, 0.0),
        q_wb: UnitQuaternion::from_euler_angles(0.05, -0.02, 0.3),
        omega_b: Vector3::new(0.1, 0.0, 0.05),
    };
    let mut plant = Plant::new(params);
    plant.set_body_state(start);
    plant.set_motor_speeds(&cmd);
    plant.step(&cmd, DEFAULT_DT_S);
    assert!(
        plant.proximity_factors().iter().all(|f| *f > 1.0),
        "both effects active"
    );
    let mut k = 0u32;
    c.bench_function("plant_step_octo_all_effects", |b| {
        b.iter(|| {
            // Put the vehicle back now and then so it stays between ground and ceiling.
            k += 1;
            if k % 1000 == 0 {
                plant.set_body_state(start);
            }
            black_box(plant.step(black_box(&cmd), DEFAULT_DT_S))
        })
    });
}

criterion_group!(benches, plant_step);
criterion_main!(benches);
