//! `--params FILE` text → `parse_param_file`, then every assignment through `ParamTable::set`
//! the way `rotorpilot run` applies them. A bad line must be refused naming the line, never
//! panic; an accepted value reads back unchanged.
#![no_main]

use libfuzzer_sys::fuzz_target;

use rotorpilot::control::{ControllerGains, ControllerKind};
use rotorpilot::params::{parse_param_file, ParamTable, VehicleSettings};
use rotorpilot::runtime::vehicle::DEFAULT_ESTIMATOR;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let lines = text.lines().count();
    let assignments = match parse_param_file(&text, "fuzz.params") {
        Ok(a) => a,
        Err(e) => {
            assert!(e.line >= 1 && e.line <= lines, "line {} of {lines}", e.line);
            assert!(!e.reason.is_empty());
            return;
        }
    };
    let mut table = ParamTable::new(&VehicleSettings::new(
        ControllerKind::Geometric,
        ControllerGains::default(),
        Some(DEFAULT_ESTIMATOR),
    ));
    for (line, name, value) in assignments {
        assert!(line >= 1 && line <= lines);
        let before = table.clone();
        match table.set(&name, value, 1e-3) {
            Ok(index) => {
                assert_eq!(table.get(index).map(|(d, v)| (d.name, v)), Some((name.as_str(), value)));
                let _ = table.settings();
            }
            Err(e) => {
                assert!(!e.to_string().is_empty());
                assert_eq!(table, before, "a refused set changed the table");
            }
        }
    }
});
