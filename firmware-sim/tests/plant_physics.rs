//! Plant behaviour: free fall, hover equilibrium, torque-to-rate signs, angular momentum,
//! determinism, ground effect in the loop, contact, the mean rate a gyroscope integrates.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use firmware_sim::rigid_body::RigidBodyState;
use firmware_sim::{rand_chacha_seed, Plant, PlantParams, DEFAULT_DT_S, GRAVITY_M_S2};
use nalgebra::{UnitQuaternion, Vector3};

const OCTO: &str = include_str!("../../airframes/octo.toml");
const QUAD_X: &str = include_str!("../../airframes/quad_x.toml");

fn params(text: &str) -> PlantParams {
    PlantParams::from_toml_str(text, "test").unwrap()
}

fn airborne(z: f64) -> RigidBodyState {
    RigidBodyState {
        pos_w: Vector3::new(0.0, 0.0, z),
        vel_w: Vector3::zeros(),
        q_wb: UnitQuaternion::identity(),
        omega_b: Vector3::zeros(),
    }
}

#[test]
fn free_fall_with_motors_off() {
    let mut plant = Plant::new(params(OCTO));
    plant.set_body_state(airborne(-100.0));
    for _ in 0..2000 {
        let status = plant.step(&[0.0; 8], DEFAULT_DT_S);
        assert!(!status.on_ground);
    }
    let t = plant.truth();
    assert!((t.t_s - 2.0).abs() < 1e-12);
    assert!((t.body.pos_w.z - (-100.0 + 0.5 * GRAVITY_M_S2 * 4.0)).abs() < 1e-9);
    assert!((t.body.vel_w.z - 2.0 * GRAVITY_M_S2).abs() < 1e-9);
    assert!((t.accel_w.z - GRAVITY_M_S2).abs() < 1e-6);
}

#[test]
fn hover_equilibrium_at_hover_speed() {
    for text in [OCTO, QUAD_X] {
        let p = params(text);
        let n = p.rotors.len();
        let hover = vec![p.hover_speed_rad_s(); n];
        let mut plant = Plant::new(p);
        plant.set_body_state(airborne(-10.0));
        plant.set_motor_speeds(&hover);
        for _ in 0..5000 {
            plant.step(&hover, DEFAULT_DT_S);
        }
        let b = plant.truth().body;
        assert!(
            (b.pos_w - Vector3::new(0.0, 0.0, -10.0)).norm() < 1e-9,
            "drifted to {:?}",
            b.pos_w
        );
        assert!(b.omega_b.norm() < 1e-9 && b.vel_w.norm() < 1e-9);
    }
}

/// Speeding up the rotors that carry a positive entry of one torque row and slowing the others
/// must spin the body positively about that axis (FRD: roll right, pitch up, yaw right).
#[test]
fn torque_to_rate_signs_for_each_axis() {
    let p = params(QUAD_X);
    let hover = p.hover_speed_rad_s();
    // Rotors 1..4 at 45°, 135°, 225°, 315° counter-clockwise seen from above, rotor 1 clockwise.
    // FRD hub y = −l sin α: rotors 1, 2 on the left (y < 0) push roll right when faster.
    let cases: [([f64; 4], usize); 3] = [
        ([1.0, 1.0, -1.0, -1.0], 0), // τx = c_T l sin α > 0 for rotors 1, 2
        ([1.0, -1.0, -1.0, 1.0], 1), // τy = c_T l cos α > 0 for rotors 1, 4 (front)
        ([-1.0, 1.0, -1.0, 1.0], 2), // τz: counter-clockwise rotors 2, 4 give +c_Q
    ];
    for (pattern, axis) in cases {
        let cmd: Vec<f64> = pattern.iter().map(|s| hover * (1.0 + 0.02 * s)).collect();
        let mut plant = Plant::new(p.clone());
        plant.set_body_state(airborne(-10.0));
        plant.set_motor_speeds(&cmd);
        for _ in 0..100 {
            plant.step(&cmd, DEFAULT_DT_S);
        }
        let w = plant.truth().body.omega_b;
        assert!(w[axis] > 1e-3, "axis {axis}: {w:?}");
        for other in (0..3).filter(|k| *k != axis) {
            assert!(
                w[other].abs() < 1e-6 * w[axis].abs().max(1.0),
                "axis {axis} leaks into {other}: {w:?}"
            );
        }
    }
}

