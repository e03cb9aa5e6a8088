//! A bad airframe file is refused with an error naming the file, the field and the reason.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use firmware_sim::PlantParams;

const QUAD_X: &str = include_str!("../../airframes/quad_x.toml");

fn refused(text: &str) -> firmware_sim::ParamsError {
    PlantParams::from_toml_str(text, "bad.toml").expect_err("must be refused")
}

#[test]
fn missing_field() {
    let text: String = QUAD_X
        .lines()
        .filter(|l| !l.starts_with("mass"))
        .collect::<Vec<_>>()
        .join("\n");
    let e = refused(&text);
    assert_eq!(
        (e.origin.as_str(), e.field.as_str(), e.reason.as_str()),
        ("bad.toml", "vehicle.mass", "missing field")
    );
    assert_eq!(e.to_string(), "bad.toml: vehicle.mass: missing field");
}

#[test]
fn negative_mass() {
    let e = refused(&QUAD_X.replace("mass = 1.5 ", "mass = -1.5 "));
    assert_eq!(e.field, "vehicle.mass");
    assert!(e.reason.contains("positive"));
}

#[test]
fn fewer_than_four_rotors() {
    let e = refused(&QUAD_X.replace("count = 4 ", "count = 3 "));
    assert_eq!(e.field, "rotors.ring.count");
    assert!(e.reason.contains("fewer than 4"));
}

fn explicit(rotors: &[(f64, f64, f64, &str)]) -> String {
    let start = QUAD_X.find("[rotors.ring]").unwrap();
    let end = QUAD_X.find("[plant.ground]").unwrap();
    let mut list = String::new();
    for (angle, arm, z, spin) in rotors {
        list.push_str(&format!(
            "[[rotors.rotor]]\nangle = {angle:?} # [deg]\narm = {arm:?} # [m]\nz = {z:?} # [m]\nspin = \"{spin}\" # [-]\n\n"
        ));
    }
    format!("{}{list}{}", &QUAD_X[..start], &QUAD_X[end..])
}

#[test]
fn explicit_list_loads_like_the_ring() {
    let list = PlantParams::from_toml_str(
        &explicit(&[
            (45.0, 0.25, 0.0, "cw"),
            (135.0, 0.25, 0.0, "ccw"),
            (225.0, 0.25, 0.0, "cw"),
            (315.0, 0.25, 0.0, "ccw"),
        ]),
        "list",
    )
    .unwrap();
    let ring = PlantParams::from_toml_str(QUAD_X, "ring").unwrap();
    for (a, b) in list.rotors.iter().zip(&ring.rotors) {
        assert!((a.hub_b - b.hub_b).norm() < 1e-12);
        assert_eq!(a.reaction_sign, b.reaction_sign);
    }
}

#[test]
fn non_coplanar_rotors() {
    let e = refused(&explicit(&[
        (45.0, 0.25, 0.0, "cw"),
        (135.0, 0.25, 0.0, "ccw"),
        (225.0, 0.25, -0.05, "cw"),
        (315.0, 0.25, 0.0, "ccw"),
    ]));
    assert_eq!(e.field, "rotors.rotor[2].z");
    assert!(e.reason.contains("not coplanar"));
}

#[test]
fn overlapping_rotors() {
    let e = refused(&explicit(&[
        (45.0, 0.25, 0.0, "cw"),
        (60.0, 0.25, 0.0, "ccw"),
        (225.0, 0.25, 0.0, "cw"),
        (315.0, 0.25, 0.0, "ccw"),
    ]));
    assert_eq!(e.field, "rotors.rotor[1]");
    assert!(e.reason.contains("overlap"));
}

#[test]
fn typo_and_bad_values_in_plant_tables() {
    let e = refused(&QUAD_X.replace("gear_height", "gear_hieght"));
    assert!(e.field.starts_with("line "), "{e}");
    assert!(e.reason.contains("gear_hieght"));
    let e = refused(&QUAD_X.replace("model = \"off\"", "model = \"magic\""));
    assert_eq!(e.field, "plant.ground.model");
    let e = refused(&format!("{QUAD_X}\n[[plant.disturbance]]\nkind = \"step\"\n"));
    assert_eq!(e.field, "plant.disturbance[0].start");
    let e = refused(&QUAD_X.replace("omega_max = 1100.0", "omega_max = nan"));
    assert_eq!(e.field, "rotors.omega_max");
}

#[test]
fn not_toml_at_all() {
    let e = refused("this is [not toml");
    assert_eq!(e.origin, "bad.toml");
    assert!(e.field.starts_with("line"));
}
