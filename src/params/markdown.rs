//! The parameter table of docs/parameters.md, generated from the rows: one line per parameter with
//! its name, wire type, value in the given table (the default when the table is fresh), range,
//! unit, what it acts on and what it means. Pure.

use super::{ParamDef, ParamTable, ParamType};

/// A markdown table of every parameter of `table`, in wire order, its values in the default
/// column; INT32 choices show the meaning of their value and list every code.
pub fn markdown_table(table: &ParamTable) -> String {
    let mut out = String::from(
        "| name | type | default | range | unit | applies to | description |\n|---|---|---|---|---|---|---|\n",
    );
    for (def, value) in (0..table.len()).filter_map(|i| table.get(i)) {
        let codes = def.choices.map(|c| c()).unwrap_or_default();
        let mut description = def.description.to_string();
        if !codes.is_empty() {
            let listed: Vec<String> = codes.iter().map(|(c, l)| format!("{c} {l}")).collect();
            description = format!("{description}: {}", listed.join(", "));
        }
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | {} | {} |\n",
            def.name,
            def.kind.name(),
            shown(def, value, &codes),
            range(def),
            def.unit,
            def.scope,
            description
        ));
    }
    out
}

/// `value` as the wire carries it (an INT32 as an integer, a REAL32 rounded to f32), with the
/// meaning of a choice's code.
fn shown(def: &ParamDef, value: f64, codes: &[(i32, &str)]) -> String {
    match def.kind {
        ParamType::Int32 => {
            let code = value as i32;
            match codes.iter().find(|(c, _)| *c == code) {
                Some((_, label)) => format!("{code} ({label})"),
                None => code.to_string(),
            }
        }
        ParamType::Real32 => (value as f32).to_string(),
    }
}

/// `min … max`.
fn range(def: &ParamDef) -> String {
    format!("{} … {}", def.min, def.max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::params::{rows, VehicleSettings};

    #[test]
    fn one_line_per_parameter_with_its_default() {
        let settings = VehicleSettings::new(ControllerKind::Geometric, ControllerGains::default(), None);
        let text = markdown_table(&ParamTable::new(&settings));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2 + rows().count());
        assert!(lines.iter().all(|l| l.starts_with('|') && l.ends_with('|')));
        assert!(
            lines[2..].iter().all(|l| l.matches(" | ").count() == 6),
            "seven columns"
        );
        assert_eq!(
            lines[2],
            "| `MIS_TAKEOFF_ALT` | REAL32 | 2.5 | 0.5 … 1000 | m | commander | \
             Height above home a take-off climbs to when the command names none |"
        );
        let nav_dll_act = lines.iter().find(|l| l.starts_with("| `NAV_DLL_ACT`"));
        assert_eq!(
            nav_dll_act.copied(),
            Some(
                "| `NAV_DLL_ACT` | INT32 | 0 (disabled) | 0 … 6 |  | failsafe | What GCS link loss does in \
                 flight, once per loss, with a critical STATUSTEXT: 0 disabled, 1 hold, 2 return, 3 land, \
                 5 terminate, 6 disarm |"
            )
        );
        assert!(text.contains("| `RP_EST_ORDER` | INT32 | 0 | 0 … 20 |"), "{text}");
    }
}