#[test]
fn torque_free_tumble_keeps_world_angular_momentum() {
    let p = params(OCTO);
    let inertia = p.inertia_kg_m2;
    let mut plant = Plant::new(p);
    let mut s = airborne(-1000.0);
    s.omega_b = Vector3::new(3.0, -1.0, 2.0);
    s.q_wb = UnitQuaternion::from_euler_angles(0.2, 0.1, -0.4);
    plant.set_body_state(s);
    let h = |b: &RigidBodyState| b.q_wb * inertia.component_mul(&b.omega_b);
    let h0 = h(&s);
    for _ in 0..5000 {
        plant.step(&[0.0; 8], DEFAULT_DT_S);
    }
    let b = plant.truth().body;
    assert!(
        (h(&b) - h0).norm() / h0.norm() < 1e-8,
        "{}",
        (h(&b) - h0).norm() / h0.norm()
    );
}

/// The mean rate of each step, integrated step by step, gives back the attitude: through a
/// tumble, and through the levelling of a landing, which the body rate (zeroed by the contact)
/// never shows (docs/model.md §10.2, eq. (10.3)).
#[test]
fn the_mean_rate_of_each_step_integrates_to_the_attitude_even_through_a_landing() {
    let p = params(QUAD_X);
    let mut plant = Plant::new(p);
    let mut s = airborne(-0.5);
    s.q_wb = UnitQuaternion::from_euler_angles(0.05, -0.03, 1.0);
    s.omega_b = Vector3::new(0.4, -0.3, 0.2);
    plant.set_body_state(s);
    let mut q = s.q_wb;
    let mut landed = false;
    for _ in 0..1000 {
        plant.step(&[0.0; 4], DEFAULT_DT_S);
        let t = plant.truth();
        q *= UnitQuaternion::from_scaled_axis(t.mean_omega_b * DEFAULT_DT_S);
        landed |= t.on_ground;
        assert!(q.angle_to(&t.body.q_wb) < 1e-9, "integrated attitude left the truth");
    }
    assert!(landed, "the drop ended on the ground");
    assert_eq!(plant.truth().mean_omega_b, Vector3::zeros(), "at rest, no rate");
}

fn noisy_run(seed: u64) -> Vec<(f64, f64)> {
    let text = format!(
        "{OCTO}\n[plant.noise]\nposition = 0.01 # [m]\ngyro = 0.002 # [rad/s]\n\n[[plant.disturbance]]\nkind = \"sinusoid\" # [-]\nfrequency = 0.5 # [Hz]\nforce = [0.3, 0.0, 0.1] # [N]\ntorque = [0.0, 0.01, 0.0] # [N·m]\n"
    );
    let p = params(&text);
    let hover = p.hover_speed_rad_s();
    let mut plant = Plant::new(p);
    let mut rng = rand_chacha_seed(seed);
    let mut out = Vec::new();
    for k in 0..3000 {
        let s = plant.sense(&mut rng);
        let cmd: Vec<f64> = (0..8)
            .map(|i| hover * (1.05 + 0.01 * ((k + i) % 7) as f64) + 5.0 * s.omega_b.x)
            .collect();
        plant.step(&cmd, DEFAULT_DT_S);
        out.push((s.pos_w.x, plant.truth().body.pos_w.z));
    }
    out
}

#[test]
fn same_seed_and_inputs_give_bit_identical_trajectories() {
    let a = noisy_run(7);
    let b = noisy_run(7);
    assert!(a
        .iter()
        .zip(&b)
        .all(|(x, y)| x.0.to_bits() == y.0.to_bits() && x.1.to_bits() == y.1.to_bits()));
    let c = noisy_run(8);
    assert_ne!(a, c, "a different seed must give different noise");
}

