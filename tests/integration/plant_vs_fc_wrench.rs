//! The plant's wrench, summed per rotor with its own geometry, equals the FC's `G_q ω²` for the
//! same speeds (docs/architecture.md §2): a sign error on either side fails here.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use firmware_sim::rotor::rotor_wrench_b;
use firmware_sim::PlantParams;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorpilot::airframe::{Airframe, AirframeSource, PRESETS};
use rotorpilot::allocation::Allocator;

#[test]
fn plant_wrench_equals_g_times_omega_squared() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for (name, _) in PRESETS {
        let src = AirframeSource::resolve(name).unwrap();
        let fc = Allocator::new(&Airframe::from_source(&src).unwrap()).unwrap();
        let plant = PlantParams::from_toml_str(&src.text, &src.origin).unwrap();
        let n = plant.rotors.len();
        for _ in 0..100 {
            let omega: Vec<f64> = (0..n)
                .map(|_| plant.rotor.omega_max_rad_s * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
                .collect();
            let (force_b, torque_b) = rotor_wrench_b(&plant.rotors, &plant.rotor, &omega, &vec![1.0; n]);
            let omega_sq: Vec<f64> = omega.iter().map(|w| w * w).collect();
            let w = fc.wrench_of(&omega_sq);
            assert!(
                (w.thrust_n + force_b.z).abs() < 1e-9,
                "{name}: thrust {} vs {}",
                w.thrust_n,
                -force_b.z
            );
            assert!(force_b.xy().norm() == 0.0);
            assert!(
                (w.torque_b - torque_b).norm() < 1e-9,
                "{name}: torque {:?} vs {:?}",
                w.torque_b,
                torque_b
            );
        }
    }
}
