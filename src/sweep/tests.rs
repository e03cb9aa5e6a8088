//! A sweep file read and checked, its runs listed and applied to a scenario table.

use std::path::Path;

use super::*;

const EX4: &str = r#"
scenario = "../ex4_estimator.toml"
metrics = ["final_position_error_norm_m", "max_tilt_deg"]

[seeds]
count = 2
first = 10

[[axis]]
field = "estimator.order"
range = [1, 5]
steps = 3
integer = true

[[axis]]
field = "estimator.ripple_db"
values = [0.5, 1.0]
"#;

fn sweep(text: &str) -> Result<Sweep, SweepError> {
    Sweep::from_toml_str(text, "s.toml", Path::new("scenarios/sweeps"))
}

#[test]
fn a_grid_sweep_lists_every_point_with_every_seed() {
    let s = sweep(EX4).unwrap();
    assert_eq!(s.scenario, Path::new("scenarios/sweeps/../ex4_estimator.toml"));
    let runs = s.runs().unwrap();
    assert_eq!(runs.len(), 3 * 2 * 2);
    assert_eq!((runs[0].point, runs[0].seed), (0, 10));
    assert_eq!((runs[1].point, runs[1].seed), (0, 11));
    let last = runs.last().unwrap();
    assert_eq!(last.values, vec![toml::Value::Integer(5), toml::Value::Float(1.0)]);
    let base: toml::Table = toml::from_str("duration = 5.0\n[estimator]\norder = 2\nwp = 5.0\n").unwrap();
    let t = s.scenario_table(&base, last).unwrap();
    assert_eq!(t["estimator"]["order"].as_integer(), Some(5));
    assert_eq!(t["estimator"]["ripple_db"].as_float(), Some(1.0));
    assert_eq!(
        t["estimator"]["wp"].as_float(),
        Some(5.0),
        "the rest of the base is kept"
    );
    assert_eq!(t["seed"].as_integer(), Some(11));
}

#[test]
fn sampled_designs_draw_their_samples() {
    let s = sweep(
        "scenario = \"x.toml\"\n[design]\nkind = \"latin_hypercube\"\nsamples = 8\nseed = 4\n\
         [[axis]]\nfield = \"initial.position[0]\"\nuniform = [-1.0, 1.0]\n",
    )
    .unwrap();
    assert_eq!(s.design, Design::LatinHypercube { samples: 8, seed: 4 });
    assert_eq!(s.runs().unwrap().len(), 8);
}

#[test]
fn bad_sweeps_name_the_field_or_the_line() {
    let err = |text: &str| sweep(text).unwrap_err().to_string();
    let e = err("scenario = \"x.toml\"\n[[axis]]\nfield = \"a.b\"\nvalues = [1]\nrange = [0, 1]\n");
    assert!(
        e.contains("axis 1 (`a.b`): give exactly one of values, range or uniform"),
        "{e}"
    );
    let e = err("scenario = \"x.toml\"\n[[axis]]\nfield = \"a\"\nrange = [0, 1]\n");
    assert!(e.contains("range needs steps"), "{e}");
    let e = err("scenario = \"x.toml\"\n[[axis]]\nfield = \"a\"\nuniform = [0, 1]\n");
    assert!(e.contains("`uniform` needs a random or latin_hypercube design"), "{e}");
    let e = err("scenario = \"x.toml\"\n[design]\nkind = \"sobol\"\n");
    assert!(e.contains("[design]: kind `sobol`"), "{e}");
    let e = err("scenario = \"x.toml\"\n[design]\nkind = \"random\"\n");
    assert!(e.contains("samples"), "{e}");
    let e =
        err("scenario = \"x.toml\"\n[[axis]]\nfield = \"a\"\nvalues = [1]\n[[axis]]\nfield = \"a\"\nvalues = [2]\n");
    assert!(e.contains("field `a` swept twice"), "{e}");
    let e = err("scenario = \"x.toml\"\n[seeds]\ncount = 0\n");
    assert!(e.contains("count must be at least 1"), "{e}");
    let e = err("scenario = \"x.toml\"\n\n[[axis]]\nfeild = \"a\"\n");
    assert!(
        e.starts_with("s.toml: ") && e.contains("line 4") && e.contains("feild"),
        "{e}"
    );
}

#[test]
fn linked_fields_take_the_axis_value_and_cannot_be_swept_twice() {
    let text = "scenario = \"x.toml\"\n[[axis]]\nfield = \"g.kv[0]\"\nalso = [\"g.kv[1]\", \"g.kv[2]\"]\nvalues = [4.0, 8.0]\n";
    let s = sweep(text).unwrap();
    let base: toml::Table = toml::from_str("[g]\nkv = [1.0, 1.0, 1.0]\n").unwrap();
    let runs = s.runs().unwrap();
    let t = s.scenario_table(&base, &runs[1]).unwrap();
    assert_eq!(t["g"]["kv"], toml::Value::Array(vec![toml::Value::Float(8.0); 3]));
    let twice = format!("{text}[[axis]]\nfield = \"g.kv[2]\"\nvalues = [1.0]\n");
    assert!(sweep(&twice)
        .unwrap_err()
        .to_string()
        .contains("field `g.kv[2]` swept twice"));
    let itself = "scenario = \"x.toml\"\n[[axis]]\nfield = \"a\"\nalso = [\"a\"]\nvalues = [1]\n";
    assert!(sweep(itself).unwrap_err().to_string().contains("field `a` swept twice"));
}

#[test]
fn an_axis_over_a_field_the_scenario_does_not_have_is_refused() {
    let base: toml::Table = toml::from_str(include_str!("../../scenarios/ex4_estimator.toml")).unwrap();
    let ok = sweep("scenario = \"x.toml\"\n[[axis]]\nfield = \"estimator.wp\"\nvalues = [2.0, 99.0]\n").unwrap();
    assert_eq!(
        ok.check_axis_fields(&base, "s.toml"),
        Ok(()),
        "values are not judged here"
    );
    let typo = sweep("scenario = \"x.toml\"\n[[axis]]\nfield = \"estimator.odrer\"\nvalues = [1]\n").unwrap();
    let e = typo.check_axis_fields(&base, "s.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("s.toml: axis 1 (`estimator.odrer`)") && e.contains("unknown field `odrer`"),
        "{e}"
    );
    let typed = sweep("scenario = \"x.toml\"\n[[axis]]\nfield = \"duration\"\nvalues = [\"long\"]\n").unwrap();
    assert!(
        typed.check_axis_fields(&base, "s.toml").is_err(),
        "a value of the wrong type"
    );
}