#[test]
fn ground_effect_factor_in_the_loop() {
    // Hubs one rotor radius above the ground: Cheeseman–Bennett gives 1/(1 − 1/16) = 1.0667.
    let text = OCTO.replace("model = \"off\"", "model = \"cheeseman_bennett\"");
    let p = params(&text);
    let rho = p.rotor.radius_m;
    let hover = vec![p.hover_speed_rad_s(); 8];
    let mut plant = Plant::new(p);
    plant.set_body_state(airborne(-rho));
    plant.set_motor_speeds(&hover);
    plant.step(&hover, DEFAULT_DT_S);
    for f in plant.proximity_factors() {
        assert!((f - 16.0 / 15.0).abs() < 1e-12);
        assert!((f - 1.0667).abs() < 5e-5);
    }
    // Extra thrust pushes the vehicle up: a = −(k − 1) g.
    assert!(
        (plant.truth().accel_w.z + GRAVITY_M_S2 / 15.0).abs() < 2e-3,
        "{}",
        plant.truth().accel_w.z
    );
    // Switched off at the same height: exactly 1, and back on again.
    plant.set_proximity_effects(false, false);
    plant.set_body_state(airborne(-rho));
    plant.step(&hover, DEFAULT_DT_S);
    assert!(plant.proximity_factors().iter().all(|f| *f == 1.0));
    plant.set_proximity_effects(true, true);
    plant.set_body_state(airborne(-rho));
    plant.step(&hover, DEFAULT_DT_S);
    assert!(plant
        .proximity_factors()
        .iter()
        .all(|f| (f - 16.0 / 15.0).abs() < 1e-12));
    // Far from the ground: exactly 1.
    plant.set_body_state(airborne(-50.0));
    plant.step(&hover, DEFAULT_DT_S);
    assert!(plant.proximity_factors().iter().all(|f| *f == 1.0));
}

#[test]
fn ceiling_draws_the_vehicle_up() {
    let text = format!("{OCTO}\n[plant.ceiling]\nheight = -3.0 # [m]\n");
    let p = params(&text);
    assert_eq!(p.warnings().len(), 1, "placeholder constants are flagged");
    let rho = p.rotor.radius_m;
    let hover = vec![p.hover_speed_rad_s(); 8];
    let mut plant = Plant::new(p);
    plant.set_body_state(airborne(-3.0 + rho));
    plant.set_motor_speeds(&hover);
    plant.step(&hover, DEFAULT_DT_S);
    assert!(plant
        .proximity_factors()
        .iter()
        .all(|f| (f - 16.0 / 15.0).abs() < 1e-12));
    assert!(plant.truth().body.vel_w.z < 0.0, "more thrust near the ceiling");
}

#[test]
fn rests_on_the_ground_without_sinking_or_bouncing_then_takes_off() {
    let p = params(QUAD_X);
    let hover = p.hover_speed_rad_s();
    let rest_z = -p.gear_height_m;
    let mut plant = Plant::new(p);
    assert_eq!(plant.truth().body.pos_w.z, rest_z);
    // Idle and then 90 % of hover: stays exactly put.
    for cmd in [0.0, 0.9 * hover] {
        for _ in 0..2000 {
            let s = plant.step(&[cmd; 4], DEFAULT_DT_S);
            assert!(s.on_ground);
            let b = plant.truth().body;
            assert_eq!(b.pos_w.z, rest_z);
            assert_eq!(b.vel_w, Vector3::zeros());
        }
    }
    // 110 % of hover: lifts off cleanly and keeps climbing.
    let mut last_z = rest_z;
    for k in 0..1000 {
        plant.step(&[1.1 * hover; 4], DEFAULT_DT_S);
        let z = plant.truth().body.pos_w.z;
        assert!(z <= last_z, "sank at tick {k}");
        last_z = z;
    }
    assert!(last_z < rest_z - 0.05 && !plant.truth().on_ground);
}

