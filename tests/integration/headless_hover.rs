//! Closed loop: every preset takes off and hovers with the hover controller, the headless run is
//! deterministic, and a mass the FC does not know about shows as a steady altitude error.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use rotorpilot::airframe::{AirframeSource, PRESETS};
use rotorpilot::runners::fly::{fly, FlyOptions};

fn opts(duration_s: f64, seed: u64) -> FlyOptions {
    FlyOptions {
        duration_s,
        seed,
        ..Default::default()
    }
}

#[test]
fn every_preset_takes_off_and_hovers() {
    for (name, _) in PRESETS {
        let src = AirframeSource::resolve(name).unwrap();
        let s = fly(&src, &opts(8.0, 0)).unwrap();
        assert!(!s.on_ground, "{name}");
        let err = s.final_error_m.iter().map(|e| e * e).sum::<f64>().sqrt();
        assert!(err < 1e-3, "{name}: final error {err} m");
        assert!((s.final_rotor_speed_rad_s - s.hover_speed_rad_s).abs() < 0.5, "{name}");
        assert!(
            s.max_tilt_deg < 1e-6,
            "{name}: symmetric climb must stay level, tilt {}",
            s.max_tilt_deg
        );
        assert_eq!(s.saturated_time_s, 0.0, "{name}");
    }
}

#[test]
fn noisy_runs_are_reproducible_per_seed() {
    let text = format!(
        "{}\n[plant.noise]\nposition = 0.02 # [m]\nvelocity = 0.01 # [m/s]\nattitude = 0.002 # [rad]\ngyro = 0.005 # [rad/s]\n",
        rotorpilot::airframe::preset_text("quad_x").unwrap()
    );
    let src = AirframeSource {
        origin: "noisy".into(),
        text,
    };
    let a = fly(&src, &opts(3.0, 11)).unwrap();
    let b = fly(&src, &opts(3.0, 11)).unwrap();
    let c = fly(&src, &opts(3.0, 12)).unwrap();
    assert_eq!(a.final_position_m, b.final_position_m);
    assert_eq!(a.max_tilt_deg, b.max_tilt_deg);
    assert_ne!(a.final_position_m, c.final_position_m);
    assert!(a.max_tilt_deg > 0.0, "noise must disturb the attitude");
}

#[test]
fn unknown_extra_mass_sags_by_weight_over_stiffness() {
    // The FC believes 1.5 kg; the vehicle weighs 1.7 kg. The geometric law (homework gains,
    // K_p,z = 25 N/m) has no integral action and no estimator here, so it settles where
    // K_p,z e_z = (m_true − m_fc) g.
    let base = rotorpilot::airframe::preset_text("fsr_quad")
        .unwrap()
        .replace("mass = 1.5 ", "mass = 1.7 ");
    let src = AirframeSource {
        origin: "heavy".into(),
        text: format!("{base}\n[fc]\nmass = 1.5 # [kg]\n"),
    };
    let s = fly(&src, &opts(15.0, 0)).unwrap();
    let expected = 0.2 * 9.81 / 25.0;
    assert!(
        (s.final_error_m[2] - expected).abs() < 2e-3,
        "sag {} vs {expected}",
        s.final_error_m[2]
    );
}
