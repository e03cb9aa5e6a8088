//! Airframe presets compiled into the binary, so `--airframe quad_x` works from any directory.

/// (name, file text) of every preset.
pub const PRESETS: &[(&str, &str)] = &[
    ("quad_x", include_str!("../../airframes/quad_x.toml")),
    ("quad_plus", include_str!("../../airframes/quad_plus.toml")),
    ("hexa_x", include_str!("../../airframes/hexa_x.toml")),
    ("octo", include_str!("../../airframes/octo.toml")),
    ("fsr_quad", include_str!("../../airframes/fsr_quad.toml")),
];

/// The text of preset `name`, if there is one.
pub fn preset_text(name: &str) -> Option<&'static str> {
    PRESETS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// Names of all presets, comma separated (for error messages).
pub fn preset_names() -> String {
    PRESETS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `key = value` line of every preset states its unit in brackets.
    #[test]
    fn every_field_has_a_unit() {
        for (name, text) in PRESETS {
            for (i, line) in text.lines().enumerate() {
                let code = line.trim();
                if code.starts_with('#') || code.starts_with('[') || code.is_empty() {
                    continue;
                }
                let comment = code.split_once('#').map(|(_, c)| c).unwrap_or("");
                assert!(
                    comment.contains('[') && comment.contains(']'),
                    "{name}.toml line {}: no unit: {line}",
                    i + 1
                );
            }
        }
    }
}