#[test]
fn landing_from_a_drop_stops_on_the_ground() {
    let p = params(QUAD_X);
    let rest_z = -p.gear_height_m;
    let mut plant = Plant::new(p);
    let mut s = airborne(-1.0);
    s.q_wb = UnitQuaternion::from_euler_angles(0.05, -0.03, 1.0);
    plant.set_body_state(s);
    let mut landed_at = None;
    for k in 0..2000 {
        let status = plant.step(&[0.0; 4], DEFAULT_DT_S);
        let b = plant.truth().body;
        assert!(b.pos_w.z <= rest_z + 1e-12, "sank below the ground");
        if status.on_ground {
            landed_at.get_or_insert(k);
            assert_eq!(b.vel_w, Vector3::zeros(), "bounced");
            assert!((b.q_wb.euler_angles().2 - 1.0).abs() < 1e-9, "heading kept");
        } else {
            assert!(landed_at.is_none(), "left the ground after landing");
        }
    }
    assert!(landed_at.is_some());
}

#[test]
fn bad_inputs_are_reported_not_panicked() {
    let p = params(QUAD_X);
    let mut plant = Plant::new(p);
    let before = plant.truth();
    assert!(plant.step(&[0.0; 4], f64::NAN).dt_rejected);
    assert!(plant.step(&[0.0; 4], -1e-3).dt_rejected);
    assert_eq!(plant.truth(), before);
    let s = plant.step(&[f64::NAN, 1.0, 2.0], DEFAULT_DT_S);
    assert!(s.command_rejected && !s.state_non_finite);
    let t = plant.truth().body;
    assert!(t.pos_w.iter().all(|x| x.is_finite()));
}

#[test]
fn motor_lag_limits_and_external_step() {
    let text = format!(
        "{QUAD_X}\n[[plant.disturbance]]\nkind = \"step\" # [-]\nstart = 0.5 # [s]\nforce = [1.5, 0.0, 0.0] # [N]\n"
    );
    let p = params(&text);
    let mut plant = Plant::new(p);
    plant.set_body_state(airborne(-50.0));
    plant.step(&[5000.0; 4], DEFAULT_DT_S);
    assert!(
        plant.motor_speeds().iter().all(|w| *w < 1100.0 && *w > 0.0),
        "lagged and below the limit"
    );
    for _ in 0..2000 {
        plant.step(&[5000.0; 4], DEFAULT_DT_S);
    }
    assert!(
        plant.motor_speeds().iter().all(|w| (w - 1100.0).abs() < 1e-6),
        "clamped to omega_max"
    );
    let t = plant.truth();
    assert_eq!(t.external_force_w, Vector3::new(1.5, 0.0, 0.0));
    assert!(t.body.vel_w.x > 0.0);
}

#[test]
fn a_failed_rotor_spins_down_whatever_it_is_commanded() {
    let p = params(QUAD_X);
    let hover = vec![p.hover_speed_rad_s(); 4];
    let mut plant = Plant::new(p);
    plant.set_body_state(airborne(-10.0));
    plant.set_motor_speeds(&hover);
    assert!(plant.set_rotor_failed(1, true) && !plant.set_rotor_failed(4, true));
    assert_eq!(plant.failed_rotors(), &[false, true, false, false]);
    for _ in 0..500 {
        plant.step(&hover, DEFAULT_DT_S);
    }
    let speeds = plant.motor_speeds();
    assert!(speeds[1] < 1.0, "rotor 2 stopped: {}", speeds[1]);
    assert!((speeds[0] - hover[0]).abs() < 1e-9);
    assert!(
        plant.truth().body.omega_b.norm() > 0.1,
        "the lost thrust makes it tumble"
    );
    plant.set_rotor_failed(1, false);
    for _ in 0..500 {
        plant.step(&hover, DEFAULT_DT_S);
    }
    assert!((plant.motor_speeds()[1] - hover[1]).abs() < 1.0, "repaired");
}
