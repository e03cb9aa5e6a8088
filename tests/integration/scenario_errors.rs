//! Bad scenario files are refused with the file, the field and the reason.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use rotorpilot::scenario::Scenario;

const GOOD: &str = r#"
duration = 2.0
[airframe]
preset = "quad_x"
[controller]
kind = "geometric"
[estimator]
order = 1
wp = 2.0
[trajectory]
kind = "hover"
position = [0.0, 0.0, -1.0]
"#;

fn error(text: &str) -> String {
    Scenario::from_toml_str(text, "bad.toml", "bad", Path::new("."))
        .map(|_| ())
        .unwrap_err()
        .to_string()
}

#[test]
fn the_good_file_loads() {
    let s = Scenario::from_toml_str(GOOD, "good.toml", "good", Path::new(".")).unwrap();
    assert_eq!(s.name, "good");
    assert_eq!(s.estimator.unwrap().gains.len(), 1);
}

#[test]
fn each_bad_field_is_named() {
    let cases = [
        (
            GOOD.replace("duration = 2.0", "duration = -2.0"),
            "bad.toml: duration: must be a positive",
        ),
        (
            GOOD.replace("kind = \"geometric\"", "kind = \"pid\""),
            "bad.toml: line 6: unknown variant `pid`",
        ),
        (
            GOOD.replace("preset = \"quad_x\"", "preset = \"tricopter\""),
            "bad.toml: airframe: tricopter",
        ),
        (
            GOOD.replace("wp = 2.0", "wp = 200.0\norder_typo = 1"),
            "unknown field `order_typo`",
        ),
        (
            GOOD.replace("order = 1", "order = 13").replace("wp = 2.0", "wp = 20.0"),
            "largest stable passband edge",
        ),
        (GOOD.replace("wp = 2.0", ""), "estimator: needs `order` and `wp`"),
        (
            GOOD.replace(
                "[controller]",
                "[controller]\ngains = { geometric = { kp = [1.0, -2.0, 3.0] } }",
            ),
            "controller.gains: geometric.kp",
        ),
        (
            GOOD.replace(
                "[controller]",
                "[controller]\ngains = { geometric = { kq = [1.0, 2.0, 3.0] } }",
            ),
            "controller.gains: unknown field `kq`",
        ),
        (
            GOOD.replace(
                "[controller]",
                "[initial]\nquaternion = [1.0, 1.0, 0.0, 0.0]\n[controller]",
            ),
            "initial.quaternion: must have unit norm",
        ),
        (
            GOOD.replace(
                "[controller]",
                "[airframe.overrides]\nvehicle = { mass = -1.0 }\n[controller]",
            ),
            "vehicle.mass",
        ),
        (
            GOOD.replace("position = [0.0, 0.0, -1.0]", "position = [0.0, 0.0]"),
            "bad.toml: line ",
        ),
    ];
    for (text, expected) in cases {
        let e = error(&text);
        assert!(e.contains(expected), "expected {expected:?} in {e:?}");
    }
}

#[test]
fn gains_can_be_overridden_partially() {
    let text = GOOD.replace(
        "[controller]",
        "[controller]\ngains = { geometric = { kp = [1.0, 2.0, 3.0] } }",
    );
    let s = Scenario::from_toml_str(&text, "t", "t", Path::new(".")).unwrap();
    assert_eq!(s.gains.geometric.kp, rotorpilot::math::Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(s.gains.geometric.kv.x, 10.0, "the rest keeps the defaults");
}
