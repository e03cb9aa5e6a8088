//! The plant feels the wind through its drag (docs/model.md §5.1–§5.3).
#![allow(clippy::expect_used)] // a broken test set-up should fail the test

use firmware_sim::{Plant, PlantParams, DEFAULT_DT_S};
use nalgebra::Vector3;

fn quad(extra: &str) -> Plant {
    let text = format!(
        "{}\n[plant.drag]\nquadratic = [0.02, 0.02, 0.04]\n[plant.initial]\nposition = [0.0, 0.0, -10.0]\n{extra}",
        include_str!("../../airframes/fsr_quad.toml")
    );
    Plant::new(PlantParams::from_toml_str(&text, "windy").expect("valid airframe"))
}

#[test]
fn a_mean_wind_pushes_a_hovering_vehicle_downwind_with_c_v_squared() {
    let mut plant = quad("[plant.wind]\nvelocity = [0.0, 5.0, 0.0]\n");
    let hover = plant.params().hover_speed_rad_s();
    plant.set_motor_speeds(&[hover; 4]);
    plant.step(&[hover; 4], DEFAULT_DT_S);
    let t = plant.truth();
    assert_eq!(t.wind_w, Vector3::new(0.0, 5.0, 0.0));
    // At rest in a 5 m/s east wind: f = c |v_a| v_a with v_a = −w: 0.02 · 25 = 0.5 N east.
    assert!(
        (t.drag_force_w - Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-9,
        "{:?}",
        t.drag_force_w
    );
    for _ in 0..999 {
        plant.step(&[hover; 4], DEFAULT_DT_S);
    }
    let t = plant.truth();
    assert!(t.body.vel_w.y > 0.2, "drifts east: {:?}", t.body.vel_w);
    assert!(t.drag_force_w.y < 0.5, "less drag once moving with the air");
}

#[test]
fn turbulence_is_seeded_and_calm_air_changes_nothing() {
    let windy = "[plant.wind]\nvelocity = [5.0, 0.0, 0.0]\nturbulence = 5.0\n";
    let run = |seed: u64, extra: &str| {
        let mut plant = quad(extra);
        plant.seed_wind(seed);
        let hover = plant.params().hover_speed_rad_s();
        for _ in 0..500 {
            plant.step(&[hover; 4], DEFAULT_DT_S);
        }
        plant.truth()
    };
    assert_eq!(run(1, windy), run(1, windy));
    assert_ne!(run(1, windy).wind_w, run(2, windy).wind_w);
    let calm = run(1, "");
    assert_eq!(calm.wind_w, Vector3::zeros());
    assert!(
        calm.drag_force_w.xy().norm() < 1e-12,
        "only its own vertical motion: {:?}",
        calm.drag_force_w
    );
}

#[test]
fn a_wind_on_an_airframe_without_drag_is_warned_about() {
    let text = format!(
        "{}\n[plant.wind]\nvelocity = [3.0, 0.0, 0.0]\n",
        include_str!("../../airframes/fsr_quad.toml")
    );
    let params = PlantParams::from_toml_str(&text, "nodrag").expect("valid airframe");
    assert!(params.warnings().iter().any(|w| w.contains("wind exerts no force")));
    let bad = format!(
        "{}\n[plant.wind]\nvelocity = [3.0, 0.0]\n",
        include_str!("../../airframes/fsr_quad.toml")
    );
    let err = PlantParams::from_toml_str(&bad, "bad").expect_err("two numbers");
    assert_eq!(err.field, "plant.wind.velocity");
    let bad = format!(
        "{}\n[[plant.wind.gust]]\nstart = 1.0\nvelocity = [1.0, 0.0, 0.0]\n",
        include_str!("../../airframes/fsr_quad.toml")
    );
    let err = PlantParams::from_toml_str(&bad, "bad").expect_err("no duration");
    assert_eq!(err.field, "plant.wind.gust[0].duration");
}
