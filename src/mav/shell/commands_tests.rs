use super::*;
use crate::control::{ControllerGains, ControllerKind};
use crate::guidance::Home;
use crate::params::VehicleSettings;

fn table() -> ParamTable {
    ParamTable::new(&VehicleSettings::new(
        ControllerKind::Geometric,
        ControllerGains::default(),
        None,
    ))
}

fn text(line: &str, params: &ParamTable, snapshot: &Snapshot) -> String {
    match run(line, Context { params, snapshot }) {
        ShellOutcome::Text(t) => t,
        other => panic!("{line}: {other:?}"),
    }
}

#[test]
fn help_ver_and_unknown_commands() {
    let (p, s) = (table(), Snapshot::initial(Home::default()));
    assert_eq!(
        text("help", &p, &s),
        "Builtin Commands:\n  commander\n  listener\n  param\n  ver\n"
    );
    assert!(text("ver all", &p, &s).contains(env!("CARGO_PKG_VERSION")));
    assert_eq!(
        text("top -d 1", &p, &s),
        "Invalid command: top\ntype 'help' for a list of commands\n"
    );
    assert_eq!(text("   ", &p, &s), "");
    assert_eq!(text("# a comment", &p, &s), "");
}

#[test]
fn param_show_filters_and_param_set_is_checked_before_it_is_asked() {
    let (p, s) = (table(), Snapshot::initial(Home::default()));
    let all = text("param show", &p, &s);
    assert_eq!(all.lines().filter(|l| l.starts_with("x ")).count(), p.len());
    let geo = text("param show rp_geo_kp*", &p, &s);
    let names: Vec<&str> = geo
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1))
        .filter(|n| n.starts_with("RP_"))
        .collect();
    assert_eq!(names, vec!["RP_GEO_KP_X", "RP_GEO_KP_Y", "RP_GEO_KP_Z"]);
    assert!(text("param show MIS_TAKEOFF_ALT", &p, &s).contains("MIS_TAKEOFF_ALT [0,0] : 2.5000"));
    assert!(text("param show RP_CTRL", &p, &s).contains(": 0\n"));
    assert_eq!(
        run(
            "param set MIS_TAKEOFF_ALT 4",
            Context {
                params: &p,
                snapshot: &s
            }
        ),
        ShellOutcome::SetParam {
            name: "MIS_TAKEOFF_ALT".into(),
            value: 4.0
        }
    );
    assert_eq!(text("param set NOPE 1", &p, &s), "ERROR: Parameter NOPE not found.\n");
    assert!(text("param set MIS_TAKEOFF_ALT abc", &p, &s).starts_with("ERROR: abc is not a number"));
    let mut after = p.clone();
    after.set("MIS_TAKEOFF_ALT", 4.0, 1e-3).unwrap();
    assert_eq!(
        param_set_text(&p, &after, "MIS_TAKEOFF_ALT", Ok(())),
        "MIS_TAKEOFF_ALT: curr: 2.5000 -> new: 4.0000\n"
    );
    let refused = param_set_text(&p, &p, "RP_CTRL", Err("RP_CTRL: 1.5 is not an integer".into()));
    assert_eq!(
        refused,
        "ERROR: param set RP_CTRL refused: RP_CTRL: 1.5 is not an integer\n"
    );
}

#[test]
fn status_and_listeners_show_the_snapshot() {
    let p = table();
    let mut s = Snapshot::initial(Home::default());
    s.armed = true;
    s.pos_w = Vec3::new(1.0, 2.0, -3.0);
    s.battery.fraction = 0.1;
    s.t_s = 2.0;
    let status = text("commander status", &p, &s);
    assert!(status.contains("arming state: ARMED"), "{status}");
    assert!(status.contains("battery warning: low (10 % remaining)"), "{status}");
    let pos = text("listener vehicle_local_position", &p, &s);
    assert!(
        pos.contains("timestamp: 2000000") && pos.contains("z: -3.0000"),
        "{pos}"
    );
    let att = text("listener vehicle_attitude", &p, &s);
    assert!(att.contains("q: [1.0000, 0.0000, 0.0000, 0.0000]"), "{att}");
    assert!(text("listener battery_status", &p, &s).contains("remaining: 0.100"));
    assert!(text("listener sensor_foo", &p, &s).contains("not found"));
}
