//! The flight controller refuses bad airframe files with file, field and reason, like the plant.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use rotorpilot::airframe::{Airframe, AirframeSource};

const QUAD_X: &str = include_str!("../../airframes/quad_x.toml");

fn refused(text: &str) -> rotorpilot::airframe::AirframeError {
    Airframe::from_toml_str(text, "bad.toml").expect_err("must be refused")
}

#[test]
fn missing_negative_and_too_few() {
    let text: String = QUAD_X
        .lines()
        .filter(|l| !l.starts_with("c_q"))
        .collect::<Vec<_>>()
        .join("\n");
    let e = refused(&text);
    assert_eq!(e.to_string(), "bad.toml: rotors.c_q: missing field");
    let e = refused(&QUAD_X.replace("mass = 1.5 ", "mass = -2.0 "));
    assert_eq!(e.field, "vehicle.mass");
    let e = refused(&QUAD_X.replace("count = 4 ", "count = 2 "));
    assert_eq!(e.field, "rotors.ring.count");
    assert!(e.reason.contains("fewer than 4"));
    let e = refused(&QUAD_X.replace("inertia = [0.029125, 0.029125, 0.055225]", "inertia = [0.03, 0.03]"));
    assert_eq!(e.field, "vehicle.inertia");
}

#[test]
fn overlapping_ring_and_non_coplanar_list() {
    let e = refused(&QUAD_X.replace("arm = 0.25 ", "arm = 0.15 "));
    assert!(e.reason.contains("overlap"), "{e}");
    let start = QUAD_X.find("[rotors.ring]").unwrap();
    let end = QUAD_X.find("[plant.ground]").unwrap();
    let mut list = String::new();
    for (k, z) in [0.0, 0.0, 0.1, 0.0].iter().enumerate() {
        let spin = if k % 2 == 0 { "cw" } else { "ccw" };
        list.push_str(&format!(
            "[[rotors.rotor]]\nangle = {} # [deg]\narm = 0.25 # [m]\nz = {z:?} # [m]\nspin = \"{spin}\" # [-]\n",
            45 + 90 * k
        ));
    }
    let e = refused(&format!("{}{list}{}", &QUAD_X[..start], &QUAD_X[end..]));
    assert!(e.reason.contains("not coplanar"), "{e}");
}

#[test]
fn fc_belief_table_is_validated() {
    let e = refused(&format!("{QUAD_X}\n[fc]\nmass = 0.0 # [kg]\n"));
    assert_eq!(e.field, "fc.mass");
}

#[test]
fn missing_file_and_unknown_name() {
    let e = AirframeSource::resolve("/nonexistent/x.toml").unwrap_err();
    assert_eq!(e.origin, "/nonexistent/x.toml");
    assert!(e.reason.contains("cannot read"));
    let e = AirframeSource::resolve("tricopter").unwrap_err();
    assert!(e.reason.contains("quad_x") && e.reason.contains("octo"));
}
