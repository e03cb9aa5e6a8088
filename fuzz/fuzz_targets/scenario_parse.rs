//! Scenario file text → `Scenario::from_toml_str` and, when accepted, its flight core. A bad
//! file must be refused with an error naming the field, never panic.
//!
//! A scenario names its airframe by preset or by file path, and that file is read. The base
//! directory does not exist (so relative paths never resolve), and inputs that could name a
//! device or a kernel file (`dev`, `proc`, `sys`, TOML unicode escapes) are skipped: reading
//! `/dev/zero` would hang the fuzzer, not find a bug.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

use rotorpilot::scenario::Scenario;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if ["dev", "proc", "sys", "\\u", "\\U"].iter().any(|s| text.contains(s)) {
        return;
    }
    match Scenario::from_toml_str(text, "fuzz.toml", "fuzz", Path::new("/nonexistent-rotorpilot-fuzz")) {
        Ok(scenario) => {
            assert!(scenario.duration_s.is_finite() && scenario.duration_s > 0.0);
            assert!(scenario.dt_s.is_finite() && scenario.dt_s > 0.0);
            let _ = scenario.flight_core();
        }
        Err(e) => assert!(
            !e.field.is_empty() && !e.reason.is_empty(),
            "error without field or reason: {e:?}"
        ),
    }
});
